#!/usr/bin/env bash
# Runs the 2D mode I case to its end and checks that the specimen split in two (two pieces of
# intact-bond connectivity, each at least 20 % of the points). A validation script, not a unit
# test: it takes minutes. Usage: scripts/validate_mode1.sh [extra `ckpd run` options]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
out=runs/mode1_2d
./build/src/ckpd run cases/mode1_2d.yaml --out "$out" "$@"
python3 scripts/check_split.py "$out/summary.json" --body plate --pieces 2
