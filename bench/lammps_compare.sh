#!/usr/bin/env bash
# ckpd against LAMMPS on LAMMPS's own PERI example, examples/peri/in.peri.pmb (a brittle
# cylinder of 3487 points shattered by a spherical indenter, PMB bonds with short-range forces,
# 1000 steps of 1e-7 s), and its ckpd counterpart bench/lammps/pmb_cylinder.yaml (same points,
# horizon, density, bond constant, critical stretch, steps; the differences are listed in that
# file's header and in docs/PERFORMANCE.md).
#
#   bench/lammps_compare.sh [--repeats 3] [--threads "1 2"] [--ckpd build/src/ckpd] [--no-sanity]
#
# Needs LAMMPS with the PERI package and its examples: on Debian `apt-get install lammps
# lammps-examples` (the example input is in lammps-examples; the package has PERI
# and MPI, not the OPENMP package). CI does not run this script.
# Per thread count N and repeat, interleaved (LAMMPS, ckpd, next N, ...) so that both see the
# same machine load, it records the whole process's wall time and peak RSS (/usr/bin/time) and
# each program's own loop time (LAMMPS "Loop time", ckpd seconds_per_step x steps); it prints
# the medians and the median of the per-repeat wall-time ratios LAMMPS / ckpd.
# LAMMPS at N > 1: `-sf omp -pk omp N` if its build has the OPENMP package, else N MPI ranks
# (`mpirun -np N`), its own way of using N cores. The example's settings are kept: neighbor
# 0.001 bin (rebuilt as needed, 46 builds), thermo every 100 steps.
# The sanity part runs each once more with damage output and prints the mean point damage
# (1 - intact/initial bonds, averaged over points) every 100 steps for both.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/.." && pwd)"
repeats=3
threads="1 2"
ckpd="$root/build/src/ckpd"
sanity=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --repeats) repeats="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --ckpd) ckpd="$2"; shift 2 ;;
    --no-sanity) sanity=0; shift ;;
    *) echo "lammps_compare.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
example=/usr/share/lammps/examples/peri/in.peri.pmb
case_file="$here/lammps/pmb_cylinder.yaml"
if ! command -v lmp > /dev/null; then
  echo "lammps_compare.sh: no 'lmp' on PATH; install LAMMPS with: sudo apt-get install lammps lammps-examples" >&2
  exit 2
fi
[[ -f "$example" ]] || { echo "lammps_compare.sh: $example not found (Debian package lammps-examples: sudo apt-get install lammps-examples)" >&2; exit 2; }
[[ -x "$ckpd" ]] || { echo "lammps_compare.sh: $ckpd not built (cmake --build build)" >&2; exit 2; }
PY=/usr/bin/python3
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
lmp_packages="$(lmp -h | sed -n '/^Installed packages:/,/^List of/p')"
grep -qw PERI <<< "$lmp_packages" || { echo "lammps_compare.sh: this LAMMPS has no PERI package" >&2; exit 2; }
has_omp=0; grep -qw OPENMP <<< "$lmp_packages" && has_omp=1
mpi_flags=()
[[ "$(id -u)" == 0 ]] && mpi_flags+=(--allow-run-as-root)

lammps_cmd() {  # N -> command prefix and suffix for N workers
  local n="$1"
  if [[ "$n" == 1 ]]; then echo "lmp"
  elif [[ $has_omp == 1 ]]; then echo "lmp -sf omp -pk omp $n"
  else echo "mpirun ${mpi_flags[*]} --bind-to none -np $n lmp"
  fi
}

