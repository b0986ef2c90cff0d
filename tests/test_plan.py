"""The next experiment: ``thermolimb plan`` designs a test that sizes a parameter a log could not, within the
actuator's limits; the plant runs it (``simulate --profile plan.csv``) and the fit of the result reports the
standard error the plan promised, within a factor of 1.5.  Bad input is one sentence, exit 2."""

import json

import numpy as np
import pandas as pd
import pytest

from thermolimb.cli.main import main
from thermolimb.model.saved import ModelFile


@pytest.fixture(scope="module")
def short(tmp_path_factory):
    """A 10-minute log of a winding on a slow housing (the plant's two-mass network): the housing's time
    constant, about 1300 s, is twice the log; the model with the second mass fitted and saved."""
    folder = tmp_path_factory.mktemp("plan")
    log, model = folder / "short.csv", folder / "short.json"
    assert main(["simulate", "--profile", "random", "--duration", "600", "--dt", "1", "--network", "second_order",
                 "--actuators", "knee:X8-9", "--seed", "5", "--out", str(log), "--quiet"]) == 0
    assert main(["fit", str(log), "--actuator", "knee", "--model", "joule,second_node", "--save", str(model),
                 "--limit-C", "90", "--quiet"]) == 0
    return folder, model


def test_a_planned_test_sizes_the_slow_mass_as_promised_within_the_limits(short, capsys):
    folder, model = short
    before = ModelFile.load(model)["knee"].stderr["frame_tau_s"]
    plan = folder / "plan.csv"
    assert main(["plan", str(model), "--identify", "frame_tau_s", "--max-effort", "20", "--duration", "1800",
                 "--noise-K", "0.056", "--out", str(plan), "--json", "--plot", str(folder)]) == 0
    promise = json.loads(capsys.readouterr().out)
    table = pd.read_csv(plan)
    # --duration and --max-effort exactly: the set-points span the test and never exceed the peak
    assert table["time"].iloc[-1] == 1800.0 and np.max(np.abs(table["effort"])) <= 20.0
    assert promise["hottest_C"] <= 90.0 - 5.0  # the forecast band's upper end under the limit less the margin
    assert (folder / "plan_knee.png").exists()
    test = folder / "test.csv"
    assert main(["simulate", "--profile", str(plan), "--actuators", "knee:X8-9", "--network", "second_order",
                 "--dt", "1", "--seed", "7", "--out", str(test), "--json"]) == 0
    ran = json.loads(capsys.readouterr().out)
    assert ran["max_true_winding_C"]["knee"] < 90.0  # the plant's true winding never reached the limit
    assert main(["fit", str(test), "--actuator", "knee", "--model", "joule,second_node", "--json"]) == 0
    fitted = json.loads(capsys.readouterr().out)
    obtained = fitted["params"]["frame_tau_s"]["stderr"]
    promised = promise["stderr_after"]["frame_tau_s"]
    assert 1 / 1.5 <= obtained / promised <= 1.5, (obtained, promised)
    assert obtained < before / 20  # the test sizes what the log could not (about 400 s before, 2 s after)


@pytest.mark.parametrize("argv, said", [
    (["--identify", "frame_tau_s", "--max-effort", "20", "--duration", "1800", "--start-C", "88"],
     "the winding starts at 88 degC, at or above the limit less its margin"),
    (["--identify", "frame_tau_s", "--max-effort", "20", "--duration", "15"], "too short for two holds"),
    (["--identify", "sensor_tau_s", "--max-effort", "20", "--duration", "1800"], "has no parameter 'sensor_tau_s'"),
    (["--identify", "frame_tau_s", "--max-effort", "20", "--duration", "1800", "--limit-C", "20"],
     "the winding starts at 25 degC, at or above the limit less its margin (20 - 5 degC)"),
])
def test_bad_plans_are_one_sentence(short, argv, said, capsys):
    folder, model = short
    assert main(["plan", str(model), *argv, "--out", str(folder / "bad.csv")]) == 2
    err = capsys.readouterr().err
    assert said in err and len(err.strip().splitlines()) == 1
    assert not (folder / "bad.csv").exists()


def test_a_question_the_model_cannot_pose_is_refused(short, tmp_path, capsys):
    """A model that reads a log column a plan does not set (the neighbours' temperatures) cannot be planned for."""
    folder, _ = short
    log = tmp_path / "three.csv"
    assert main(["simulate", "--profile", "random", "--duration", "600", "--dt", "1", "--seed", "1", "--out",
                 str(log), "--quiet"]) == 0
    model = tmp_path / "neighbours.json"
    assert main(["fit", str(log), "--actuator", "knee", "--model", "joule,neighbor_coupling", "--save", str(model),
                 "--limit-C", "90", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["plan", str(model), "--identify", "neighbor_ratio", "--max-effort", "20", "--duration", "1800",
                 "--out", str(tmp_path / "p.csv")]) == 2
    assert "reads the log column 'neighbors'" in capsys.readouterr().err
