"""The module documents itself: every public class, function, method, property and exception
has a docstring; the callables have signatures inspect can read, whose parameter names the
calls accept; a version; reprs that say what an object is."""
import inspect
import re
import subprocess

import pytest

import ckpd
from ckpd.sweep import _program


def _public_members(cls):
    for name, member in vars(cls).items():
        if not name.startswith("_") or name == "__init__":
            yield name, member


def test_every_public_name_and_member_has_a_docstring():
    undocumented = []
    for name in ckpd.__all__:
        obj = getattr(ckpd, name)
        if name == "__version__":
            continue
        if not (inspect.getdoc(obj) or "").strip():
            undocumented.append(name)
        if inspect.isclass(obj) and not issubclass(obj, Exception):
            for member_name, member in _public_members(obj):
                doc = member.__doc__ if isinstance(member, property) else getattr(member, "__doc__", None)
                if not (doc or "").strip():
                    undocumented.append(f"{name}.{member_name}")
    assert undocumented == []


def test_help_of_simulation_shows_every_member_with_its_documentation():
    text = pydoc_text(ckpd.Simulation)
    for name, _ in _public_members(ckpd.Simulation):
        assert re.search(rf"^ \|  {name}\b", text, re.M), name
    assert "run(self, steps=None, until=None, callback=None, every=1)" in text
    assert "The simulated time, s" in text


def pydoc_text(obj):
    import pydoc

    return pydoc.plaintext.document(obj)


def test_signatures_are_readable_by_inspect():
    assert list(inspect.signature(ckpd.Simulation.run).parameters) == ["self", "steps", "until", "callback", "every"]
    assert inspect.signature(ckpd.Simulation.run).parameters["every"].default == 1
    assert str(inspect.signature(ckpd.check_case)) == "(case, overrides=None, steps=3, threads=0)"
    assert list(inspect.signature(ckpd.Simulation.__init__).parameters) == [
        "self", "case", "overrides", "out", "restart", "threads", "progress"]


def _defaults(function, **given):
    """Every parameter of `function`'s signature by keyword: its default, else `given`."""
    out = {}
    for name, p in inspect.signature(function).parameters.items():
        if name == "self":
            continue
        out[name] = given[name] if name in given else p.default
        assert out[name] is not inspect.Parameter.empty, name
    return out


def test_the_signatures_parameter_names_are_the_ones_the_calls_take(tmp_path, plate):
    plate["time"]["steps"] = 2
    sim = ckpd.Simulation(**_defaults(ckpd.Simulation.__init__, case=plate, out=str(tmp_path), threads=1))
    assert sim.run(**_defaults(ckpd.Simulation.run)) == 2
    assert sim.checkpoint(**_defaults(ckpd.Simulation.checkpoint)).endswith("checkpoint.h5")
    sim.finish(**_defaults(ckpd.Simulation.finish))
    assert sim.summary()["status"] == "completed"
    report = ckpd.check_case(**_defaults(ckpd.check_case, case=plate, steps=0, threads=1))
    assert report["bodies"][0]["points"] == 400


def test_version_is_the_programs():
    assert re.fullmatch(r"\d+\.\d+\.\d+", ckpd.__version__)
    out = subprocess.run([_program(), "--version"], capture_output=True, text=True, check=True).stdout
    assert out.startswith(f"ckpd {ckpd.__version__} ")


def test_reprs_say_what_an_object_is(tmp_path, plate):
    sim = ckpd.Simulation(plate, out=tmp_path)
    assert repr(sim) == "<ckpd.Simulation 'case dict': 1 body, step 0 of 60, t = 0.0 s, ready>"
    sim.run(steps=5)
    assert re.fullmatch(r"<ckpd.Simulation 'case dict': 1 body, step 5 of 60, t = 2\.50*\d?e-05 s, running>", repr(sim))
    assert repr(sim.bodies["plate"]) == "<ckpd.Body 'plate', 2D, 400 points>"
    assert repr(sim.conditions[1]) == "<ckpd.Condition 1: velocity on 'plate'>"
    sim.run()
    assert re.fullmatch(r"<ckpd.Run .*: 7 history rows, \d+ frames, completed>", repr(ckpd.open_run(tmp_path)))


@pytest.mark.parametrize("name", ["BusyError", "CaseError", "CheckpointError", "InstabilityError",
                                  "SweepError", "TunnellingError"])
def test_exceptions_are_named_as_users_import_them(name):
    assert getattr(ckpd, name).__module__ == "ckpd"
    assert getattr(ckpd, name).__doc__.strip()
