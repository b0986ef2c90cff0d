"""Logs that read without an error but mean something else: each is converted with a note or refused in one line."""

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from thermolimb.logs import LogError, from_frame, parse_mapping, read_log
from thermolimb.logs.bag_writer import write_mcap


@pytest.fixture
def frame():
    t = np.arange(300.0)
    return pd.DataFrame({"time": t, "actuator": "knee", "effort": 5 + 3 * np.sin(t / 20),
                         "temperature": 30 + 0.02 * t + 0.5 * np.sin(t / 30)})


@pytest.mark.parametrize("scale, unit", [(1e3, "milliseconds"), (1e6, "microseconds"), (1e9, "nanoseconds")])
def test_time_counted_since_1970_in_a_finer_unit_is_converted_and_said(frame, scale, unit):
    log = from_frame(frame.assign(time=1.7e9 * scale + scale * frame["time"]))
    t = log.series("knee").time_s
    assert np.allclose(np.diff(t), 1.0, rtol=1e-6)  # the samples' one-second steps, not 1000 s
    assert any(f"counted in {unit} since 1970: converted to s" in note for note in log.notes)


def test_epoch_seconds_and_stated_units_are_left_alone(frame):
    log = from_frame(frame.assign(time=1.7e9 + frame["time"]))
    assert np.allclose(np.diff(log.series("knee").time_s), 1.0) and not log.notes
    stated = from_frame(frame.assign(time=1.7e12 + frame["time"]).rename(columns={"time": "time [s]"}))
    assert np.allclose(np.diff(stated.series("knee").time_s), 1.0) and not stated.notes


def test_time_steps_too_long_for_seconds_are_said(frame):
    log = from_frame(frame.assign(time=12e3 * frame["time"]))
    assert any("if the time column counts milliseconds" in note for note in log.notes)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.one_of(st.integers(-5, 5).map(float), st.just(float("nan"))), max_size=30), st.booleans())
def test_the_distinct_steps_are_numpys_unique_then_diff_in_order_or_not(values, in_order):
    """The long-step check's steps skip the sort where the stamps are in order already; the same steps always."""
    from thermolimb.logs.plausible import _distinct_steps

    t = np.sort(values) if in_order else np.asarray(values, dtype=float)
    assert np.array_equal(_distinct_steps(t), np.diff(np.unique(t)), equal_nan=True)


def test_temperatures_in_kelvin_are_converted_and_said(frame):
    kelvin = frame.assign(temperature=frame["temperature"] + 273.15, ambient=295.15)
    log = from_frame(kelvin)
    s = log.series("knee")
    assert np.allclose(s.temperature_C, frame["temperature"]) and np.allclose(s.signals.ambient_C, 22.0)
    said = [note for note in log.notes if "taken as kelvin" in note]
    assert len(said) == 2 and "303.1 to" in said[0]  # the numbers that show it, from the log


def test_a_stated_degC_keeps_kelvin_like_numbers(frame):
    log = from_frame(frame.assign(temperature=frame["temperature"] + 250).rename(
        columns={"temperature": "temperature [degC]"}))
    assert log.series("knee").temperature_C.min() > 250 and not log.notes


@pytest.mark.parametrize("sign", [1, -1])
def test_a_jump_between_degC_and_kelvin_is_refused(frame, sign):
    part = frame.index >= 150 if sign > 0 else frame.index < 150
    jumped = frame.assign(temperature=frame["temperature"].where(~part, frame["temperature"] + 273.15))
    with pytest.raises(LogError, match=rf"jumps by {'[+]' if sign > 0 else '-'}273\.\d K at row 150 .*kelvin"):
        from_frame(jumped)


def test_a_repeated_column_is_refused_when_read_and_said_otherwise(tmp_path, frame):
    rows = "".join(f"{r.time},{r.actuator},{r.effort},{r.temperature},{r.temperature + 1},1,2\n"
                   for r in frame.itertuples())
    path = tmp_path / "two.csv"
    path.write_text("time,actuator,effort,temperature,temperature,note,note\n" + rows)
    with pytest.raises(LogError, match="names column 'temperature' 2 times"):
        read_log(path)
    path.write_text("time,actuator,effort,temperature,housing_C,note,note\n" + rows)
    log = read_log(path)
    assert any("names column 'note' 2 times" in note for note in log.notes)


@pytest.fixture(scope="module")
def plant_log():
    from thermolimb.plant import PlantEffects, simulate_profile
    from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS

    return simulate_profile("random", 600.0, 1.0, list(CASE_NAMES), list(CASE_SPECS), PlantEffects.from_names(""),
                            seed=0).log


