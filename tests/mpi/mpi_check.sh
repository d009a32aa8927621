#!/bin/sh
# The MPI tests (issue 14), registered with ctest in tests/CMakeLists.txt. Runs of one case at
# 1, 2 and 3 ranks (one thread each) must agree (compare_runs.py: positions to 1e-12 relative,
# the same broken bonds, fragments and damage); a checkpoint written at 2 ranks continued at 3
# must equal the uninterrupted run; bad input must print one error and exit 2 on every rank; a
# body with a far field (evaluated whole on every rank) must agree at 1 and 2 ranks; SIGTERM sent
# to one rank must stop every rank after the same step with a checkpoint that continues to the
# uninterrupted run; the field frames (and checkpoint) of runs at 1, 2 (and 3) ranks must be the
# same files (compare_runs.py --files). Exit 77 (skipped) for a build without MPI.
# SCHEME (distributed or replicated): the scheme summary.json says the ranks ran on.
#   mpi_check.sh CKPD SOURCE_DIR WORK_DIR equivalence CASE SCHEME | restart CASE SCHEME | errors |
#                far_field CASE SCHEME | signal CASE SCHEME | files CASE SCHEME |
#                files_gathered CASE SCHEME
set -eu
ckpd=$1 src=$2 work=$3 what=$4
case_file=${5:+$src/$5}
scheme=${6:-}
"$ckpd" --version | grep -q "MPI none" && { echo "ckpd is built without MPI: skipped"; exit 77; }
command -v mpirun >/dev/null || { echo "no mpirun: skipped"; exit 77; }
python=/usr/bin/python3
mpi() {
  np=$1
  shift
  OMP_NUM_THREADS=1 mpirun --oversubscribe --allow-run-as-root -np "$np" -x OMP_NUM_THREADS "$@"
}
# The scheme a run of several ranks in DIR ran on must be SCHEME.
ran_on() {
  $python - "$1/summary.json" "$scheme" <<'PY'
import json, sys
state = json.load(open(sys.argv[1]))["decomposition"]["state"]
print(f"{sys.argv[1]}: {state.split(':')[0]}")
sys.exit(0 if state.startswith(sys.argv[2] + ":") else 1)
PY
}
# A distributed run with contact must have chosen its contact ghosts again during the run (the
# bodies moved past the skin), so that the comparison covers a change of ghosts.
ghosts_chosen_again() {
  $python - "$1/summary.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))["contact"]
if "contact_ghost_selections" not in c:
    sys.exit(0)  # replicated state, or no contact
print(f"{sys.argv[1]}: contact ghosts chosen {c['contact_ghost_selections']} times, "
      f"at most {c['contact_ghosts_most_on_a_rank']} on a rank")
sys.exit(0 if c["contact_ghost_selections"] >= 2 and c["contact_ghosts_most_on_a_rank"] > 0 else 1)
PY
}
# The single-process run of a case with contact must have had points in contact (and, under a
# law with a dashpot, dissipated energy in it): a comparison of runs without contact proves little.
touched() {
  $python - "$1/summary.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))["contact"]
if not c["active"]:
    sys.exit(0)
damped = any(law["damping_ratio"] > 0 for law in c["laws"])
print(f"{sys.argv[1]}: at most {c['point_pairs_in_contact_peak']} point pairs in contact, "
      f"{c['damping_dissipated']} J dissipated by dashpots")
sys.exit(0 if c["point_pairs_in_contact_peak"] > 0 and (not damped or c["damping_dissipated"] > 0)
         else 1)
PY
}
# The ranks' count of point pairs in contact at the most must be the single process's.
same_contact_count() {
  $python - "$@" <<'PY'
import json, sys
peaks = [json.load(open(f"{d}/summary.json"))["contact"].get("point_pairs_in_contact_peak")
         for d in sys.argv[1:]]
print(f"point pairs in contact at the most: {peaks}")
sys.exit(0 if len(set(peaks)) == 1 else 1)
PY
}
rm -rf "$work"
mkdir -p "$work"
case $what in
equivalence)
  OMP_NUM_THREADS=1 "$ckpd" run "$case_file" --out "$work/np1" --quiet
  mpi 2 "$ckpd" run "$case_file" --out "$work/np2" --quiet
  mpi 3 "$ckpd" run "$case_file" --out "$work/np3" --quiet
  grep -q '"ranks": 3' "$work/np3/summary.json"
  ran_on "$work/np2"
  ran_on "$work/np3"
  touched "$work/np1"
  ghosts_chosen_again "$work/np2"
  ghosts_chosen_again "$work/np3"
  same_contact_count "$work/np1" "$work/np2" "$work/np3"
  # --files: the frames the ranks wrote (together, with parallel HDF5) are the single process's.
  $python "$src/tests/mpi/compare_runs.py" "$work/np1" "$work/np2" "$work/np3" --files
  ;;
