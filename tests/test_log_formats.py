"""Logs as users bring them: CSV dialects, preambles, comments, time formats, joint patterns, pauses, holes.

Each test writes a small file the way real loggers do and reads it with the
suite's own options; the fuzz test feeds the reader arbitrary text and
demands that it either reads it or refuses it with a ``LogError``.
"""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from thermolimb.logs import LogError, parse_mapping, read_log

N = 40


def bench_rows(n=N):
    t = np.arange(n) * 0.5
    return t, np.linspace(0.0, 3.0, n), 25.0 + 0.05 * t


def _comma(x: float, digits: int) -> str:
    return f"{x:.{digits}f}".replace(".", ",")


def test_semicolons_decimal_commas_iso_timestamps_and_comments(tmp_path):
    t, effort, temperature = bench_rows()
    stamps = pd.Timestamp("2022-10-26T08:17:21.847Z") + pd.to_timedelta(t, unit="s")
    lines = ["# exported by a cobot's controller", "Timestamp;Current;Temp;;"]
    lines += [f"{s.strftime('%Y-%m-%dT%H:%M:%S.%f')[:-3]}Z;{_comma(e, 4)};{_comma(T, 3)};;"
              for s, e, T in zip(stamps, effort, temperature)]
    lines.insert(10, "# a comment in the middle")
    path = tmp_path / "cobot.csv"
    path.write_text("\n".join(lines) + "\n")
    log = read_log(path, parse_mapping("time=Timestamp,effort=Current,temperature=Temp"), actuator_name="j0")
    frame = log.frame
    np.testing.assert_allclose(frame["time"], t, atol=1e-6)  # seconds from the first stamp
    np.testing.assert_allclose(frame["effort"], np.round(effort, 4))
    assert log.actuators == ("j0",)
    assert any("seconds from the first sample" in n for n in log.notes)


def test_data_logger_preamble_and_clock_times(tmp_path):
    t, effort, temperature = bench_rows()
    lines = ['"Device: USB-2408"', '"Channel Count: 2"', '"Start Time: 20/11/2025 18:21:10.8"',
             '"Sample","Time (s)","Load","Winding (°C)"']
    lines += [f'"{k}","{int(s // 60)}:{s % 60:04.1f}","{e:.3f}","{T:.3f}"' for k, (s, e, T)
              in enumerate(zip(t + 55.0, effort, temperature))]
    path = tmp_path / "daq.csv"
    path.write_text("\ufeff" + "\n".join(lines) + "\n", encoding="utf-8")
    log = read_log(path, parse_mapping("time=Time (s),effort=Load,temperature=Winding (°C)"))
    np.testing.assert_allclose(log.frame["time"], t + 55.0, atol=1e-9)  # m:ss.s read as elapsed seconds


def test_a_row_of_units_under_the_header_gives_the_units(tmp_path):
    """A DAQ's export: the header, then a row of units, then numbers.  The units are read as a header's
    ``name [unit]`` would be: the effort in mA, the temperature converted from degF."""
    t, effort, temperature = bench_rows()
    lines = ["time,actuator,effort,temperature", "[s],-,mA,°F"]
    lines += [f"{s},knee,{1000 * e:.1f},{T * 9 / 5 + 32:.3f}" for s, e, T in zip(t, effort, temperature)]
    path = tmp_path / "daq.csv"
    path.write_text("\n".join(lines) + "\n")
    log = read_log(path)
    assert log.series("knee").n == N and log.units["effort"] == "mA"
    np.testing.assert_allclose(log.frame["temperature"], temperature, atol=1e-3)
    assert any("degrees Fahrenheit" in note for note in log.notes)
    lines[1] = "-1.0,knee,1.0,80.0"  # numbers, not units: a data row, read as one
    path.write_text("\n".join(lines) + "\n")
    assert read_log(path).series("knee").n == N + 1


