// The instruction set a build states (ckpd --version, summary.json) and the guard that refuses a
// host without it (src/cli/isa.cpp).
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "src/cli/cli_options.hpp"
#include "src/cli/isa.hpp"

namespace {
bool contains(const std::vector<std::string>& names, const std::string& name) {
  for (const std::string& n : names)
    if (n == name) return true;
  return false;
}
bool lacks_everything(std::size_t) {
  return false;
}
}  // namespace

TEST_CASE("the extensions a build states are those its compiler's macros name", "[isa]") {
  // This file is compiled with the flags of the engine (CKPD_ARCH applies to every target).
  const std::vector<std::string> names = ckpd::isa::compiled_extensions();
  INFO(ckpd::instruction_set_text());
#if defined(__x86_64__)
#ifdef __SSE4_2__
  CHECK(contains(names, "sse4.2"));
#else
  CHECK_FALSE(contains(names, "sse4.2"));
#endif
#ifdef __AVX2__
  CHECK(contains(names, "avx2"));
#else
  CHECK_FALSE(contains(names, "avx2"));
#endif
#ifdef __FMA__
  CHECK(contains(names, "fma"));
#else
  CHECK_FALSE(contains(names, "fma"));
#endif
#ifdef __AVX512F__
  CHECK(contains(names, "avx512f"));
#else
  CHECK_FALSE(contains(names, "avx512f"));
#endif
#endif
  const std::string text = ckpd::instruction_set_text();
  CHECK(text.rfind("CKPD_ARCH=", 0) == 0);
  for (const std::string& n : names) CHECK(text.find(n) != std::string::npos);
  CHECK(ckpd::version_line().find("instruction set " + text) != std::string::npos);
  const auto build = ckpd::build_json();
  CHECK(build["isa_extensions"].get<std::vector<std::string>>() == names);
  CHECK(!build["arch"].get<std::string>().empty());
}

TEST_CASE("a host that lacks an extension the build uses is refused with a line naming each",
          "[isa]") {
  // The machine running the tests runs the build: it lacks nothing, or the guard would have
  // stopped this program before main.
  CHECK(ckpd::isa::refusal(ckpd::isa::host_has).empty());
  const std::vector<std::string> names = ckpd::isa::compiled_extensions();
  const std::string line = ckpd::isa::refusal(lacks_everything);
  INFO(line);
  if (names.empty()) {
    CHECK(line.empty());  // a baseline build runs on any x86-64
  } else {
    CHECK(line.rfind("ckpd: error: this ckpd was built for CKPD_ARCH=", 0) == 0);
    for (const std::string& n : names) CHECK(line.find(" " + n) != std::string::npos);
    CHECK(line.find("-DCKPD_ARCH=") != std::string::npos);
    CHECK(line.back() == '\n');
    CHECK(line.find('\n') == line.size() - 1);  // one line
  }
}
