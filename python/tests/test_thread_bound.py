"""Thread counts from Python have the ckpd program's bound (0 to 4096): a larger one raises
ValueError before any thread starts (threads=10**6 used to crash inside OpenMP)."""
import pytest

import ckpd


def test_a_million_threads_raise_value_error(plate):
    with pytest.raises(ValueError, match=r"threads: expected 0 \(all cores\) to 4096 OpenMP threads, got 1000000"):
        ckpd.Simulation(plate, threads=10**6)


def test_negative_threads_raise_value_error(plate):
    with pytest.raises(ValueError, match=r"threads: expected 0 \(all cores\) to 4096"):
        ckpd.Simulation(plate, threads=-1)


def test_check_case_and_run_cases_have_the_same_bound(tmp_path, plate):
    with pytest.raises(ValueError, match=r"threads: expected 0 \(all cores\) to 4096"):
        ckpd.check_case(plate, threads=4097)
    with pytest.raises(ValueError, match=r"threads: expected"):
        ckpd.run_cases([plate], tmp_path, threads=10**6)


def test_a_sweep_refuses_too_many_threads_per_run_or_jobs(tmp_path):
    with pytest.raises(ValueError, match=r"threads_per_run: expected 0 \(all cores\) to 4096"):
        ckpd.run_sweep(tmp_path / "sweep.yaml", out=tmp_path / "out", threads_per_run=10**6)
    with pytest.raises(ValueError, match=r"jobs: expected"):
        ckpd.run_sweep(tmp_path / "sweep.yaml", out=tmp_path / "out", jobs=5000)

