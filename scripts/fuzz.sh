#!/usr/bin/env bash
# Builds the libFuzzer harnesses (fuzz/, clang, ASan + UBSan) in build-san
# (scripts/sanitizer_build.sh, shared with scripts/test_sanitized.sh) and runs them.
#   scripts/fuzz.sh [seconds per target, default 60] [target ...]
# Targets: fuzz_case_loader fuzz_sweep_file fuzz_expression (default: all three, one after
# the other; run several copies of the script for parallel runs). Each target's corpus lives
# in build-san/corpus/<target> (seeded from cases/ on first use), findings in
# build-san/findings/<target>, the log in build-san/<target>.log. libFuzzer's -fork mode keeps
# going after a finding, so one run reports every crash, timeout and out-of-memory it meets.
# Environment: CKPD_FUZZ_TIMEOUT (seconds one input may take before it counts as a hang,
# default 10; on a loaded machine the larger seeds need 60), CKPD_FUZZ_BUILD=0 (run the
# harnesses already built, e.g. while the same build folder compiles the tests).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_case_loader fuzz_sweep_file fuzz_expression)

build="${CKPD_SAN_BUILD:-build-san}"
[ "${CKPD_FUZZ_BUILD:-1}" = 0 ] || scripts/sanitizer_build.sh "${targets[@]}"

seed() {  # the seed corpus of one target, from cases/
  local target=$1 dir=$build/corpus/$1
  [ -d "$dir" ] && return
  mkdir -p "$dir"
  case "$target" in
    fuzz_case_loader) cp cases/*.yaml cases/stress/*.yaml "$dir"/ ;;
    fuzz_sweep_file) cp cases/sweeps/*.yaml "$dir"/ ;;
    fuzz_expression)
      # Every expression of the sweep files, and a few that exercise each operator.
      grep -ho 'expr: *"[^"]*"' cases/sweeps/*.yaml | sed 's/expr: *"//; s/"$//' |
        while read -r e; do printf '%s' "$e" > "$dir/$(printf '%s' "$e" | md5sum | cut -c1-12)"; done
      local n=0
      for e in "3.015 * spacing" "-sqrt(2 * energy / mass)" "min(a, b) ^ 2 - -c" "log10(x) + exp(-y / 2)" \
               "max(sin(pi * t), cos(e)) / abs(tan(0.5))" "2^3^2" "((1))" "1e-3 * (a + b)"; do
        printf '%s' "$e" > "$dir/seed$((n++))"
      done ;;
  esac
}

for target in "${targets[@]}"; do
  seed "$target"
  mkdir -p "$build/findings/$target"
  # -timeout: a single input taking 10 s is a hang; -rss_limit_mb: 2 GB is a memory blow-up.
  "./$build/fuzz/$target" "$build/corpus/$target" -fork=1 -ignore_crashes=1 \
    -ignore_timeouts=1 -ignore_ooms=1 -timeout="${CKPD_FUZZ_TIMEOUT:-10}" -rss_limit_mb=2048 \
    -max_total_time="$seconds" \
    -artifact_prefix="$build/findings/$target/" 2>&1 | tee "$build/$target.log" | tail -5
done
