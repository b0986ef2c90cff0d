"""The monitor's reader is the logs package's: what fit reads it reads, what fit refuses it says, line by line."""

from __future__ import annotations

import datetime
import json
import os

import numpy as np
import pytest

from thermolimb.cli.main import main
from thermolimb.logs import read_log
from thermolimb.logs.follow import PROBE_ROWS, CsvFollower
from thermolimb.model import DEFAULT_MODEL, ThermalModel, save_model
from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS


def _rows(log_path):
    lines = log_path.read_text().splitlines()
    return lines[0], lines[1:]


def _all(runs):
    return {name: np.concatenate([r.arrays["time"] for r in parts]) for name, parts in runs.items()}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """The plant's canonical log (three actuators, one row per actuator and sample), as lines."""
    path = tmp_path_factory.mktemp("follow") / "run.csv"
    simulate_profile("random", 600.0, 1.0, list(CASE_NAMES), list(CASE_SPECS), PlantEffects.realistic_sensor(),
                     seed=2, network=NETWORKS["first_order"]).log.write(path)
    return _rows(path)


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("follow") / "model.json"
    model = ThermalModel(DEFAULT_MODEL, {"RC_s": 80.0, "betaR_K_per_effort2": 0.1, "beta_biasR_K_per_effort": 0.0,
                                         "T_offset_C": 25.0})
    save_model(model, path, actuator="knee", limit_C=90.0)
    return path


def test_a_log_followed_in_pieces_reads_as_the_whole_file_reads(tmp_path, written):
    header, rows = written
    path = tmp_path / "grow.csv"
    follower = CsvFollower(path)
    got = {}
    with open(path, "w") as f:
        f.write(header + "\n")
        for k in range(0, len(rows), 37):  # the writer appends in pieces, the last line sometimes half written
            chunk = "\n".join(rows[k:k + 37]) + "\n"
            f.write(chunk[:-5] if k + 37 < len(rows) else chunk)
            f.flush()
            for name, times in _all(follower.poll()).items():
                got.setdefault(name, []).append(times)
            if k + 37 < len(rows):
                f.write(chunk[-5:])
    for name, times in _all(follower.poll(final=True)).items():
        got.setdefault(name, []).append(times)
    whole = read_log(path)
    for name in whole.actuators:
        np.testing.assert_array_equal(np.concatenate(got[name]), whole.series(name).time_s)
    assert follower.skipped == 0


def test_a_note_every_piece_would_repeat_is_said_once(tmp_path, written):
    """Temperatures stated in kelvin: the first piece says they are converted, and no piece appended after it says
    so again (every appended line repeated it: a monitor following a log for hours said it each second)."""
    header, rows = written
    columns = header.split(",")
    k = columns.index("temperature")
    columns[k] = "temperature [K]"

    def kelvin(line):
        fields = line.split(",")
        fields[k] = f"{float(fields[k]) + 273.15:.2f}"
        return ",".join(fields)

    path = tmp_path / "kelvin.csv"
    follower = CsvFollower(path)
    with open(path, "w") as f:
        f.write(",".join(columns) + "\n")
        for start in range(0, 600, 150):
            f.write("\n".join(kelvin(line) for line in rows[start:start + 150]) + "\n")
            f.flush()
            follower.poll()
    said = [n for n in follower.notes if "read in K" in n]
    assert len(said) == 1 and follower.rows == 600, follower.notes