echo "== ckpd vs LAMMPS: $example"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "LAMMPS: $(lmp -h | grep -m1 -E '^Large-scale|LAMMPS \(' || true) OPENMP package: $([[ $has_omp == 1 ]] && echo yes || echo 'no (N > 1: MPI ranks)')"
echo "ckpd: $ckpd ($(cd "$root" && git rev-parse --short HEAD 2>/dev/null || echo '?'))"
echo "load before: $(uptime)"
results="$work/results.txt"
: > "$results"
for rep in $(seq 1 "$repeats"); do
  for n in $threads; do
    d="$work/lmp_${n}_$rep"; mkdir -p "$d"
    ( cd "$d" && OMP_NUM_THREADS=1 /usr/bin/time -f "%e %M %U %S" -o time.txt \
        $(lammps_cmd "$n") -in "$example" -log none > screen.txt 2>&1 )
    loop="$(grep -m1 'Loop time of' "$d/screen.txt" | awk '{print $4}')"
    echo "lammps $n $rep $loop $(cat "$d/time.txt")" >> "$results"
    c="$work/ckpd_${n}_$rep"
    /usr/bin/time -f "%e %M %U %S" -o "$work/ckpd_time.txt" \
      "$ckpd" run "$case_file" --out "$c" --threads "$n" --quiet
    cloop="$($PY -c "import json,sys; s=json.load(open(sys.argv[1])); print(s['seconds_per_step']*s['steps'])" "$c/summary.json")"
    echo "ckpd $n $rep $cloop $(cat "$work/ckpd_time.txt")" >> "$results"
    tail -2 "$results" | sed 's/^/  run: /'
  done
done
echo "load after: $(uptime)"
$PY - "$results" <<'PYEOF'
import statistics as st, sys
rows = [l.split() for l in open(sys.argv[1])]
data = {}
for prog, n, rep, loop, wall, rss_kb, user, sys_s in rows:
    data.setdefault((prog, int(n)), {})[int(rep)] = (
        float(wall), float(rss_kb) / 1024, float(loop), float(user) + float(sys_s))
print("\n| workers | LAMMPS wall s | ckpd wall s | ratio LAMMPS/ckpd (median of per-repeat) "
      "| LAMMPS loop s | ckpd loop s | LAMMPS CPU s | ckpd CPU s "
      "| LAMMPS peak RSS MB | ckpd peak RSS MB |")
print("|---|---|---|---|---|---|---|---|---|---|")
for n in sorted({k[1] for k in data}):
    L, C = data[("lammps", n)], data[("ckpd", n)]
    reps = sorted(set(L) & set(C))
    med = lambda d, i: st.median(d[r][i] for r in reps)
    ratio = st.median(L[r][0] / C[r][0] for r in reps)
    print(f"| {n} | {med(L,0):.2f} | {med(C,0):.2f} | {ratio:.2f} | {med(L,2):.2f} | {med(C,2):.2f} "
          f"| {med(L,3):.2f} | {med(C,3):.2f} | {med(L,1):.1f} | {med(C,1):.1f} |")
print(f"(medians of {len(reps)} repeats; CPU = user + system of all threads/ranks; LAMMPS peak "
      "RSS is of the largest process: with MPI, one rank)")
PYEOF

[[ $sanity == 1 ]] || exit 0
echo
echo "== sanity: mean point damage every 100 steps (1 worker each)"
s="$work/sanity"; mkdir -p "$s"
sed -e 's/^thermo .*/compute dmg all reduce ave c_1\nthermo_style custom step c_dmg\nthermo 100/' \
  "$example" > "$s/in.sanity"
( cd "$s" && lmp -in in.sanity -log none > screen.txt 2>&1 )
"$ckpd" run "$case_file" --out "$s/ckpd" --threads 1 --quiet --set output.field_interval=100 \
  --set 'output.fields=[damage]'
$PY - "$s" <<'PYEOF'
import glob, sys, h5py, numpy as np
s = sys.argv[1]
lmp, on = [], False
for line in open(f"{s}/screen.txt"):
    w = line.split()
    if w[:2] == ["Step", "c_dmg"]:
        on = True
    elif on and len(w) == 2 and w[0].isdigit():
        lmp.append(float(w[1]))
    elif on:
        on = False
ck = [float(np.array(h5py.File(f)["body_0/damage"]).mean())
      for f in sorted(glob.glob(f"{s}/ckpd/fields/frame_*.h5"))]
print("| step | LAMMPS mean damage | ckpd mean damage |")
print("|---|---|---|")
for k, (a, b) in enumerate(zip(lmp, ck)):
    print(f"| {100 * k} | {a:.4f} | {b:.4f} |")
PYEOF
grep -E "^ *1000 " "$s/screen.txt" > /dev/null || true
# The column by its header name: history.csv gains columns as features land.
awk -F, 'NR == 1 { for (k = 1; k <= NF; k++) if ($k == "broken_bonds") c = k }
  END { print "ckpd broken bonds at the end: " (c ? $c : "no broken_bonds column") }' "$s/ckpd/history.csv"
