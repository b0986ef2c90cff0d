"""The Python API's mistakes are one sentence each (what is wrong, what is expected); progress bars reach a terminal
only, never a pipe or a log file."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from thermolimb.model import Signals, ThermalModel
from thermolimb.model.saved import ModelFileError, save_model
from thermolimb.plant import X8_9, PlantEffects, ThermalPlant

MODEL = ThermalModel(("joule", "effort_bias"), {"RC_s": 100.0, "betaR_K_per_effort2": 0.1,
                                                "beta_biasR_K_per_effort": 0.0, "T_offset_C": 25.0})


def test_signals_from_lists_are_arrays_and_simulate():
    s = Signals([0, 1, 2], [1, 1, 1])
    assert isinstance(s.time_s, np.ndarray) and isinstance(s.effort, np.ndarray)
    assert MODEL.simulate(s, 30.0).shape == (3,)


@pytest.mark.parametrize("call, message", [
    (lambda: Signals([0, 2, 1], [1, 1, 1]), "Signals.time_s goes back at sample 2 (2 s, then 1 s)"),
    (lambda: MODEL.simulate(Signals(np.arange(3.0), [1, np.nan, 1]), 30.0), "the effort is nan at sample 1"),
    (lambda: ThermalPlant(["a", "b"], [X8_9, X8_9], PlantEffects()).step(np.array([1.0]), None, 1.0),
     "1 effort value(s) for 2 actuators (a, b)"),
])
def test_a_mistake_is_one_sentence(call, message):
    with pytest.raises(ValueError) as error:
        call()
    assert message in str(error.value) and "\n" not in str(error.value)


def test_saving_a_nan_limit_is_refused(tmp_path):
    with pytest.raises(ModelFileError, match='"limit_C" must be a number of degC between -60 and 400 .* got nan'):
        save_model(MODEL, tmp_path / "m.json", limit_C=float("nan"))
    assert not (tmp_path / "m.json").exists()


def test_no_progress_bar_into_a_pipe(tmp_path):
    """A command whose work shows a bar on a terminal writes no carriage return into a piped standard error."""
    run = [sys.executable, "-m", "thermolimb", "simulate", "--profile", "random", "--duration", "600", "--dt", "1",
           "--out", str(tmp_path / "run.csv")]
    assert subprocess.run(run, capture_output=True).returncode == 0
    done = subprocess.run([sys.executable, "-m", "thermolimb", "diagnose", str(tmp_path / "run.csv"), "--actuator",
                           "knee", "--auto"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "\r" not in done.stderr and "it/s" not in done.stderr
