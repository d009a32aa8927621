#!/bin/sh
# The instruction-set guard (src/cli/isa.cpp) end to end, on a CPU without AVX-512: valgrind's
# virtual CPU reports AVX2 but no AVX-512 (cpuid), as an older x86-64 would. A build that uses
# AVX-512 must refuse there with one line naming it (exit 1), not die of SIGILL; a build that
# does not must run. Exit 77 (skipped) without valgrind.
#   isa_guard_check.sh PATH/TO/ckpd
ckpd="$1"
command -v valgrind >/dev/null 2>&1 || { echo "valgrind not found: skipped"; exit 77; }
version=$("$ckpd" --version) || { echo "ckpd --version failed on this host"; exit 1; }
echo "$version"
# OMP_WAIT_POLICY set: ckpd would otherwise start itself again through /proc/self/exe, which is
# valgrind under valgrind.
out=$(OMP_WAIT_POLICY=passive valgrind -q "$ckpd" --version 2>&1)
rc=$?
echo "under valgrind: exit $rc"
echo "$out"
case "$version" in
  *avx512f*)
    [ "$rc" -eq 1 ] || { echo "FAIL: expected exit 1"; exit 1; }
    lines=$(printf '%s\n' "$out" | grep -c .)
    [ "$lines" -eq 1 ] || { echo "FAIL: expected one line"; exit 1; }
    case "$out" in
      "ckpd: error: this ckpd was built for CKPD_ARCH="*"needs"*avx512f*"which this CPU lacks"*) ;;
      *) echo "FAIL: the refusal does not name avx512f"; exit 1 ;;
    esac
    case "$out" in *avx2*) echo "FAIL: names avx2, which valgrind's CPU has"; exit 1 ;; esac ;;
  *)
    [ "$rc" -eq 0 ] || { echo "FAIL: a build without AVX-512 should run under valgrind"; exit 1; } ;;
esac
echo "ok"
