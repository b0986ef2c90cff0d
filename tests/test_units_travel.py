"""A model's units travel with it: a log whose effort is in another unit of the same kind (mN m for N m) is
converted, and said, by predict, the monitor and export's check; one of another kind (a current for a torque)
is refused in one sentence, exit 2."""

import json

import pandas as pd
import pytest

from thermolimb.cli.main import main


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("units")
    log, model = folder / "run.csv", folder / "knee.json"
    assert main(["simulate", "--profile", "random", "--duration", "900", "--dt", "1", "--network", "first_order",
                 "--actuators", "knee:X8-9", "--seed", "4", "--out", str(log), "--quiet"]) == 0
    assert main(["fit", str(log), "--actuator", "knee", "--save", str(model), "--limit-C", "90", "--quiet"]) == 0
    frame = pd.read_csv(log)
    milli, amps = folder / "milli.csv", folder / "amps.csv"
    frame.assign(effort=frame["effort"] * 1000.0).rename(columns={"effort": "effort [mN m]"}).to_csv(milli,
                                                                                                 index=False)
    frame.rename(columns={"effort": "effort [A]"}).to_csv(amps, index=False)
    return folder, model, log, milli, amps


def _predict(model, log):
    assert main(["predict", str(model), str(log), "--threshold", "80", "--json", "--draws", "8"]) == 0


def test_predict_converts_an_effort_of_the_same_kind_and_refuses_another(logs, capsys):
    folder, model, log, milli, amps = logs
    _predict(model, log)
    same = json.loads(capsys.readouterr().out)
    _predict(model, milli)
    out, err = capsys.readouterr()
    converted = json.loads(out)
    assert "effort in mN m read in N m" in err
    for key in ("peak_predicted_C", "measured_rmse_K", "measured_max_error_K"):
        assert converted[key] == pytest.approx(same[key], rel=1e-9, abs=1e-9), key
    assert main(["predict", str(model), str(amps), "--threshold", "80"]) == 2
    err = capsys.readouterr().err
    assert "heats from an effort in N m; the log gives its effort in A" in err and len(err.strip().splitlines()) == 1


def test_the_monitor_refuses_a_log_whose_effort_is_another_kind(logs, capsys):
    folder, model, _, _, amps = logs
    assert main(["monitor", str(model), "--follow", str(amps), "--json-lines", "--idle-exit", "0.2"]) == 2
    assert "heats from an effort in N m; the log gives its effort in A" in capsys.readouterr().err


def test_the_monitor_reads_an_effort_of_the_same_kind_in_the_model_s_unit(logs, capsys):
    folder, model, log, milli, _ = logs
    assert main(["monitor", str(model), "--follow", str(log), "--json-lines", "--idle-exit", "0.2"]) == 0
    plain = capsys.readouterr().out.strip().splitlines()[-1]
    assert main(["monitor", str(model), "--follow", str(milli), "--json-lines", "--idle-exit", "0.2"]) == 0
    out, err = capsys.readouterr()
    assert "effort in mN m is read in N m" in err
    assert json.loads(out.strip().splitlines()[-1])["actuators"] == json.loads(plain)["actuators"]


def test_export_checks_the_model_in_mujoco_against_a_log_in_another_unit_of_its_kind(logs, capsys):
    pytest.importorskip("mujoco")
    folder, model, log, milli, amps = logs
    argv = ["export", str(model), "--actuator", "knee", "--to", "mujoco", "--motor-const", "0.1", "--resistance", "1",
            "--json"]
    assert main([*argv[:2], str(log), *argv[2:]]) == 0
    same = json.loads(capsys.readouterr().out)["check"]
    assert main([*argv[:2], str(milli), *argv[2:]]) == 0
    converted = json.loads(capsys.readouterr().out)["check"]
    assert converted["max_difference_K"] == pytest.approx(same["max_difference_K"], rel=1e-6, abs=1e-9)
    assert converted["rise_K"] == pytest.approx(same["rise_K"], rel=1e-9)
    assert main([*argv[:2], str(amps), *argv[2:]]) == 2
    assert "the log gives its effort in A" in capsys.readouterr().err
