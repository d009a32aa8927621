#!/usr/bin/env python3
"""Checks `ckpd schema` (the JSON Schema of the case file, from the loader's key table) against
the case files and the loader's sources. Usage: case_schema_check.py CHECK CKPD SOURCE_DIR

  validate  every case in cases/, tests/ and bench/ validates (python3-jsonschema), and each
            case in cases/ names docs/ckpd.schema.json in its yaml-language-server comment
  misspelt  a case with any one of its keys misspelt fails validation
  literals  every key the loader's sources read ("...optional("k")", required, has) is a key
            of the schema, and every key of the schema is read somewhere
Exit 0 when the check holds, 1 with the failures listed otherwise.
"""
import copy
import json
import pathlib
import re
import subprocess
import sys

import jsonschema
import yaml

COMMENT = "# yaml-language-server: $schema="


class Loader(yaml.SafeLoader):
    """YAML as ckpd reads it: 1e-3 (no dot) is a number, as in YAML 1.2."""


Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?$"),
    list("-+0123456789."))


def load(path):
    with open(path, encoding="utf-8") as f:
        return yaml.load(f, Loader=Loader)


# Hostile inputs the loader must refuse (an alias bomb, ...): not cases, and not to be loaded.
REFUSED = ("tests/data/inputs",)


def case_files(root):
    """The case files of the repository (sweep files, which name a base case, are not cases)."""
    files = []
    for folder in ("cases", "tests", "bench"):
        for path in sorted((root / folder).rglob("*.yaml")):
            if any(path.relative_to(root).as_posix().startswith(r + "/") for r in REFUSED):
                continue
            if "base" not in (load(path) or {}):
                files.append(path)
    return files


def key_paths(node, path=()):
    """(path, key) of every map key in a case, less the names under `materials`."""
    if isinstance(node, dict):
        for key, value in node.items():
            if path != ("materials",):
                yield path, key
            yield from key_paths(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from key_paths(value, path + (i,))


def renamed(case, path, key, new):
    case = copy.deepcopy(case)
    node = case
    for step in path:
        node = node[step]
    node[new] = node.pop(key)
    return case


def schema_keys(schema):
    """Every property name the schema defines."""
    names = set()

    def walk(node):
        if isinstance(node, dict):
            for k, v in node.items():
                if k == "properties":
                    names.update(v)
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)
    walk(schema)
    return names


def check_validate(validator, root):
    failures = []
    files = case_files(root)
    for path in files:
        for error in validator.iter_errors(load(path)):
            failures.append(f"{path}: {'.'.join(map(str, error.absolute_path))}: {error.message}")
        if path.parts[len(root.parts)] == "cases":
            first = path.read_text(encoding="utf-8").splitlines()[0]
            target = (path.parent / first[len(COMMENT):]).resolve()
            if not first.startswith(COMMENT) or target != (root / "docs/ckpd.schema.json"):
                failures.append(f"{path}: line 1 is not '{COMMENT}<path to docs/ckpd.schema.json>'")
    if len(files) < 20:
        failures.append(f"only {len(files)} case files found")
    print(f"{len(files)} case files checked")
    return failures


def check_misspelt(validator, root):
    failures = []
    tried = 0
    for name in ("kalthoff_winkler.yaml", "sphere_disc_impact.yaml", "rigid_indenter.yaml",
                 "mesh_plate_impact.yaml", "kalthoff_winkler_2d_state_based.yaml"):
        case = load(root / "cases" / name)
        assert validator.is_valid(case), name
        for path, key in key_paths(case):
            wrong = key[:-1] if len(key) > 1 else key + "x"
            tried += 1
            if validator.is_valid(renamed(case, path, key, wrong)):
                failures.append(f"cases/{name}: {'.'.join(map(str, path + (key,)))} misspelt "
                                f"'{wrong}' passes the schema")
    print(f"{tried} misspelt keys tried")
    return failures


READ = re.compile(r'(?:\.|->)(?:optional|required|has)\("([A-Za-z_0-9]+)"\)')


def check_literals(schema, root):
    keys = schema_keys(schema)
    failures = []
    read = set()
    for path in sorted((root / "src").rglob("*.cpp")):
        rel = path.relative_to(root).as_posix()
        if rel.startswith(("src/sweep/", "src/case/keys/", "src/cli/")):
            continue  # sweep files are not case files; the table itself; no key reads
        for line_no, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for key in READ.findall(line):
                read.add(key)
                if key not in keys:
                    failures.append(f"{rel}:{line_no}: reads key '{key}', which the schema lacks")
    # The contact laws' parameters are read by name from contact/laws/ (a Catch2 test checks them
    # against the table); every other key of the schema is read by the loader.
    laws = "".join(p.read_text(encoding="utf-8") for p in (root / "contact").rglob("*.cpp"))
    for key in sorted(keys - read):
        if f'"{key}"' not in laws:
            failures.append(f"the schema's key '{key}' is read nowhere in src/")
    print(f"{len(read)} keys read by the loader, {len(keys)} in the schema")
    return failures


def main():
    check, ckpd, root = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3]).resolve()
    schema = json.loads(subprocess.run([ckpd, "schema"], check=True, capture_output=True,
                                       text=True).stdout)
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    if check == "validate":
        failures = check_validate(validator, root)
    elif check == "misspelt":
        failures = check_misspelt(validator, root)
    elif check == "literals":
        failures = check_literals(schema, root)
    else:
        sys.exit(f"unknown check {check!r}")
    for f in failures:
        print(f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
