#!/bin/sh
# Faults of one rank must end every rank of the job within 10 s, with a message (registered with
# ctest in tests/CMakeLists.txt; exit 77, skipped, for a build without MPI):
#   refusal    one rank refuses its case (an MPMD launch where only rank 1 has max_memory=1000):
#              every rank exits 2, the refusal printed once.
#   mismatch   two ranks load different valid cases, or the same case with different --set:
#              every rank exits 2, the difference printed once, no step taken.
#   killed     kill -9 of one rank of three during the run: mpirun and the other ranks are gone
#              within 10 s.
#   mpi_faults.sh CKPD SOURCE_DIR WORK_DIR refusal|mismatch|killed
set -eu
ckpd=$1 src=$2 work=$3 what=$4
"$ckpd" --version | grep -q "MPI none" && { echo "ckpd is built without MPI: skipped"; exit 77; }
command -v mpirun >/dev/null || { echo "no mpirun: skipped"; exit 77; }
rm -rf "$work"
mkdir -p "$work"
case_file=$src/tests/mpi/two_bodies.yaml
mpirun_opts="--oversubscribe --allow-run-as-root -x OMP_NUM_THREADS=1"
export OMP_NUM_THREADS=1
# The seconds since the epoch, to one decimal.
now() { date +%s.%N | cut -c1-12; }
elapsed_below() { awk -v a="$1" -v b="$2" -v limit="$3" 'BEGIN { exit !(b - a < limit) }'; }

# One rank per app context: each writes its exit status to status.RANK; stderr to err.
mpmd() {
  rm -f "$work"/status.*
  start=$(now)
  # shellcheck disable=SC2086
  timeout 60 mpirun $mpirun_opts \
    -np 1 sh -c '"$0" "$@"; echo $? > '"$work"'/status.$OMPI_COMM_WORLD_RANK' "$ckpd" run "$@" \
    : -np 1 sh -c '"$0" "$@"; echo $? > '"$work"'/status.$OMPI_COMM_WORLD_RANK' "$ckpd" run \
    $second 2>"$work/err" >/dev/null || true
  took=$(now)
  elapsed_below "$start" "$took" 10 || { echo "the job took more than 10 s"; cat "$work/err"; exit 1; }
}
# Both ranks exited 2 and stderr holds PATTERN in exactly one "ckpd: error:" line.
expect_both_2() {
  label=$1 pattern=$2
  count=$(grep -c "ckpd: error: .*$pattern" "$work/err" || true)
  [ "$count" = 1 ] || { echo "$label: the error was printed $count times:"; cat "$work/err"; exit 1; }
  for r in 0 1; do
    [ -f "$work/status.$r" ] || { echo "$label: rank $r reported no exit status"; cat "$work/err"; exit 1; }
    [ "$(cat "$work/status.$r")" = 2 ] ||
      { echo "$label: rank $r exited $(cat "$work/status.$r"), not 2"; cat "$work/err"; exit 1; }
  done
  [ ! -e "$work/out/summary.json" ] || { echo "$label: a summary was written"; exit 1; }
  echo "$label: one message, exit 2 on both ranks"
}

case $what in
refusal)
  second="$case_file --out $work/out --quiet --set max_memory=1000000"
  mpmd "$case_file" --out "$work/out" --quiet
  expect_both_2 "refusal on rank 1 only" "needs at least"
  ;;
mismatch)
  second="$src/tests/mpi/pulled_bars.yaml --out $work/out --quiet"
  mpmd "$case_file" --out "$work/out" --quiet
  expect_both_2 "two different cases" "rank 1 of 2 did not load what rank 0 loaded: the resolved case"
  second="$case_file --out $work/out --quiet --set time.steps=10"
  mpmd "$case_file" --out "$work/out" --quiet
  expect_both_2 "one case, different --set" "did not load what rank 0 loaded: the resolved case"
  second="$case_file --out $work/other --quiet"
  mpmd "$case_file" --out "$work/out" --quiet
  expect_both_2 "different output folders" "--out, --restart or --gather-output differs"
  ;;
killed)
  # shellcheck disable=SC2086
  mpirun $mpirun_opts -np 3 "$ckpd" run "$case_file" --out "$work/out" --quiet \
    --set time.steps=1000000 --set output.history_interval=1000000 \
    --set output.field_interval=1000000 2>"$work/err" >/dev/null &
  launcher=$!
  # The ranks are mpirun's children; wait until all three are stepping (run.log exists).
  tries=0
  while [ ! -s "$work/out/run.log" ] || [ "$(pgrep -P "$launcher" | wc -l)" -lt 3 ]; do
    tries=$((tries + 1))
    [ "$tries" -lt 600 ] || { echo "the run did not start"; kill "$launcher"; exit 1; }
    sleep 0.1
  done
  sleep 1
  victims=$(pgrep -P "$launcher")
  victim=$(echo "$victims" | sed -n 2p)
  start=$(now)
  kill -9 "$victim"
  gone=0
  for _ in $(seq 1 150); do
    alive=0
    for p in $victims; do kill -0 "$p" 2>/dev/null && alive=$((alive + 1)); done
    if [ "$alive" = 0 ] && ! kill -0 "$launcher" 2>/dev/null; then gone=1; break; fi
    sleep 0.1
  done
  took=$(now)
  if [ "$gone" != 1 ]; then
    echo "15 s after kill -9 of rank process $victim, ranks or mpirun still run:"
    for p in $victims $launcher; do kill -9 "$p" 2>/dev/null || true; done
    cat "$work/err"
    exit 1
  fi
  wait "$launcher" && { echo "mpirun exited 0 after a rank was killed"; exit 1; }
  elapsed_below "$start" "$took" 10 || { echo "the job took more than 10 s to end"; exit 1; }
  grep -q "signal 9\|Killed\|killed" "$work/err" || { echo "no message about the killed rank:"; cat "$work/err"; exit 1; }
  echo "kill -9 of one rank of 3: every rank and mpirun gone in $(awk -v a="$start" -v b="$took" 'BEGIN { print b - a }') s"
  ;;
*)
  echo "unknown check '$what'"
  exit 2
  ;;
esac
