# Run at every build (`cmake -P`, from the ckpd_git_commit target in src/CMakeLists.txt): writes
# OUT with the commit the sources are at now, so that `ckpd --version` and summary.json name the
# commit that was built, not the one of the last configure. "-dirty" when tracked files differ
# from that commit; "unknown" outside a git checkout (a source archive). The file is rewritten
# only when its text changes, so a build at the same commit recompiles nothing; the first edit
# of any tracked file (docs too) adds "-dirty" once: cli_options.cpp recompiles and the
# programs relink (about 16 s on the 2-core VM).
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
                RESULT_VARIABLE commit_status)
if(NOT commit_status EQUAL 0 OR NOT commit)
  set(commit "unknown")
else()
  execute_process(COMMAND git status --porcelain --untracked-files=no WORKING_DIRECTORY ${SRC}
                  OUTPUT_VARIABLE changes OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(changes)
    string(APPEND commit "-dirty")
  endif()
endif()
set(text "#pragma once\n// Generated at build time by cmake/write_git_commit.cmake.\nnamespace ckpd::build {\ninline constexpr const char* kGitCommit = \"${commit}\";\n}  // namespace ckpd::build\n")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUT} "${text}")
endif()
