#!/usr/bin/env bash
# Contact benchmark (docs/PERFORMANCE.md, "Contact"): time per step spent in contact against
# the bodies' own forces, for the sphere-disc scene and the many-body scene, on 1 and 2 threads
# (REPEATS runs each: take the median), and the broad phase's candidate pairs against the number
# of bodies.
#
#   bench/contact_bench.sh [CKPD_BINARY] [OUT_DIR]
#
# Environment:
#   PARTS    which parts to run (default "sphere_disc_full sphere_disc many scaling"):
#            sphere_disc_full  the seed scene at full resolution, SPHERE_DISC_STEPS steps
#                              (default 2; its set-up alone takes minutes), once per thread count
#            sphere_disc       the same scene with the disc at nu = 0.25 (bonds only: about 500x
#                              cheaper), 200 steps, REPEATS times per thread count
#            many              cases/many_bodies.yaml to MANY_END (default 3e-4 s), REPEATS times
#            scaling           bench/many_bodies_case.py --bodies N for N in SCALING_BODIES
#                              (default "25 50 100 200"), to 1 ms (past every first impact), one
#                              thread
#   REPEATS  default 3
# Prints one line per run: scene, threads, steps, s/step, contact s/step, body-force s/step,
# set-up s, and the contact counters.
set -euo pipefail
cd "$(dirname "$0")/.."
ckpd="${1:-build/src/ckpd}"
out="${2:-/tmp/ckpd-contact-bench}"
repeats="${REPEATS:-3}"
parts="${PARTS:-sphere_disc_full sphere_disc many scaling}"
mkdir -p "$out"

report() {  # summary.json, label, threads -> one line
  python3 - "$1" "$2" "$3" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
c, steps = j["contact"], max(j["steps"], 1)
print(f"{sys.argv[2]:<18} threads {sys.argv[3]}  bodies {len(j['bodies']):>3}  steps {j['steps']:>6}  "
      f"step {j['seconds_per_step']*1e3:9.3f} ms  contact {c['contact_seconds']/steps*1e3:8.3f} ms  "
      f"bodies {c['body_force_seconds']/steps*1e3:9.3f} ms  setup {j['setup_seconds']:7.1f} s  "
      f"rebuilds {c['broad_phase_rebuilds']}  pairs/step {c['pairs_checked']/steps:.2f}  "
      f"candidate peak {c['candidate_pairs_peak']}  touching peak {c['touching_pairs_peak']}  "
      f"point pairs peak {c['point_pairs_in_contact_peak']}  peak RSS {j['peak_rss_mb']:.0f} MB",
      flush=True)
EOF
}

# The sphere starts touching the disc (its lowest point l_c above the disc's top points), so
# every timed step has contact. dt = 0.85552 us.
touching="bodies.sphere.geometry.center=[0, 0, 0.013]"
has() { [[ " $parts " == *" $1 "* ]]; }

if has sphere_disc_full; then
  for threads in 1 2; do
    dir="$out/sphere_disc_full_t$threads"
    "$ckpd" run cases/sphere_disc_impact.yaml --quiet --threads "$threads" --out "$dir" \
      --set "$touching" \
      --set "time.end=$(python3 -c "print(${SPHERE_DISC_STEPS:-2} * 8.5552e-07 * 0.999)")"
    report "$dir/summary.json" sphere_disc_full "$threads"
  done
fi

if has sphere_disc; then
  for threads in 1 2; do
    for r in $(seq "$repeats"); do
      dir="$out/sphere_disc_t${threads}_r$r"
      "$ckpd" run cases/sphere_disc_impact.yaml --quiet --threads "$threads" --out "$dir" \
        --set "$touching" --set materials.disc.poisson_ratio=0.25 --set time.end=1.7e-4
      report "$dir/summary.json" sphere_disc_nu025 "$threads"
    done
  done
fi

if has many; then
  for threads in 1 2; do
    for r in $(seq "$repeats"); do
      dir="$out/many_bodies_t${threads}_r$r"
      "$ckpd" run cases/many_bodies.yaml --quiet --threads "$threads" --out "$dir" \
        --set "time.end=${MANY_END:-3e-4}"
      report "$dir/summary.json" many_bodies "$threads"
    done
  done
fi

if has scaling; then
  for n in ${SCALING_BODIES:-25 50 100 200}; do
    dir="$out/scaling_$n"
    mkdir -p "$dir"
    bench/many_bodies_case.py --bodies "$n" > "$dir/case.yaml"
    "$ckpd" run "$dir/case.yaml" --quiet --threads 1 --out "$dir"
    report "$dir/summary.json" "balls_$n" 1
  done
fi
