"""ckpd from Python: load a case (file or dict), step it, steer it, read its results.

    import ckpd
    sim = ckpd.Simulation("cases/mode1_2d.yaml", overrides={"time.end": 1e-4}, out="runs/m1")
    sim.run(callback=lambda s: print(s.time, s.energies["kinetic"]), every=100)
    run = ckpd.open_run("runs/m1")
"""
import os as _os

# As the ckpd program does (src/main.cpp): idle OpenMP threads sleep unless the user chose a
# policy. OpenMP reads it when it loads, with the compiled module just below.
_os.environ.setdefault("OMP_WAIT_POLICY", "passive")

from ._ckpd import (  # noqa: E402
    Body,
    CaseError,
    CheckpointError,
    Condition,
    InstabilityError,
    Simulation,
    SweepError,
    TunnellingError,
    check_case,
)
from .results import Run, open_run  # noqa: E402

# Named as users import them (ckpd.CaseError, not ckpd._ckpd.CaseError) in reprs and tracebacks.
for _type in (Body, CaseError, CheckpointError, Condition, InstabilityError, Simulation,
              SweepError, TunnellingError):
    _type.__module__ = "ckpd"
del _type
from .sweep import SweepTable, run_cases, run_sweep  # noqa: E402

__all__ = [
    "Body",
    "CaseError",
    "CheckpointError",
    "Condition",
    "InstabilityError",
    "Run",
    "Simulation",
    "SweepError",
    "SweepTable",
    "TunnellingError",
    "check_case",
    "open_run",
    "run_cases",
    "run_sweep",
]
