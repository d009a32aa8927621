#!/usr/bin/env python3
"""Checks that the source folders include each other only downwards, so that they form layers
without cycles. Exit 0 when clean; otherwise lists every offending #include and exits 1.

The layers, lowest first (a folder may include its own files and those of any lower layer):
  base/              what every layer shares (the parallel-threshold policy)
  bodies/            one peridynamic body
  contact/           contact between point sets (never a Body: it sees bodies through a view)
  src/input/         the YAML node wrapper every reader uses
  src/geometry/      shapes, lattices, meshes
  src/engine/        the scene, conditions, rigid bodies, time integration
  src/output/        history, fields, checkpoints, reports
  src/case/          case files turned into a scene
  src/sweep/         sweep files, run keys, the runner
  src/cli/           the `ckpd` subcommands
  src/main.cpp       the program
  python/            the Python module (on top of everything)
Folders below the listed ones (src/geometry/mesh/) belong to their parent's layer. None of them
may include reference/ (the plain reference kernel that tests and benchmarks check against).
Usage: scripts/check_layers.py [ROOT]
"""
import pathlib
import re
import sys

LAYERS = ["base", "bodies", "contact", "src/input", "src/geometry", "src/engine", "src/output",
          "src/case", "src/sweep", "src/cli", "src", "python"]
# Headers a layer may not include even though they lie below it, and why.
FORBIDDEN = {
    "contact": {"bodies/body.hpp": "contact sees bodies only through a point-set view"},
}
# Folders no layer may include: (prefix, why).
OFF_LIMITS = [("reference/", "the reference kernel is for tests and benchmarks only")]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def layer_of(path: str):
    """The layer a repository-relative path belongs to (the longest matching prefix)."""
    best = None
    for layer in LAYERS:
        if layer == "src":
            if path.startswith("src/"):
                best = best or layer
        elif path == layer or path.startswith(layer + "/"):
            if best is None or best == "src" or len(layer) > len(best):
                best = layer
    return best


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    rank = {layer: i for i, layer in enumerate(LAYERS)}
    problems = []
    checked = 0
    for folder in ("base", "bodies", "contact", "src", "python"):
        for f in sorted((root / folder).rglob("*")):
            if f.suffix not in (".cpp", ".hpp", ".h"):
                continue
            rel = f.relative_to(root).as_posix()
            own = layer_of(rel)
            for lineno, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = m.group(1)
                for prefix, why in OFF_LIMITS:
                    if target.startswith(prefix):
                        problems.append(f"{rel}:{lineno}: {own}/ includes {target}: {why}")
                to = layer_of(target)
                if to is None:
                    continue  # a header outside the layered folders
                checked += 1
                if rank[to] > rank[own]:
                    problems.append(f"{rel}:{lineno}: {own}/ includes {target}, a higher layer ({to}/)")
                why = FORBIDDEN.get(own, {}).get(target)
                if why:
                    problems.append(f"{rel}:{lineno}: {own}/ includes {target}: {why}")
    for p in problems:
        print(p)
    print(f"check_layers: {checked} includes checked, {len(problems)} violations")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
