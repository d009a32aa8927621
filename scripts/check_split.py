#!/usr/bin/env python3
"""Checks from a run's summary.json that a body split into N large pieces.

A piece is a connected component of intact bonds holding at least --min-fraction of the body's
points (points that lost every bond are components of one point and do not count).
Exit status 0 when the body has exactly --pieces such pieces, 1 otherwise.

    scripts/check_split.py runs/mode1_2d/summary.json --body plate --pieces 2
"""
import argparse
import json
import sys


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("summary")
    parser.add_argument("--body", help="body name (default: the first body)")
    parser.add_argument("--pieces", type=int, default=2)
    parser.add_argument("--min-fraction", type=float, default=0.2)
    args = parser.parse_args()
    with open(args.summary) as f:
        summary = json.load(f)
    if summary.get("status") != "completed":
        print(f"run did not complete: status {summary.get('status')}: {summary.get('message', '')}")
        return 1
    bodies = summary["bodies"]
    body = next((b for b in bodies if args.body in (None, b["name"])), None)
    if body is None:
        print(f"no body named {args.body}")
        return 1
    large = [s for s in body["largest_fragments"] if s >= args.min_fraction * body["points"]]
    print(f"body '{body['name']}': {body['points']} points, {body['fragments']} components, "
          f"largest {body['largest_fragments'][:4]}, {len(large)} pieces of at least "
          f"{args.min_fraction:.0%}; broken bonds {body['broken_bonds']}, "
          f"max damage {body['max_damage']:.3f}")
    return 0 if len(large) == args.pieces else 1


if __name__ == "__main__":
    sys.exit(main())
