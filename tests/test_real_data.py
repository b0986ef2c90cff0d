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


def test_short_bench_runs_hold_the_offset_where_the_winding_started(real):
    """Two-minute heating runs, far shorter than the motor's time constant, and no cooling: the offset is held at
    the coolest run's first reading, and said, where the fit ran it to its 400 degC bound (issue 81, item 5)."""
    series = runs(real["bldc"], "bldc")
    first, steps = auto_diagnose(series)
    held = [a for a in steps[-1].base.set_aside if a.get("parameter") == "T_offset_C"]
    coolest = min(s.temperature_C[0] for s in series)
    assert held and held[0]["held_at"] == coolest and steps[-1].base.model.params["T_offset_C"] == coolest
    assert "this log only heats" in held[0]["reason"] and "cannot fix the temperature the winding cools to" in held[
        0]["reason"]
    assert not any(f.startswith("T_offset_C") for f in steps[-1].base.flags)


def test_a_heating_only_log_with_an_ambient_holds_the_offset_at_it(real):
    """The same bench runs with an ambient column (as a thrust stand logs one): the offset is held at the logged
    ambient's mean, not at the first reading."""
    from dataclasses import replace

    from thermolimb.workbench.validation import Scheme, validate_model

    series = [replace(s, signals=replace(s.signals, ambient_C=np.full(s.n, 19.5))) for s in runs(real["bldc"], "bldc")]
    report = validate_model(series, ("joule",), Scheme(), reduce=True)
    held = [a for a in report.set_aside if a.get("parameter") == "T_offset_C"]
    assert held and held[0]["held_at"] == 19.5 and "held at the logged ambient's mean, 19.50 degC" in held[0]["reason"]


def test_a_change_that_moves_the_offset_where_its_flags_say_it_cannot_be_is_implausible(real):
    """A change is implausible where its refit puts the offset at a bound or far from the readings and its base's
    fit did not (issue 81, item 6): on the bench's two heating runs the offset left free runs to 180 degC, 159 K
    from the coolest reading; held at the first reading it is not flagged."""
    from thermolimb.workbench.diagnosis.judgement import displaced_offset
    from thermolimb.workbench.diagnosis.refit import evaluate
    from thermolimb.workbench.validation import Scheme

    series = runs(real["bldc"], "bldc")
    held = evaluate(series, ("joule",), Scheme(), fixed={"T_offset_C": min(s.temperature_C[0] for s in series)})
    free = evaluate(series, ("joule",), Scheme())
    said = displaced_offset(free, held)
    assert said.startswith("it moves the offset where it cannot be (T_offset_C = ") and "K from the coolest" in said
    assert displaced_offset(held, held) is None and displaced_offset(free, free) is None  # the base's own: no change