def test_nan_readings_in_a_bag_are_refused_like_a_table_or_left_out_when_asked(tmp_path, plant_log):
    f = plant_log.frame
    path = tmp_path / "nan.mcap"
    write_mcap(replace(plant_log, frame=f.assign(temperature=f["temperature"].where(f.index % 50 != 7))), path)
    with pytest.raises(LogError, match=r"temperature of knee has 12 missing or non-finite reading\(s\) of 601.*"
                                       r"--drop-incomplete"):
        read_log(path)
    log = read_log(path, drop_incomplete=True)
    assert log.series("knee").n == 601 - 12
    assert any("12 missing or non-finite reading(s) of temperature of knee left out" in n for n in log.notes)
    write_mcap(replace(plant_log, frame=f.assign(temperature=np.nan)), path)
    with pytest.raises(LogError, match="has no finite reading"):
        read_log(path)


def test_a_bag_in_kelvin_is_converted(tmp_path, plant_log):
    path = tmp_path / "kelvin.mcap"
    write_mcap(replace(plant_log, frame=plant_log.frame.assign(temperature=plant_log.frame["temperature"] + 273.15)),
               path)
    log = read_log(path)
    assert np.allclose(log.series("knee").temperature_C, plant_log.series("knee").temperature_C, atol=1e-6)
    assert any("taken as kelvin" in note for note in log.notes)


def test_model_parameters_outside_their_bounds_are_refused_unless_an_unconstrained_regression_made_them():
    from thermolimb.model import ThermalModel

    values = {"RC_s": 40.0, "betaR_K_per_effort2": -1e9, "T_offset_C": 25.0}
    with pytest.raises(ValueError, match=r"betaR_K_per_effort2 = -1e\+09 is outside its bounds \[0, inf\]"):
        ThermalModel(("joule",), values)
    assert ThermalModel(("joule",), values, bounded=False).params["betaR_K_per_effort2"] == -1e9


def test_a_temperature_held_between_its_updates_is_read_on_them(tmp_path, capsys):
    """A PlotJuggler export of joint states at 20 Hz and a temperature topic at 1 Hz, its blanks filled (each
    reading repeated until the next, 7 ms after the joint state it follows), is read on the temperature's updates:
    its readings as the sensor gave them, the effort's root mean square over each second.  Read row by row, the
    filled walk took ``+ sensor_lag`` on a plant without one (thermolimb/logs/held.py).  The plant's own readings,
    quantised to 0.1 degC on the same 20 Hz rows, are not held and are read row by row."""
    from thermolimb.plant import X8_9, PlantEffects, simulate_profile

    fx = PlantEffects.from_names("sensor_noise,quantisation,speed_losses")
    hip = simulate_profile("random", 600.0, 0.05, ["hip"], [X8_9], fx, seed=1).log.series("hip")
    t, effort, temperature = hip.time_s, hip.signals.effort, hip.temperature_C
    second = np.flatnonzero(np.isclose(t % 1.0, 0.0) | np.isclose(t % 1.0, 1.0))
    states = pd.DataFrame({"__time": t, "/joint_states/hip/effort": effort})
    temps = pd.DataFrame({"__time": t[second] + 0.007, "/temps/hip/temperature": temperature[second]})
    export = pd.concat([states, temps]).sort_values("__time", kind="stable").ffill().iloc[1:]
    export.to_csv(path := tmp_path / "plotjuggler.csv", index=False)
    log = read_log(path, mapping=parse_mapping("time=__time,temperature=/temps/{j}/temperature,"
                                               "effort=/joint_states/{j}/effort"))
    assert "hip's temperature holds each reading for about 20 rows: it changes only on a 1 s clock" in str(log.notes)
    # inspect reads the file with the map it suggests and says so, as fit would (the row before the first
    # temperature message holds none: the suggestion then carries --drop-incomplete)
    from thermolimb.cli.main import main

    pd.concat([states.iloc[:1], export]).to_csv(blank := tmp_path / "blank_first.csv", index=False)
    for file, flag in ((path, ""), (blank, " --drop-incomplete")):
        assert main(["inspect", str(file)]) == 0
        out = capsys.readouterr().out
        assert ('suggested: --map "time=__time,temperature=/temps/hip/temperature,effort=/joint_states/hip/effort"'
                + flag + "\n") in out
        assert f"note: read with this map: {file.stem}'s temperature holds each reading for about 20 rows" in out
    run = log.series("hip")
    assert run.n == second.size  # every update a sample, the first and the last rows' among them
    assert np.allclose(run.time_s, t[second] + 0.007, atol=1e-9)
    assert np.array_equal(run.temperature_C, temperature[second])
    # each second's effort: the 20 Hz rows it holds (the first 7 ms still the row before's), as heat
    rows = export["__time"].to_numpy()
    held = export["/joint_states/hip/effort"].to_numpy()
    for k in (3, 100, 400):
        inside = (rows >= run.time_s[k]) & (rows < run.time_s[k + 1])
        pieces = np.diff(np.r_[run.time_s[k], rows[inside][1:], run.time_s[k + 1]])
        assert np.isclose(run.signals.effort[k] ** 2, np.sum(held[inside] ** 2 * pieces) / pieces.sum())
    # a recording resumed after a pause restarts the clock at another phase: each run read on its own
    resumed = export.assign(__time=export["__time"] + t[-1] + 100.43)
    pd.concat([export, resumed]).to_csv(both := tmp_path / "resumed.csv", index=False)
    log = read_log(both, mapping=parse_mapping("time=__time,temperature=/temps/{j}/temperature,"
                                               "effort=/joint_states/{j}/effort"))
    assert "(in 2 of its 2 runs)" in str(log.notes) and "read on its 1202 updates" in str(log.notes)
    assert [r.n for r in log.runs("hip")] == [second.size, second.size]
    plain = read_log(write(tmp_path, pd.DataFrame({"time": t, "actuator": "hip", "effort": effort,
                                                   "temperature": temperature})))
    assert plain.series("hip").n == t.size and not any("holds each reading" in n for n in plain.notes)


