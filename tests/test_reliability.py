"""Careless input on every command: one sentence and exit 2, checked before any work, nothing half-written."""

import json
import os
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from thermolimb.cli.main import main
from thermolimb.logs import from_frame, read_log


def run(argv, capsys) -> tuple[int, str]:
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse: a mistake in the options
        code = exc.code
    err = capsys.readouterr().err
    return code, err


def one_sentence(err: str) -> bool:
    return "Traceback" not in err and len(err.strip().splitlines()) == 1


@pytest.fixture
def small_log(tmp_path):
    t = np.arange(200.0)
    frame = pd.DataFrame({"time": t, "actuator": "knee", "effort": 5 + 3 * np.sin(t / 20),
                          "temperature": 30 + 0.02 * t})
    path = tmp_path / "small.csv"
    from_frame(frame).write(path)
    return path


@pytest.mark.parametrize("argv, option", [
    (["simulate", "--duration", "inf", "--out", "{tmp}/a.csv"], "--duration"),
    (["simulate", "--duration", "nan", "--out", "{tmp}/a.csv"], "--duration"),
    (["simulate", "--ambient", "-500", "--out", "{tmp}/a.csv"], "--ambient"),
    (["simulate", "--ambient", "nan", "--out", "{tmp}/a.csv"], "--ambient"),
    (["simulate", "--dt", "0", "--out", "{tmp}/a.csv"], "--dt"),
    (["simulate", "--seed", "-1", "--out", "{tmp}/a.csv"], "--seed"),
    (["simulate", "--load-scale", "-2", "--out", "{tmp}/a.csv"], "--load-scale"),
    (["simulate", "--out", "{tmp}"], "--out"),  # a directory
    (["simulate", "--out", "{file}/a.csv"], "--out"),  # inside a file
    (["compare-strategies", "--env", "x", "--seed", "-1"], "--seed"),
    (["compare-strategies", "--env", "x", "--workers", "0"], "--workers"),
    (["compare-strategies", "--env", "x", "--episodes", "0"], "--episodes"),
    (["compare-strategies", "--env", "x", "--max-time", "nan"], "--max-time"),
    (["fit", "{log}", "--cv", "0"], "--cv"),
    (["fit", "{log}", "--split", "1.5"], "--split"),
    (["fit", "{log}", "--datasheet", "RC_s"], "--datasheet"),
    (["fit", "{log}", "--datasheet", "RC_s=1,RC_s=2"], "--datasheet"),
    (["fit", "{log}", "--datasheet", "RC_s=nan"], "--datasheet"),
    (["fit", "{log}", "--datasheet", "RC_x=600"], "--datasheet"),  # not a parameter of the model
    (["compare", "{log}", "--datasheet", "RC_s=-5"], "--datasheet"),  # outside what RC_s can be
    (["diagnose", "{log}", "--fleet", "--datasheet", "frame_tau_s=900"], "--datasheet"),
    (["fit", "{log}", "--plot", "{file}"], "--plot"),
    (["diagnose", "{log}", "--plot", "{file}"], "--plot"),
    (["demo", "diagnose", "--out", "{file}"], "--out"),
    (["report", "{file}"], "out"),
    (["simulate", "--out", "/proc/thermolimb/a.csv"], "--out"),  # read-only even for root
    (["fit", "{log}", "--plot", "/proc/thermolimb"], "--plot"),
    (["compare-strategies", "--env", "x", "--strategies", ""], "--strategies"),
    (["compare-strategies", "--env", "x", "--strategies", "minimax,,vertical_only"], "--strategies"),
])
def test_options_out_of_range_are_refused_at_parse_time(argv, option, tmp_path, small_log, capsys):
    (tmp_path / "file").write_text("x")
    argv = [a.format(tmp=tmp_path, file=tmp_path / "file", log=small_log) for a in argv]
    code, err = run(argv, capsys)
    assert code == 2
    assert one_sentence(err) and option in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["file", "small.csv"])  # nothing written


def test_a_simulation_too_long_to_hold_is_refused_before_it_starts(tmp_path, capsys):
    code, err = run(["simulate", "--duration", "1e8", "--dt", "0.001", "--out", tmp_path / "a.csv"], capsys)
    assert code == 2 and one_sentence(err) and "rows are written" in err
    assert not list(tmp_path.iterdir())


def test_corrupt_summary_is_named(tmp_path, capsys):
    (tmp_path / "thermal-fit").mkdir()
    (tmp_path / "thermal-fit" / "summary.json").write_text("{not json")
    code, err = run(["report", tmp_path], capsys)
    assert code == 2 and one_sentence(err) and "thermal-fit/summary.json" in err
    assert not (tmp_path / "index.html").exists()


def _no_temporaries(folder) -> bool:
    return not [p for p in folder.rglob("*") if "partial" in p.name]


def test_an_interrupted_write_leaves_the_previous_log_and_no_temporary(tmp_path, small_log, monkeypatch):
    target = tmp_path / "out.csv"
    target.write_text("previous\n")
    log = read_log(small_log)

    def interrupted(self, path, **kwargs):
        with open(path, "w") as f:
            f.write("half a log")
        raise KeyboardInterrupt

    monkeypatch.setattr(pd.DataFrame, "to_csv", interrupted)
    with pytest.raises(KeyboardInterrupt):
        log.write(target)
    assert target.read_text() == "previous\n"
    assert _no_temporaries(tmp_path)