def test_a_piece_whose_optional_cells_are_blank_is_left_out_with_drop_incomplete(tmp_path):
    """Followed with --drop-incomplete, a piece of one row whose current cell is blank is that row left out, as the
    whole file's reading leaves it out: a column empty in one piece is not refused as a column empty in the log."""
    path = tmp_path / "blank.csv"
    rows = [f"{k:.1f},knee,{1 + k % 3},{30 + 0.01 * k:.2f},{'' if k % 50 == 49 else 0.5 * (1 + k % 3)}"
            for k in range(300)]
    follower = CsvFollower(path, read={"drop_incomplete": True})
    got = []
    with open(path, "w") as f:
        f.write("time,actuator,effort,temperature,current\n")
        for k, row in enumerate(rows):
            f.write(row + "\n")
            f.flush()
            if k >= PROBE_ROWS and k % 50 in (48, 49):  # the blank row (49) arrives alone
                got += [r.arrays["time"] for r in follower.poll().get("knee", [])]
    got += [r.arrays["time"] for r in follower.poll(final=True).get("knee", [])]
    np.testing.assert_array_equal(np.concatenate(got), read_log(path, drop_incomplete=True).series("knee").time_s)
    assert not any("holds no value" in n for n in follower.notes)  # a piece's blank cell is no empty column


def test_a_log_of_many_actuators_starts_when_each_has_its_rows(tmp_path):
    # six joints, a row each per sample: the first PROBE_ROWS rows hold too few of each for the start to read
    path = tmp_path / "six.csv"
    rows = [f"{0.01 * k:.2f},j{a},{a + 1},{30 + 0.01 * k:.2f}" for k in range(2 * PROBE_ROWS) for a in range(6)]
    follower = CsvFollower(path)
    got = {}
    with open(path, "w") as f:
        f.write("time,actuator,effort,temperature\n")
        for k in range(0, len(rows), 10):
            f.write("\n".join(rows[k:k + 10]) + "\n")
            f.flush()
            for name, times in _all(follower.poll()).items():
                got.setdefault(name, []).append(times)
    assert sorted(got) == [f"j{a}" for a in range(6)]
    assert all(np.concatenate(got[n]).size == 2 * PROBE_ROWS for n in got)


def test_what_fit_reads_the_monitor_reads(tmp_path, written):
    """A byte-order mark, semicolons with decimal commas and ISO time stamps: fit reads it, and so does the
    follower, to the same samples."""
    header, rows = written
    t0 = datetime.datetime(2026, 1, 1, 12, 0, 0)
    lines = [header.replace(",", ";")]
    for row in rows:
        fields = row.split(",")
        fields[0] = (t0 + datetime.timedelta(seconds=float(fields[0]))).isoformat() + "Z"
        lines.append(";".join(f if i < 2 else f.replace(".", ",") for i, f in enumerate(fields)))
    path = tmp_path / "lab.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8-sig")
    follower = CsvFollower(path)
    got = _all(follower.poll(final=True))
    whole = read_log(path)
    for name in whole.actuators:
        np.testing.assert_allclose(got[name], whole.series(name).time_s)


def test_a_row_of_units_is_followed_as_fit_reads_it(tmp_path, written):
    header, rows = written
    path = tmp_path / "units.csv"
    path.write_text("\n".join([header, ",".join(["s", "-", "N m", "degC"] + [""] * (header.count(",") - 3))]
                               + rows) + "\n")
    whole = read_log(path)
    got = _all(CsvFollower(path).poll(final=True))
    for name in whole.actuators:
        np.testing.assert_allclose(got[name], whole.series(name).time_s)
    assert len(got[whole.actuators[0]]) == sum(row.split(",")[1] == whole.actuators[0] for row in rows)


def test_a_separator_at_the_end_of_each_data_line_is_no_field(tmp_path, written):
    """A logger that ends each data line with a separator its header lacks: the header is still the header (not a
    preamble), no column becomes an index, and the follower reads what fit reads."""
    header, rows = written
    path = tmp_path / "trailing.csv"
    path.write_text("\n".join([header] + [row + "," for row in rows]) + "\n")
    whole = read_log(path)
    assert set(whole.actuators) == {row.split(",")[1] for row in rows}
    first = rows[0].split(",")
    assert whole.frame["actuator"].iloc[0] == first[1] and whole.frame["time"].iloc[0] == float(first[0])
    got = _all(CsvFollower(path).poll(final=True))
    for name in whole.actuators:
        np.testing.assert_allclose(got[name], whole.series(name).time_s)


