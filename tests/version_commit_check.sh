#!/bin/sh
# `ckpd --version` names the commit the binary was built from (stamped at build time by
# cmake/write_git_commit.cmake), not the commit of the last configure: the 12-digit HEAD of the
# source tree, "-dirty" allowed; "unknown" only outside a git checkout.
#   version_commit_check.sh CKPD SOURCE_DIR
ckpd="$1"
src="$2"
line=$("$ckpd" --version | head -n 1)
if head=$(git -C "$src" rev-parse --short=12 HEAD 2>/dev/null); then
  expected="commit $head"
else
  expected="commit unknown"
fi
case "$line" in
  *"$expected,"* | *"$expected-dirty,"*) echo "ok: $line" ;;
  *) echo "FAIL: '$line' does not name '$expected' (rebuild after a commit restamps it)"; exit 1 ;;
esac