restart)
  OMP_NUM_THREADS=1 "$ckpd" run "$case_file" --out "$work/whole" --quiet
  mpi 2 "$ckpd" run "$case_file" --out "$work/split" --quiet --set time.steps=120 \
    --set output.checkpoint_interval=120
  ran_on "$work/split"
  mpi 3 "$ckpd" run "$case_file" --out "$work/split" --quiet --restart "$work/split/checkpoint.h5"
  ran_on "$work/split"
  grep -q '"ranks": 3' "$work/split/summary.json"
  $python "$src/tests/mpi/compare_runs.py" "$work/whole" "$work/split"
  ;;
far_field)
  OMP_NUM_THREADS=1 "$ckpd" run "$case_file" --out "$work/np1" --quiet
  mpi 2 "$ckpd" run "$case_file" --out "$work/np2" --quiet
  ran_on "$work/np2"
  # The far field must have been in use: some points linear, some exact at the end.
  $python - "$work/np1/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
f = [b["far_field"]["exact_fraction"] for b in s["bodies"] if "far_field" in b]
print(f"far-field exact fractions at the end: {f}")
sys.exit(0 if f and all(0 < x < 1 for x in f) else 1)
PY
  $python "$src/tests/mpi/compare_runs.py" "$work/np1" "$work/np2"
  ;;