def test_bad_lines_are_said_with_their_number_and_skipped(tmp_path, written):
    header, rows = written
    knee = [r for r in rows if r.split(",")[1] == "knee"][: 3 * PROBE_ROWS]
    bad = {PROBE_ROWS + 10: "inserted", PROBE_ROWS + 20: "kelvin", PROBE_ROWS + 30: "text",
           PROBE_ROWS + 40: "back"}
    lines = [header]
    for k, row in enumerate(knee):
        fields = row.split(",")
        if bad.get(k) == "inserted":
            fields.insert(3, "9.9")
        elif bad.get(k) == "kelvin":
            fields[3] = str(float(fields[3]) + 273.15)
        elif bad.get(k) == "text":
            fields = ["the writer said something", "here"]
        elif bad.get(k) == "back":
            fields[0] = "0.5"
        lines.append(",".join(fields))
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n")
    follower = CsvFollower(path)
    got = _all(follower.poll(final=True))
    said = "\n".join(follower.notes)
    for k in bad:
        assert f"line {k + 2}" in said, (k, said)  # line numbers count the header as line 1
    assert "inserted without a new header" in said and "kelvin" in said and "does not come after" in said
    assert follower.skipped == len(bad) and got["knee"].size == len(knee) - len(bad)


def test_a_long_pause_starts_a_new_run(tmp_path, written):
    header, rows = written
    knee = [r for r in rows if r.split(",")[1] == "knee"][: 3 * PROBE_ROWS]
    lines = [header]
    for k, row in enumerate(knee):
        fields = row.split(",")
        if k >= 2 * PROBE_ROWS:
            fields[0] = str(float(fields[0]) + 36000.0)  # ten hours later
        lines.append(",".join(fields))
    path = tmp_path / "pause.csv"
    path.write_text("\n".join(lines) + "\n")
    follower = CsvFollower(path)
    runs = follower.poll(final=True)["knee"]
    after = [r.arrays["time"][0] > 36000.0 for r in runs]
    assert [r.new_run for r in runs] == [k == 0 or a for k, a in enumerate(after)] and sum(after) == 1
    assert "paused for 36001 s" in "\n".join(follower.notes)


def test_a_rotated_file_is_said_and_followed_from_its_start(tmp_path, written):
    header, rows = written
    path = tmp_path / "rot.csv"
    path.write_text("\n".join([header] + rows[: 2 * PROBE_ROWS]) + "\n")
    follower = CsvFollower(path)
    follower.poll()
    os.replace(_write(tmp_path / "new.csv", [header] + rows[2 * PROBE_ROWS: 4 * PROBE_ROWS]), path)
    follower.poll()
    follower.poll(final=True)
    assert "replaced under the same name" in "\n".join(follower.notes)
    assert follower.rows == 4 * PROBE_ROWS


def test_a_file_written_again_from_its_start_starts_a_new_run(tmp_path, written):
    """A log truncated in place and written again from t = 0 (same inode, shorter): said, and each actuator's first
    piece is a new run -- the monitor joined it to the old run's readings and died on time going back."""
    header, rows = written
    path = tmp_path / "again.csv"
    path.write_text("\n".join([header] + rows[: 4 * PROBE_ROWS]) + "\n")
    follower = CsvFollower(path)
    follower.poll()
    with open(path, "w") as f:  # truncated, the same file
        f.write("\n".join([header] + rows[: 2 * PROBE_ROWS]) + "\n")
    runs = follower.poll(final=True)
    said = "\n".join(follower.notes)
    assert "replaced under the same name" in said and "time starts again at t = 0 s" in said, said
    assert runs and all(pieces[0].new_run and pieces[0].arrays["time"][0] == 0.0 for pieces in runs.values())


def _write(path, lines):
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("follow, says", [
    ("missing.csv", "did not appear"), (".", "a folder with no ROS 2 bag"), ("/dev/null", "not a regular file"),
    ("log.parquet", "written whole, not row by row"), ("log.csv.gz", "unknown log format"),
])
def test_what_cannot_be_followed_is_one_sentence(tmp_path, monkeypatch, capsys, model_file, follow, says):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "log.parquet").write_bytes(b"PAR1")
    (tmp_path / "log.csv.gz").write_bytes(b"\x1f\x8b")
    code = main(["monitor", str(model_file), "--follow", follow, "--json-lines", "--idle-exit", "0.3"])
    err = capsys.readouterr().err
    assert code == 2 and says in err and "Traceback" not in err


