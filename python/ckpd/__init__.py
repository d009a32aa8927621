"""ckpd from Python: load a case (file or dict), step it, steer it, read its results.

    import ckpd
    sim = ckpd.Simulation("cases/mode1_2d.yaml", overrides={"time.end": 1e-4}, out="runs/m1")
    sim.run(callback=lambda s: print(s.time, s.energies["kinetic"]), every=100)
    run = ckpd.open_run("runs/m1")

Units are SI throughout (2D bodies: per metre of thickness). help(ckpd.Simulation) lists what a
simulation offers; the package has type stubs (mypy, editors).
"""
import os as _os

# As the ckpd program does (src/main.cpp): idle OpenMP threads sleep unless the user chose a
# policy. OpenMP reads it when it loads, with the compiled module just below.
_os.environ.setdefault("OMP_WAIT_POLICY", "passive")

from ._ckpd import (  # noqa: E402
    Body,
    BusyError,
    CaseError,
    CheckpointError,
    Condition,
    InstabilityError,
    Simulation,
    SweepError,
    TunnellingError,
    __version__,
    check_case,
)
from .results import Run, open_run  # noqa: E402

# Named as users import them (ckpd.CaseError, not ckpd._ckpd.CaseError) in reprs and tracebacks.
for _type in (Body, BusyError, CaseError, CheckpointError, Condition, InstabilityError, Simulation,
              SweepError, TunnellingError):
    _type.__module__ = "ckpd"
del _type
check_case.__module__ = "ckpd"
from .sweep import SweepTable, run_cases, run_sweep  # noqa: E402

__all__ = [
    "Body",
    "BusyError",
    "CaseError",
    "CheckpointError",
    "Condition",
    "InstabilityError",
    "Run",
    "Simulation",
    "SweepError",
    "SweepTable",
    "TunnellingError",
    "__version__",
    "check_case",
    "open_run",
    "run_cases",
    "run_sweep",
]
