"""Small, fast cases for the module's tests (each runs in well under a second)."""
import copy
import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("CKPD_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))

# Mode I in 2D, coarse: a 1 m steel square at dx = 50 mm (20 x 20 points) with a 0.5 m edge
# crack, its top and bottom three rows pulled apart at 5 m/s each in y.
PLATE = {
    "description": "mode I 2D, 20 x 20 points (pytest)",
    "materials": {"steel": {"density": 7580, "youngs_modulus": 210e9, "poisson_ratio": 0.3,
                            "fracture_energy": 140}},
    "bodies": [{"name": "plate", "material": "steel", "dimension": 2, "plane": "stress",
                "geometry": {"type": "box", "min": [0, 0], "max": [1, 1]},
                "spacing": 0.05, "horizon_ratio": 3.015,
                "precracks": [[[0, 0.5], [0.5, 0.5]]]}],
    "conditions": [
        {"type": "velocity", "body": "plate",
         "region": {"type": "box", "min": [0, 0.85], "max": [1, 1]},
         "value": [0, 5.0], "components": ["y"]},
        {"type": "velocity", "body": "plate",
         "region": {"type": "box", "min": [0, 0], "max": [1, 0.15]},
         "value": [0, -5.0], "components": ["y"]},
    ],
    "time": {"steps": 60, "dt": 5e-6},
    "output": {"history_interval": 10},
}


@pytest.fixture
def plate():
    """A fresh copy of the small mode I case (tests change it freely)."""
    return copy.deepcopy(PLATE)


@pytest.fixture
def source_dir():
    return SOURCE
