"""The loop on real logs the suite did not generate (``thermolimb/data/real``), from the default start.

What each asserts is what the README reports: where the search finds physics,
and where the data cannot tell (and the suite says so rather than guessing).
"""

import numpy as np
import pytest

from thermolimb.data import REAL_LOGS
from thermolimb.workbench.diagnosis import auto_diagnose


@pytest.fixture(scope="module")
def real():
    return {key: log.read() for key, log in REAL_LOGS.items()}


def runs(logs, name):
    return [r for log in logs for r in log.runs(name)]


def test_each_real_log_reads_with_its_documented_options(real):
    assert real["ur3"][0].actuators == ("J0", "J1", "J2", "J3", "J4", "J5")
    assert len(runs(real["ur3"], "J0")) == 2  # two parts 5.2 h apart
    assert any("only a time stamp" in n for n in real["ur3"][0].notes)
    assert [log.actuators for log in real["wx200"]] == [("waist",), ("waist",)]
    assert [log.actuators for log in real["bldc"]] == [("bldc",), ("bldc",)]


@pytest.mark.slow
def test_ur3_wrist_joint_finds_heat_from_its_neighbours(real):
    """J5 sits next to J4 in the wrist: their temperatures move together beyond what J5's current explains."""
    first, steps = auto_diagnose(runs(real["ur3"], "J5"))
    assert "neighbor_coupling" in steps[-1].model
    assert first.auto[-1]["rmse_K"] < 0.5 * first.auto[0]["rmse_K"]
    assert any("betaR_K_per_effort2 vanishes" in f for f in first.auto[0]["flags"])  # signed current, one sign


def test_dynamixel_at_whole_degrees_leaves_nothing_to_add(real):
    """1 degC steps: the base model is near the quantisation floor (1/sqrt(12) = 0.29 K; measured 0.60 K on the
    last 30 % of each run) and nothing is added."""
    first, steps = auto_diagnose(runs(real["wx200"], "waist"))
    assert first.auto[0]["rmse_K"] < 2.2 / np.sqrt(12.0)
    assert not set(steps[-1].model) - {"joule", "effort_bias"}


def test_short_bench_runs_say_the_offset_does_the_heating(real):
    """Two-minute heating runs, far shorter than the motor's time constant: the fit is flagged, not trusted."""
    first, _ = auto_diagnose(runs(real["bldc"], "bldc"))
    assert any("T_offset_C" in f and "from the coolest reading" in f for f in first.auto[-1]["flags"])
