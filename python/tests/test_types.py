"""The type stubs hold: mypy (Debian's `mypy`, which scripts/test.sh installs) passes on
examples/python and the package against them, and mypy's stubtest finds the stubs of the
compiled module in agreement with the module itself (names, members, parameters)."""
import os
import pathlib
import subprocess
import sys

import ckpd

BUILT = pathlib.Path(ckpd.__file__).resolve().parent  # the package as built (stubs copied)


def _run(source_dir, args, mypy_path):
    env = dict(os.environ, MYPYPATH=str(mypy_path))
    r = subprocess.run([sys.executable, "-m", *args], capture_output=True, text=True, env=env,
                       cwd=source_dir)
    assert "No module named mypy" not in r.stderr, (
        "mypy is not installed (scripts/test.sh installs Debian's mypy)")
    return r


def test_mypy_passes_on_the_examples_and_the_package(source_dir):
    r = _run(source_dir, ["mypy", "--config-file", "python/mypy.ini", "--cache-dir",
                          str(BUILT.parent / ".mypy_cache"), "examples/python", "python/ckpd"],
             mypy_path=source_dir / "python")
    assert r.returncode == 0, r.stdout + r.stderr


def test_the_stubs_agree_with_the_compiled_module(source_dir):
    r = _run(source_dir, ["mypy.stubtest", "--mypy-config-file", "python/mypy.ini", "--allowlist",
                          "python/stubtest_allowlist.txt", "ckpd._ckpd"],
             mypy_path=BUILT.parent)
    assert r.returncode == 0, r.stdout + r.stderr
