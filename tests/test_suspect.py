"""Readings a sensor cannot have meant are found, said with their span, and left out of fitting and validation
(or the actuator refused when too little is left); a temperature in degF beside an ambient in degC is flagged;
the bundled real logs, honest sensors all, are left alone."""

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from thermolimb.logs import read_log
from thermolimb.logs.table import LogError
from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile
from thermolimb.workbench.validation import fit_and_validate


@pytest.fixture(scope="module")
def frame():
    spec = replace(X8_9, network=NETWORKS["first_order"])
    log = simulate_profile("random", 7200.0, 1.0, ["knee"], [spec], PlantEffects.from_names("sensor_noise,quantisation"),
                           seed=1).log
    return log.frame.copy()


def _fit(frame, tmp_path, name):
    path = tmp_path / name
    frame.to_csv(path, index=False)
    log = read_log(path)
    return log, fit_and_validate(log.runs("knee"), "joule,effort_bias")


def test_a_sensor_at_its_ceiling_is_left_out_and_the_fit_recovers(frame, tmp_path):
    t = frame["temperature"].to_numpy()
    _, clean = _fit(frame, tmp_path, "clean.csv")
    ceiling = round(float(np.percentile(t, 85)), 1)
    log, pinned = _fit(frame.assign(temperature=np.minimum(t, ceiling)), tmp_path, "pinned.csv")
    note = next(n for n in log.notes if "ceiling" in n)
    assert f"pinned at its highest reading, {ceiling:g} degC" in note and "left out of fitting and validation" in note
    beta = pinned.model.params["betaR_K_per_effort2"] / clean.model.params["betaR_K_per_effort2"]
    assert 0.9 < beta < 1.1  # the ceiling no longer reads as less heating (it read 32 % low before)


def test_a_stuck_sensor_is_left_out_with_its_span(frame, tmp_path):
    t = frame["temperature"].to_numpy().copy()
    t[3000:5000] = t[3000]
    log, fit = _fit(frame.assign(temperature=t), tmp_path, "stuck.csv")
    assert any("stuck at" in n and "from 2999 s to 4999 s" in n for n in log.notes)
    assert fit.validation["rmse_K"] < 0.1


def test_a_slow_joint_read_in_whole_degrees_is_not_stuck(tmp_path):
    """A 2 Hz log of 40 minutes, whole-degree readings, a joint heating by a degree every ten minutes while its
    effort moves: each reading is held for ten minutes (a quarter of the log) and left by one degree.  Nothing is
    cut (before, each of those ten minutes was left out as a stuck sensor and the run split there)."""
    t = np.arange(0.0, 2400.0, 0.5)
    effort = 2.0 + 1.5 * np.sign(np.sin(2 * np.pi * t / 300.0))  # on and off every 150 s
    temperature = np.round(30.0 + t / 600.0)
    path = tmp_path / "slow.csv"
    path.write_text("time,actuator,effort,temperature\n" + "".join(
        f"{a},J2,{e},{c}\n" for a, e, c in zip(t, effort, temperature)))
    log = read_log(path)
    assert not any("stuck" in n for n in log.notes), log.notes
    assert log.series("J2").n == t.size and len(log.runs("J2")) == 1
    # the same joint ending on its hardest effort: its last, highest reading is held while more heat than on
    # average comes in, but no longer than every reading before it was held -- a coarse sensor, not a ceiling
    harder = np.where(t >= 2100.0, 2.0 * effort + 3.0, effort)
    path.write_text("time,actuator,effort,temperature\n" + "".join(
        f"{a},J2,{e},{c}\n" for a, e, c in zip(t, harder, temperature)))
    log = read_log(path)
    assert not any("ceiling" in n for n in log.notes), log.notes
    assert log.series("J2").n == t.size
    faster = np.round(30.0 + t / 100.0)  # a degree every 100 s; its sensor hangs for ten minutes, then jumps 6 K
    faster[1300:2500] = faster[1300]
    path.write_text("time,actuator,effort,temperature\n" + "".join(
        f"{a},J2,{e},{c}\n" for a, e, c in zip(t, effort, faster)))
    log = read_log(path)
    assert any("stuck at 36 degC" in n and "to 1249.5 s" in n for n in log.notes), log.notes


def test_too_little_left_is_refused(frame, tmp_path):
    t = frame["temperature"].to_numpy().copy()
    t[5:] = t[5]
    (tmp_path / "dead.csv").write_text(frame.assign(temperature=t).to_csv(index=False))
    with pytest.raises(LogError, match="after leaving out the readings a sensor cannot have meant"):
        read_log(tmp_path / "dead.csv")


def test_fahrenheit_beside_an_ambient_in_celsius_is_flagged(frame, tmp_path):
    path = tmp_path / "f.csv"
    frame.assign(temperature=frame["temperature"] * 1.8 + 32, ambient=25.0).to_csv(path, index=False)
    assert any("looks like degF" in n for n in read_log(path).notes)