def test_parquet_datetime_time_column(tmp_path):
    t, effort, temperature = bench_rows()
    frame = pd.DataFrame({"time": pd.Timestamp("2024-01-01") + pd.to_timedelta(t, unit="s"), "actuator": "knee",
                          "effort": effort, "temperature": temperature})
    frame.to_parquet(tmp_path / "log.parquet")
    log = read_log(tmp_path / "log.parquet")
    np.testing.assert_allclose(log.frame["time"], t)
    assert any("time stamps turned into seconds from the first sample" in note for note in log.notes)
    frame.assign(time=(t + 7.0).astype(str)).to_parquet(tmp_path / "text.parquet")  # seconds written as text
    log = read_log(tmp_path / "text.parquet")
    np.testing.assert_allclose(log.frame["time"], t + 7.0)  # the numbers as given, not from the first sample
    assert not any("time stamps" in note for note in log.notes)


def test_unreadable_time_is_refused_not_guessed(tmp_path):
    t, effort, temperature = bench_rows()
    frame = pd.DataFrame({"time": [f"sample {k}" for k in range(N)], "actuator": "knee", "effort": effort,
                          "temperature": temperature})
    frame.to_csv(tmp_path / "log.csv", index=False)
    with pytest.raises(LogError, match=r"time column 'time' is not a number of seconds.*row 0"):
        read_log(tmp_path / "log.csv")


def test_joint_pattern_reads_every_joint_in_order(tmp_path):
    t, effort, temperature = bench_rows()
    cols = {"Timestamp": t}
    for j in (2, 0, 1):  # columns in any order; the first temperature column misnamed as real files do
        cols[f"Current_J{j}"] = effort * (j + 1)
        cols["Temperature_T0" if j == 0 else f"Temperature_J{j}"] = temperature + j
        cols[f"Speed_J{j}"] = np.full(N, 0.1 * j)
    cols["Tool_current"] = 0.0
    pd.DataFrame(cols).to_csv(tmp_path / "arm.csv", index=False)
    log = read_log(tmp_path / "arm.csv", parse_mapping(
        "time=Timestamp,effort=Current_J{j},temperature=Temperature_*{j},velocity=Speed_J{j}"))
    assert log.actuators == ("J0", "J1", "J2")
    j1 = log.series("J1")
    np.testing.assert_allclose(j1.signals.effort, effort * 2)
    np.testing.assert_allclose(j1.temperature_C, temperature + 1)
    assert j1.signals.neighbor_names == ("J0", "J2")  # consecutive joints are neighbours


def test_joint_pattern_with_a_joint_missing_a_channel(tmp_path):
    t, effort, temperature = bench_rows()
    frame = pd.DataFrame({"t": t, "I0": effort, "T0": temperature, "I1": effort})
    frame.to_csv(tmp_path / "arm.csv", index=False)
    with pytest.raises(LogError, match=r"joint\(s\) \[1\] have a effort column but no temperature column"):
        read_log(tmp_path / "arm.csv", parse_mapping("time=t,effort=I{j},temperature=T{j}"))


def test_duplicate_map_key_is_refused():
    with pytest.raises(LogError, match="names 'effort' twice"):
        parse_mapping("effort=a,temperature=b,effort=c")


def test_rows_with_only_a_time_stamp_are_left_out_and_said(tmp_path):
    t, effort, temperature = bench_rows()
    frame = pd.DataFrame({"time": t, "actuator": "knee", "effort": effort, "temperature": temperature})
    frame.loc[[5, 6], ["effort", "temperature"]] = np.nan
    frame.to_csv(tmp_path / "log.csv", index=False)
    log = read_log(tmp_path / "log.csv")
    assert len(log.frame) == N - 2
    assert any("2 sample(s)" in n and "only a time stamp" in n for n in log.notes)