def test_a_failing_report_leaves_the_previous_index(tmp_path, capsys, monkeypatch):
    (tmp_path / "demo").mkdir()
    (tmp_path / "demo" / "summary.json").write_text(json.dumps({"a": 1.0}))
    previous = "<title>thermolimb report</title> previous"  # a page an earlier report wrote
    (tmp_path / "index.html").write_text(previous)

    def broken(self, *args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr("pathlib.Path.write_text", broken)
    with pytest.raises(OSError):
        main(["report", str(tmp_path)])
    monkeypatch.undo()
    assert (tmp_path / "index.html").read_text() == previous
    assert _no_temporaries(tmp_path)


def test_the_report_never_replaces_a_page_it_did_not_write(tmp_path, capsys):
    (tmp_path / "demo").mkdir()
    (tmp_path / "demo" / "summary.json").write_text(json.dumps({"a": 1.0}))
    (tmp_path / "index.html").write_text("<html>the lab's own page</html>")
    assert main(["report", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "was not written by thermolimb report" in err and len(err.strip().splitlines()) == 1
    assert (tmp_path / "index.html").read_text() == "<html>the lab's own page</html>"
    (tmp_path / "index.html").unlink()
    assert main(["report", str(tmp_path)]) == 0 and main(["report", str(tmp_path)]) == 0  # its own page: replaced


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_output_folder_is_refused_before_any_work(tmp_path, small_log, capsys):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        code, err = run(["fit", small_log, "--plot", locked / "plots"], capsys)
    finally:
        locked.chmod(0o700)
    assert code == 2 and one_sentence(err) and "not writable" in err


def test_a_binary_file_named_csv_is_refused_in_one_printable_line(tmp_path, capsys):
    path = tmp_path / "junk.csv"
    path.write_bytes(bytes(range(256)) * 40)
    code, err = run(["fit", path, "--quiet"], capsys)
    assert code == 2 and one_sentence(err) and "not a text file" in err
    assert err.rstrip("\n").isprintable(), err


def test_temperatures_no_actuator_reads_are_refused(tmp_path, small_log, capsys):
    frame = pd.read_csv(small_log)
    for name, temperature in (("kelvin.csv", frame["temperature"] + 273.15 + 300), ("counts.csv", 10 * 4096.0)):
        path = tmp_path / name
        frame.assign(temperature=temperature).to_csv(path, index=False)
        code, err = run(["fit", path, "--quiet"], capsys)
        assert code == 2 and one_sentence(err) and "'temperature' reads" in err and "degC" in err, err


def test_an_error_after_pybullet_is_imported_is_still_one_line(tmp_path):
    """PyBullet prints its build time on the C-level standard error when imported; the suite keeps it off."""
    done = subprocess.run([sys.executable, "-m", "thermolimb.cli.main", "demo", "nope"], capture_output=True,
                          text=True, cwd=tmp_path)
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert not list(tmp_path.iterdir())


@pytest.fixture(scope="module")
def plant_run_csv(tmp_path_factory):
    path = tmp_path_factory.mktemp("faults") / "run.csv"
    assert main(["simulate", "--duration", "600", "--dt", "1", "--network", "first_order", "--out", str(path),
                 "--quiet"]) == 0
    return path


def _cli(*argv: str) -> list[str]:
    return [sys.executable, "-m", "thermolimb.cli.main", *argv]


@pytest.mark.parametrize("extra", [[], ["--json"]])
def test_standard_output_on_a_full_disk_is_one_sentence(plant_run_csv, extra):
    with open("/dev/full", "w") as full:
        proc = subprocess.run(_cli("fit", str(plant_run_csv), "--actuator", "knee", "--quiet", *extra), stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=120)
    assert proc.returncode == 1
    assert proc.stderr.strip() == "thermolimb fit: error: could not write standard output: the disk is full"


def test_a_closed_pipe_ends_the_command_quietly(plant_run_csv):
    proc = subprocess.Popen(_cli("fit", str(plant_run_csv), "--json", "--quiet"), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    proc.stdout.close()  # the reader went away before the first byte, as `| true` does
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141 and err == ""


def test_fitted_models_reports_and_estimators_pickle(plant_run_csv):
    import pickle

    from thermolimb.model import ThermalModel
    from thermolimb.workbench.validation import Scheme, validate_model

    report = validate_model([read_log(plant_run_csv).series("knee")], "joule,effort_bias", Scheme())
    again = pickle.loads(pickle.dumps(report))
    assert again.validation == report.validation and again.model == report.model
    assert pickle.loads(pickle.dumps(report.estimator)).params_ == report.estimator.params_
    with pytest.raises(ValueError, match="finite"):
        ThermalModel(("joule",), {"RC_s": 40.0, "betaR_K_per_effort2": float("nan"), "T_offset_C": 25.0})


def test_sigterm_while_writing_is_met_like_ctrl_c(tmp_path, monkeypatch):
    """SIGTERM (timeout, systemd, CI) arrives while the log is half written: exit 143, no temporary, no output."""
    import signal
    from pathlib import Path

    def terminated_midway(self, path, **kwargs):
        Path(path).write_text("time,actuator\n0,knee\n")  # half a file in the temporary
        os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(pd.DataFrame, "to_csv", terminated_midway)
    before = signal.getsignal(signal.SIGTERM)
    assert main(["simulate", "--duration", "60", "--out", str(tmp_path / "run.csv"), "--quiet"]) == 143
    assert list(tmp_path.iterdir()) == []
    assert signal.getsignal(signal.SIGTERM) is before  # the command puts the process's own handler back


def test_a_fleet_counts_a_file_once_however_it_is_reached(tmp_path):
    from thermolimb.workbench.fleet import expand_paths

    log = tmp_path / "logs" / "a.csv"
    log.parent.mkdir()
    log.write_text("time,actuator,effort,temperature\n")
    (tmp_path / "logs" / "loop").symlink_to(tmp_path / "logs")  # a folder that contains itself
    paths = expand_paths([str(log), str(tmp_path / "logs" / "**" / "*.csv"), log.parent])
    assert paths == [log]