def test_the_bundled_real_logs_are_left_alone():
    from thermolimb.data import REAL_LOGS

    for key in REAL_LOGS:
        for log in REAL_LOGS[key].read():
            assert not [n for n in log.notes if "cannot have meant" in n or "left out of fitting" in n or "degF" in n]


def test_dropouts_are_left_out(frame, tmp_path):
    t = frame["temperature"].to_numpy().copy()
    t[1000] = 0.0
    t[2000:2002] = -40.0
    t[3000] = 255.0
    log, fit = _fit(frame.assign(temperature=t), tmp_path, "dropouts.csv")
    note = next(n for n in log.notes if "dropout" in n)
    assert "and 2 more stretches (4 samples)" in note
    assert fit.validation["rmse_K"] < 0.1


def test_a_winding_heated_by_fast_pulses_is_not_a_dropout(tmp_path):
    """The X8 winding node heats 10-30 K within two seconds under a pulse and cools as fast (the hidden-effects
    case that runs hot): at 1 Hz that is a ramp, not a reading far from steady neighbours.  The same readings
    with real dropouts injected still have those found, and only those."""
    from thermolimb.plant.cases import HIDDEN_CASES

    log = HIDDEN_CASES["winding_tempco"].log(0, duration_s=1800.0)
    assert not [n for n in log.notes if "left out" in n]
    frame = log.frame
    knee = frame[frame["actuator"] == "knee"].copy()
    t = knee["temperature"].to_numpy().copy()
    # where the readings are steady for a few samples on either side: a sensor dropping to 0 there
    steady = [k for k in range(10, t.size - 10) if np.all(np.abs(np.diff(t[k - 4:k + 5])) < 1.0)]
    assert len(steady) >= 2
    t[steady[0]] = 0.0
    t[steady[-1]] = -40.0
    path = tmp_path / "pulses.csv"
    knee.assign(temperature=t).to_csv(path, index=False)
    notes = [n for n in read_log(path).notes if "dropout" in n]
    assert len(notes) == 1 and "and 1 more stretches (2 samples)" in notes[0], notes


def test_a_joint_nobody_asked_about_never_sinks_the_one_asked_about(frame, tmp_path, capsys):
    """In the log validated on, another joint reads garbage (kelvin every other row, then stuck): --actuator
    knee reads and checks the knee only, in both logs."""
    from thermolimb.cli.main import main

    other = frame.assign(actuator="wrist")
    other["temperature"] = np.where(np.arange(len(other)) % 2, 300.0, 27.0)
    frame.to_csv(tmp_path / "fit.csv", index=False)
    # the knee again, read 0.25 K warmer: another run (the same run twice is refused, tests/test_clobber.py)
    pd.concat([frame.assign(temperature=frame["temperature"] + 0.25), other]).to_csv(tmp_path / "other.csv",
                                                                                    index=False)
    assert main(["fit", str(tmp_path / "fit.csv"), "--actuator", "knee", "--validate-on", str(tmp_path / "other.csv"),
                 "--quiet"]) == 0
    capsys.readouterr()
    # read whole, the wrist is set aside with one note naming it and why, and the knee is fitted
    assert main(["fit", str(tmp_path / "other.csv"), "--quiet"]) == 0
    out, err = capsys.readouterr()
    assert "actuator 'wrist'" in err and "that actuator is set aside, the others are read" in err
    assert out.startswith("knee: model")
    # asked for by name, the wrist is refused with the reason it was set aside
    assert main(["fit", str(tmp_path / "other.csv"), "--actuator", "wrist", "--quiet"]) == 2
    assert "temperature of actuator 'wrist' jumps by +273.0 K" in capsys.readouterr().err


def test_fahrenheit_in_a_log_that_starts_under_load_is_flagged_from_its_first_reading(tmp_path):
    """A winding logged in degF beside a 25 degC ambient, the log starting under load (issue 82, item 6): no
    readings at rest, so the first reading (77 degF, where the air is) says it; the same log in degC, starting at
    the air's 25 degC, is left alone; a motor that starts hot in degC (77 degC, 52 K above the air) cannot be told
    from it by its first reading, and the note says that it may be."""
    t = np.arange(0.0, 1200.0)
    winding_C = 25.0 + 40.0 * (1.0 - np.exp(-t / 300.0))
    frame = pd.DataFrame({"time": t, "actuator": "knee", "effort": 10.0 + np.sin(t / 50.0), "ambient": 25.0})
    for temperature, said in ((winding_C * 1.8 + 32.0, True), (winding_C, False), (winding_C + 52.0, True)):
        path = tmp_path / "under_load.csv"
        frame.assign(temperature=temperature).to_csv(path, index=False)
        notes = [n for n in read_log(path).notes if "looks like degF" in n]
        assert bool(notes) is said, notes
    said = " ".join(read_log_notes(frame.assign(temperature=winding_C * 1.8 + 32.0), tmp_path))
    assert "reads 77.0 at its first reading where the ambient reads 25.0 degC" in said
    assert "unless the winding started 52 K above the air" in said


def read_log_notes(frame, folder):
    path = folder / "again.csv"
    frame.to_csv(path, index=False)
    return read_log(path).notes