def test_incomplete_rows_are_an_error_unless_asked(tmp_path):
    t, effort, temperature = bench_rows()
    frame = pd.DataFrame({"time": t, "actuator": "knee", "effort": effort, "temperature": temperature})
    frame.loc[7, "temperature"] = np.nan
    frame.to_csv(tmp_path / "log.csv", index=False)
    with pytest.raises(LogError, match="--drop-incomplete"):
        read_log(tmp_path / "log.csv")
    log = read_log(tmp_path / "log.csv", drop_incomplete=True)
    assert len(log.frame) == N - 1 and any("incomplete" in n for n in log.notes)


def test_a_pause_in_logging_makes_runs(tmp_path):
    t = np.concatenate([np.arange(30.0), 10_000.0 + np.arange(30.0)])
    frame = pd.DataFrame({"time": t, "actuator": "knee", "effort": 1.0, "temperature": 25 + 0.01 * t % 3})
    frame.to_csv(tmp_path / "log.csv", index=False)
    log = read_log(tmp_path / "log.csv")
    runs = log.runs("knee")
    assert [r.n for r in runs] == [30, 30] and runs[1].time_s[0] == 10_000.0
    assert "cut the log into 2 runs" in log.describe_gaps("knee")


def test_wide_file_named_by_the_user(tmp_path):
    t, effort, temperature = bench_rows()
    pd.DataFrame({"t": t, "torque": effort, "winding": temperature}).to_csv(tmp_path / "run1.csv", index=False)
    log = read_log(tmp_path / "run1.csv", parse_mapping("time=t,effort=torque,temperature=winding"),
                   actuator_name="hip")
    assert log.actuators == ("hip",)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=st.text(alphabet=st.sampled_from(list("0123456789.,;:-+eE #\"\ntimeactuatorffortpquknT ZnaN")),
                    max_size=600))
def test_reader_fuzz_reads_or_refuses_with_one_sentence(tmp_path, text):
    """Arbitrary CSV-like text: either a valid log, or a LogError -- never another exception."""
    path = tmp_path / "fuzz.csv"
    path.write_text("time,actuator,effort,temperature\n" + text)
    try:
        log = read_log(path)
    except LogError as exc:
        assert "\n" not in str(exc).strip()
        return
    assert np.all(np.diff(log.frame["time"].to_numpy()) > 0) or len(log.actuators) > 1


def test_one_place_decides_a_paths_format_for_reading_writing_following_and_finding(tmp_path):
    from thermolimb.logs.formats import asked_for, followed_as, is_log, log_format, written_as

    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
    assert [log_format(p) for p in ("a.csv", "a.TSV", "a.pq", "a.xlsx", "a.bag", "a.mcap", "a.db3", bag)] == \
        ["csv", "csv", "parquet", "xlsx", "bag", "bag", "bag", "bag"]
    assert [written_as(p) for p in ("a.csv", "a.parquet", "a.mcap")] == ["csv", "parquet", "mcap"]
    assert [followed_as(p) for p in ("a.txt", "a.mcap", bag)] == ["csv", "mcap", "mcap"]
    assert is_log(tmp_path / "a.csv") and is_log(bag) and is_log(tmp_path / "a.xlsx")
    assert not is_log(tmp_path / "a.docx")
    # no writer for a ROS 1 bag, nor for a spreadsheet, which is not followed either: one sentence each
    with pytest.raises(LogError, match="unknown log format"):
        written_as("a.bag")
    with pytest.raises(LogError, match="not as Excel workbooks"):
        written_as("a.xlsx")
    with pytest.raises(LogError, match="not a log being written"):
        followed_as("a.xlsx")
    # one actuator asked for: a bag's joint, a wide table's name, a long table's rows
    assert asked_for("a.mcap", "knee", None) == {"actuator_name": "knee", "actuators": None}
    assert asked_for("a.csv", "knee", {"temperature": "T"}) == {"actuator_name": "knee", "actuators": None}
    assert asked_for("a.csv", "knee", {"actuator": "joint"}) == {"actuator_name": None, "actuators": None}
    assert asked_for("a.csv", "knee", None) == {"actuator_name": None, "actuators": ["knee"]}