def test_after_a_pause_the_estimate_starts_again_from_the_reading(tmp_path, written, model_file):
    """Ten hours without a reading: the monitor's filter starts again from the first reading after the pause
    (carried over the pause, the model's state would be hours stale)."""
    from thermolimb.model.saved import ModelFile
    from thermolimb.monitor import Session

    header, rows = written
    knee = [r for r in rows if r.split(",")[1] == "knee"][: 3 * PROBE_ROWS]
    lines = [header]
    for k, row in enumerate(knee):
        fields = row.split(",")
        if k >= 2 * PROBE_ROWS:
            fields[0] = str(float(fields[0]) + 36000.0)
            fields[3] = str(float(fields[3]) + 30.0)  # the joint came back warm
        lines.append(",".join(fields))
    path = _write(tmp_path / "pause.csv", lines)
    session = Session(ModelFile.load(model_file), {}, [], publish_every_s=0.0)
    estimates = session.feed(CsvFollower(path).poll(final=True))
    last = estimates[-1]
    assert last.time_s > 36000.0 and abs(last.winding_C - last.measured_C) < 1.0


def test_a_log_written_again_from_its_start_is_published_from_its_first_sample(tmp_path, written, model_file):
    """Cut short and written again with time from 0 (issue 82, item 5): the new run is published from its first
    sample; before, nothing of it was until its clock passed the old run's last time (on a robot that ran for
    hours, hours of a dark dashboard)."""
    import io

    from thermolimb.model.saved import ModelFile
    from thermolimb.monitor import Session
    from thermolimb.monitor.outputs import JsonLinesOutput

    header, rows = written
    path = tmp_path / "again.csv"
    path.write_text("\n".join([header] + rows[: 4 * PROBE_ROWS]) + "\n")
    stream = io.StringIO()
    session = Session(ModelFile.load(model_file), {}, [JsonLinesOutput(stream)], publish_every_s=10.0)
    follower = CsvFollower(path)
    session.feed(follower.poll())
    old_last = json.loads(stream.getvalue().splitlines()[-1])["time_s"]
    with open(path, "w") as f:  # truncated, the same file, written again from t = 0
        f.write("\n".join([header] + rows[: 2 * PROBE_ROWS]) + "\n")
    before = session.publications
    session.feed(follower.poll())
    published = [json.loads(line)["time_s"] for line in stream.getvalue().splitlines()[before:]]
    assert published and published[0] < 10.0 + 1e-9 < old_last  # the new run's first period, at once
    assert published == sorted(published) and published[-1] < old_last


def test_a_column_inserted_for_good_is_said_once_not_on_every_line(tmp_path, written):
    """From some line on the writer adds a column without a new header (issue 82, item 5): the first lines of the
    new shape are said, then the change once for the run, not a note on each of the hundreds of lines after it;
    when rows of the header's shape come back, that is said with the count skipped, and they are read."""
    header, rows = written
    body = rows[: 2 * PROBE_ROWS]
    odd = [row + ",7" for row in rows[2 * PROBE_ROWS: 2 * PROBE_ROWS + 300]]
    back = rows[2 * PROBE_ROWS + 300: 2 * PROBE_ROWS + 330]
    path = _write(tmp_path / "inserted.csv", [header, *body, *odd, *back])
    follower = CsvFollower(path)
    runs = follower.poll(final=True)
    shape = [n for n in follower.notes if "fields" in n]
    assert len(shape) == 4, shape  # two lines said, the change once, the return once
    assert "the row's shape changed without a new header" in shape[2]
    assert "rows of 7 fields again, after 300 lines of 8 fields" in shape[3]
    assert follower.skipped == 300 and runs