signal)
  # Two ranks run far past the case's end; once rank 0 has written the history row of step 200
  # (the bead reaches the plate about then), rank 1 alone gets SIGTERM. Each rank's wrapper records its ckpd's pid and exit status.
  rm -f "$work"/pid.* "$work"/status.*
  mpi 2 sh -c '"$0" "$@" & echo $! > '"$work"'/pid.$OMPI_COMM_WORLD_RANK; wait $!;
               echo $? > '"$work"'/status.$OMPI_COMM_WORLD_RANK' \
    "$ckpd" run "$case_file" --out "$work/split" --quiet --set time.steps=1000000 \
    --set output.field_interval=1000000 2>"$work/err" &
  launcher=$!
  tries=0
  until [ -f "$work/pid.1" ] && [ "$(wc -l 2>/dev/null <"$work/split/history.csv" || echo 0)" -ge 12 ]; do
    tries=$((tries + 1))
    if [ $tries -gt 1200 ]; then
      echo "the run did not start stepping in 120 s"
      kill $(cat "$work"/pid.* 2>/dev/null) 2>/dev/null || true
      exit 1
    fi
    sleep 0.1
  done
  kill -TERM "$(cat "$work/pid.1")"
  wait "$launcher" || true
  for r in 0 1; do
    [ "$(cat "$work/status.$r")" = 130 ] || { echo "rank $r exited $(cat "$work/status.$r"), not 130"; cat "$work/err"; exit 1; }
  done
  [ "$(grep -c 'interrupted by a signal at step' "$work/err")" = 1 ] || { echo "expected one stop message:"; cat "$work/err"; exit 1; }
  [ -f "$work/split/checkpoint.h5" ] || { echo "no checkpoint"; exit 1; }
  stopped=$($python -c 'import json,sys; s=json.load(open(sys.argv[1])); print(s["status"], s["steps"])' \
    "$work/split/summary.json")
  echo "both ranks exited 130; summary: $stopped; $(cat "$work/err")"
  [ "${stopped% *}" = interrupted ] || { echo "summary status is not 'interrupted'"; exit 1; }
  ran_on "$work/split"
  # Continue 120 steps past the stop (through the fracture) and compare with one process run
  # straight to that step.
  steps=$((${stopped#* } + 120))
  mpi 2 "$ckpd" run "$case_file" --out "$work/split" --quiet --restart "$work/split/checkpoint.h5" \
    --set time.steps=$steps --set output.field_interval=$steps
  OMP_NUM_THREADS=1 "$ckpd" run "$case_file" --out "$work/whole" --quiet --set time.steps=$steps \
    --set output.field_interval=$steps
  $python "$src/tests/mpi/compare_runs.py" "$work/whole" "$work/split" \
    --extra-history-step "${stopped#* }"
  ;;
files | files_gathered)
  # Frames off the history rows (every 30 steps; rows every 20), every point field, and a
  # checkpoint at step 120: the files the ranks write must be the single process's, and, where
  # the build has parallel HDF5 (CKPD_SHARED_FILES=ON), written by every rank into them unless
  # the run is told to gather them to rank 0 (files_gathered: --gather-output).
  gather=""
  shared=${CKPD_SHARED_FILES:-OFF}
  [ "$what" = files_gathered ] && { gather=--gather-output; shared=OFF; }
  fields=position,reference_position,displacement,velocity,force_density,damage,free_surface
  fields=$fields,strain_energy_density,volume,body_id,point_id,deformation_gradient
  fields=$fields,green_lagrange_strain,dilatation,stress
  for np in 1 2; do
    if [ $np = 1 ]; then run="env OMP_NUM_THREADS=1"; else run="mpi $np"; fi
    $run "$ckpd" run "$case_file" --out "$work/np$np" --quiet --set output.field_interval=30 \
      --set output.checkpoint_interval=120 --set "output.fields=[$fields]" $gather
  done
  ran_on "$work/np2"
  $python - "$work/np2/summary.json" "$shared" <<'PY'
import json, sys
how = json.load(open(sys.argv[1]))["decomposition"]["frames_and_checkpoints"]
print(f"frames and checkpoints: {how}")
shared = sys.argv[2].upper() in ("ON", "1", "TRUE")
sys.exit(0 if how.startswith("written by every rank") == shared else 1)
PY
  $python "$src/tests/mpi/compare_runs.py" "$work/np1" "$work/np2" --files
  # The checkpoint two ranks wrote continues in one process (its content hash and every row
  # accepted) to the uninterrupted run.
  OMP_NUM_THREADS=1 "$ckpd" run "$case_file" --out "$work/np2" --quiet --set output.field_interval=30 \
    --set output.checkpoint_interval=120 --set "output.fields=[$fields]" \
    --restart "$work/np2/checkpoint.h5"
  grep -q '"ranks": 1' "$work/np2/summary.json"
  $python "$src/tests/mpi/compare_runs.py" "$work/np1" "$work/np2"
  ;;
errors)
  # Each rank writes its exit status; stderr must hold the error exactly once.
  expect_failure() {
    label=$1 pattern=$2 ranks_asked=$3
    shift 3
    rm -f "$work"/status.*
    mpi "$ranks_asked" sh -c '"$0" "$@"; echo $? > '"$work"'/status.$OMPI_COMM_WORLD_RANK' \
      "$ckpd" "$@" 2>"$work/err" >/dev/null || true
    count=$(grep -c "ckpd: error: .*$pattern" "$work/err" || true)
    [ "$count" = 1 ] || { echo "$label: the error was printed $count times:"; cat "$work/err"; exit 1; }
    ranks=$(ls "$work"/status.* | wc -l)
    [ "$ranks" = "$np_used" ] || { echo "$label: $ranks of $np_used ranks reported"; exit 1; }
    for f in "$work"/status.*; do
      [ "$(cat "$f")" = 2 ] || { echo "$label: $f exited $(cat "$f"), not 2"; exit 1; }
    done
    echo "$label: one message, exit 2 on all $np_used ranks"
  }
  two=$src/tests/mpi/two_bodies.yaml
  np_used=2 expect_failure "misspelt key" "unknown key 'stepz'" 2 run "$two" --set time.stepz=3 \
    --out "$work/bad"
  touch "$work/a_file"
  np_used=2 expect_failure "unwritable output folder" "cannot create the output directory" 2 \
    run "$two" --out "$work/a_file/out"
  cat >"$work/two_points.yaml" <<'YAML'
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: pair, material: steel, geometry: {type: box, min: [0, 0, 0], max: [0.002, 0.001, 0.001]},
     spacing: 0.001, horizon_ratio: 1.5}
time: {steps: 3}
YAML
  np_used=3 expect_failure "more ranks than points" "fewer than the 3 ranks" 3 \
    run "$work/two_points.yaml" --out "$work/tiny"
  mpi 2 "$ckpd" run "$two" --out "$work/ckpt" --quiet --set time.steps=2 \
    --set output.checkpoint_interval=2
  np_used=2 expect_failure "checkpoint of another case" "written by another case" 2 \
    run "$src/tests/mpi/rigid_indenter.yaml" --restart "$work/ckpt/checkpoint.h5" --out "$work/other"
  ;;
*)
  echo "unknown check '$what'"
  exit 2
  ;;
esac
