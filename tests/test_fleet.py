"""A fleet at once: rows per actuator and run, identical on every backend, and parameter drift flagged."""

import json
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
from conftest import FIRST_ORDER_X8

from thermolimb.cli.main import main
from thermolimb.plant import PlantEffects, Quantisation, SensorNoise, ThermalPlant, run_profile
from thermolimb.plant.profiles import random_holds
from thermolimb.workbench.drift import drift
from thermolimb.workbench.fleet import expand_paths, fit_fleet

NAMES = ("a0", "a1", "a2", "a3")
FAN_FAILS = 2  # a2's thermal resistance to ambient rises by half from run 3 on (a failing fan)
RESISTANCE_FACTOR = 1.5


def _fleet_logs(runs=4, duration_s=3600.0):
    net = FIRST_ORDER_X8.network
    hot = replace(FIRST_ORDER_X8, network=replace(
        net, resistance_K_per_W=tuple(RESISTANCE_FACTOR * r for r in net.resistance_K_per_W)))
    logs = []
    for run in range(runs):
        rng = np.random.default_rng(100 + run)
        specs = [hot if (k == FAN_FAILS and run >= 2) else FIRST_ORDER_X8 for k in range(len(NAMES))]
        plant = ThermalPlant(list(NAMES), specs, PlantEffects(sensor_noise=SensorNoise(), quantisation=Quantisation()),
                             rng=rng)
        logs.append(replace(run_profile(plant, random_holds(duration_s, 1.0, len(NAMES), rng)).log,
                            source=f"run{run}.parquet"))
    return logs


@pytest.fixture(scope="module")
def fleet_logs():
    return _fleet_logs()


@pytest.fixture(scope="module")
def rows(fleet_logs):
    return fit_fleet(fleet_logs, "joule,effort_bias", backend="process", workers=2)


def test_one_row_per_actuator_and_run_with_uncertainty(rows):
    assert [(r["actuator"], r["run"]) for r in rows] == [(a, f"run{k}#1") for k in range(4) for a in NAMES]
    for r in rows:
        assert r["error"] is None and r["validation_rmse_K"] < 0.2
        assert all(p["stderr"] > 0 for p in r["params"].values())


def test_process_pool_gives_the_rows_of_the_serial_loop(fleet_logs, rows):
    assert fit_fleet(fleet_logs, "joule,effort_bias", backend="serial") == rows


def test_drift_flags_the_actuator_whose_fan_fails_and_no_other(rows):
    records = {r["actuator"]: r for r in drift(rows)}
    assert [name for name, r in records.items() if r["flagged"]] == ["a2"]
    rc = records["a2"]["params"]["RC_s"]["values"]
    assert 1.35 < np.mean(rc[2:]) / np.mean(rc[:2]) < 1.65  # RC = R C: up by the factor the resistance rose
    assert "RC_s moves" in records["a2"]["why"]


def test_a_run_that_cannot_be_identified_gives_an_error_row(fleet_logs):
    log = fleet_logs[0]
    frame = log.frame.copy()
    frame.loc[frame["actuator"] == "a1", "effort"] = 0.0
    frame.loc[frame["actuator"] == "a1", "temperature"] = 25.0
    rows = fit_fleet([replace(log, frame=frame)], "joule,effort_bias", backend="serial", actuators=["a0", "a1"])
    assert rows[0]["error"] is None  # a slot nothing drives, said as fit says it of one actuator
    assert "a motor that is not connected" in rows[1]["error"] and "params" not in rows[1]
    frame.loc[frame["actuator"] == "a1", "temperature"] = 25.0 + 0.1 * (np.arange(len(frame)) % 7 == 0)[
        frame["actuator"] == "a1"]
    rows = fit_fleet([replace(log, frame=frame)], "joule,effort_bias", backend="serial", actuators=["a0", "a1"])
    assert "cannot identify" in rows[1]["error"] and "params" not in rows[1]


def test_fleet_command_over_a_folder_writes_its_table_whole(fleet_logs, tmp_path, capsys):
    folder = tmp_path / "logs"
    for log in fleet_logs[:3]:
        log.write(folder / log.source)
    (folder / "notes.md").write_text("not a log")
    assert expand_paths([folder]) == sorted(folder.glob("*.parquet"))
    table = tmp_path / "fleet.csv"
    assert main(["fit", "--fleet", str(folder), "--table", str(table), "--plot", str(tmp_path / "plots"),
                 "--workers", "2"]) == 0
    out = capsys.readouterr().out
    assert "a2" in out and "drift" in out
    frame = pd.read_csv(table)
    assert len(frame) == 12 and {"RC_s", "RC_s_stderr", "validation_rmse_K"} <= set(frame.columns)
    assert (tmp_path / "plots" / "drift.png").stat().st_size > 10_000
    assert main(["diagnose", "--fleet", str(folder / "run*.parquet"), "--actuator", "a0", "--json",
                 "--backend", "serial"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert [r["actuator"] for r in record["rows"]] == ["a0"] * 3
    assert all("recommended" in r for r in record["rows"])


@pytest.mark.parametrize("argv, expected", [
    (["fit", "--fleet", "{empty}"], "the folder holds no log"),
    (["fit", "--fleet", "{empty}/*.csv"], "the pattern matches no log"),
    (["fit", "--fleet", "{log}", "--table", "{tmp}/rows.txt"], "expected a .csv or .json file"),
    (["fit", "--fleet", "{log}", "--cv", "runs"], "a fleet fits each run on its own"),
    (["fit", "--fleet", "{log}", "--backend", "ray", "--address", "127.0.0.1:1"], "no Ray cluster answers"),
])
def test_fleet_bad_input_is_one_sentence_and_writes_nothing(fleet_logs, tmp_path, capsys, argv, expected):
    (tmp_path / "empty").mkdir()
    log = fleet_logs[0].write(tmp_path / "one.parquet")
    argv = [a.format(empty=tmp_path / "empty", log=log, tmp=tmp_path) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert expected in err and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["empty", "one.parquet"]


@pytest.mark.slow
def test_ray_gives_the_rows_of_the_serial_loop(fleet_logs, rows):
    pytest.importorskip("ray")
    assert fit_fleet(fleet_logs, "joule,effort_bias", backend="ray") == rows
