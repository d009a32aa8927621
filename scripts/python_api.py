#!/usr/bin/env python3
"""Writes docs/PYTHON_API.md, the reference of the Python module `ckpd`, from the module's own
docstrings and signatures (what help() shows): edit the docstrings (python/src/*.cpp,
python/ckpd/*.py), then run this. A test (python/tests/test_api_page.py) fails while the page
and the docstrings differ.

    PYTHONPATH=build/python python3 scripts/python_api.py          # writes the page
    PYTHONPATH=build/python python3 scripts/python_api.py --check  # exit 1 if it is stale
"""
import argparse
import inspect
import pathlib
import sys

PAGE = pathlib.Path(__file__).resolve().parents[1] / "docs" / "PYTHON_API.md"


def signature(obj, drop_self=True):
    """The call signature without annotations (the types are in the stubs, ckpd/_ckpd.pyi)."""
    sig = inspect.signature(obj)
    params = [p.replace(annotation=inspect.Parameter.empty) for p in sig.parameters.values()
              if not (drop_self and p.name == "self")]
    return str(sig.replace(parameters=params, return_annotation=inspect.Signature.empty))


def doc(obj):
    return (inspect.getdoc(obj) or "").strip()


def members(cls):
    """(kind, name, object) of the class's own public members, in definition order."""
    out = []
    for name, member in vars(cls).items():
        if name.startswith("_"):
            continue
        if isinstance(member, property):
            out.append(("property", name, member))
        elif isinstance(member, (classmethod, staticmethod)):
            out.append(("method", name, getattr(cls, name)))
        elif callable(member):
            out.append(("method", name, member))
    return out


def render_class(name, cls):
    # Classes without a constructor (Body, Condition) come from a Simulation.
    made = signature(cls.__init__)
    if made == "(*args, **kwargs)":
        made = ""
    lines = [f"### ckpd.{name}{made}", "", doc(cls), ""]
    for kind, member_name, member in members(cls):
        if kind == "method":
            drop = not isinstance(vars(cls)[member_name], classmethod)
            head = f"`{member_name}{signature(member, drop_self=drop)}`"
            if isinstance(vars(cls)[member_name], classmethod):
                head += " (class method)"
        else:
            head = f"`{member_name}`" + ("" if member.fset is None else " (settable)")
        text = doc(member).replace("\n", "\n  ")
        lines.append(f"- {head}: {text}")
    lines.append("")
    return lines


def render():
    import ckpd

    functions, classes, errors = [], [], []
    for name in ckpd.__all__:
        obj = getattr(ckpd, name)
        if name.startswith("_"):
            continue
        if inspect.isclass(obj):
            (errors if issubclass(obj, Exception) else classes).append((name, obj))
        else:
            functions.append((name, obj))
    lines = ["# The Python module `ckpd`: reference", "",
             "Generated from the module's docstrings by `scripts/python_api.py` (what "
             "`help(ckpd.X)` shows); types are in the stubs (`ckpd/_ckpd.pyi`, `py.typed`). "
             "Version: `ckpd.__version__`, the program's version.", "",
             doc(ckpd), "", "## Functions", ""]
    for name, obj in functions:
        lines += [f"### ckpd.{name}{signature(obj, drop_self=False)}", "", doc(obj), ""]
    lines += ["## Classes", ""]
    for name, obj in classes:
        lines += render_class(name, obj)
    lines += ["## Exceptions", ""]
    for name, obj in errors:
        bases = ", ".join(b.__name__ for b in obj.__bases__)
        lines += [f"### ckpd.{name} ({bases})", "", doc(obj), ""]
    return "\n".join(lines).rstrip("\n") + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true", help="exit 1 if the page is not up to date")
    args = p.parse_args()
    text = render()
    if args.check:
        if not PAGE.exists() or PAGE.read_text() != text:
            print(f"{PAGE}: differs from the docstrings; run scripts/python_api.py", file=sys.stderr)
            return 1
        return 0
    PAGE.write_text(text)
    print(f"wrote {PAGE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