def write(tmp_path, frame):
    frame.to_csv(path := tmp_path / "log.csv", index=False)
    return path


@settings(max_examples=60, deadline=None)
@example(rows_per_update=4, phase=0.0, jitter=0.28125, resolution=0.01, seed=2564)  # once missed (held.py)
@given(rows_per_update=st.integers(4, 60), phase=st.floats(0.0, 0.99), jitter=st.floats(0.0, 0.3),
       resolution=st.sampled_from([0.01, 0.1, 0.5]), seed=st.integers(0, 2**16))
def test_a_held_reading_is_found_on_its_clock_and_a_sampled_one_is_not(rows_per_update, phase, jitter, resolution,
                                                                        seed):
    """Whatever the update period (4 to 60 rows), the phase, the rows' jitter (up to 0.3 of a row) and the
    sensor's resolution, a temperature repeated until its next update is found with its period (to 1 %) where most
    updates change its reading, and the same temperature read on every row (quantised, not held) is not.  (A held
    reading that changes on fewer than half its updates moves by less than a step in two: its half-update delay is
    under a quarter of a step, beneath the sensor's own resolution.)"""
    from thermolimb.logs.held import update_grid

    rng = np.random.default_rng(seed)
    n = 400 * rows_per_update
    t = np.arange(n) * 0.05 + rng.uniform(-jitter, jitter, n) * 0.05 * (np.arange(n) > 0)
    truth = 30.0 + 20.0 * (1.0 - np.exp(-t / (0.3 * t[-1]))) + 2.0 * np.sin(t / (0.05 * t[-1]))
    period = rows_per_update * 0.05
    updates = np.floor((t - phase * period) / period)  # the update each row follows (its reading repeated)
    at = np.searchsorted(t, (np.maximum(updates, 0.0)) * period + phase * period)
    held = np.round(truth[np.minimum(at, n - 1)] / resolution) * resolution
    found = update_grid(t, held)
    if np.count_nonzero(np.diff(held)) >= 0.5 * 400:  # most updates change it (else its lag is under a quarter step)
        assert found is not None and abs(found[0] / period - 1.0) < 0.01
    assert update_grid(t, np.round(truth / resolution) * resolution) is None


def test_inspect_says_why_its_map_would_be_refused(tmp_path, frame, capsys):
    """``inspect`` reads the file with the map it suggests, as ``fit`` would: a temperature logged in hundredths of
    a degree is listed, mapped, and said to be refused, in the sentence ``fit`` would give."""
    from thermolimb.cli.main import main

    wide = frame.drop(columns="actuator").rename(columns={"time": "t_s", "effort": "torque_Nm",
                                                          "temperature": "motor_temp"})
    wide.assign(motor_temp=100 * wide["motor_temp"]).to_csv(path := tmp_path / "counts.csv", index=False)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert 'suggested: --map "' in out
    assert "note: read with this map, the file is refused: " in out and "expected degC between" in out
