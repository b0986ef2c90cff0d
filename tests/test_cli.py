"""The command line, run in-process through its main(argv), and once as the installed script."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from thermolimb.cli.main import main

FIT_KEYS = {"actuator", "model", "method", "channel_units", "params", "train", "validation", "flags",
            "flags_said", "validation_scheme", "evidence", "set_aside"}
METRIC_KEYS = {"rmse_K", "max_abs_K", "fit_percent"}


@pytest.fixture(scope="module")
def sim_log(tmp_path_factory):
    path = tmp_path_factory.mktemp("sim") / "log.csv"
    code = main(["simulate", "--profile", "random", "--duration", "3600", "--dt", "1", "--network", "first_order",
                 "--effects", "effort_bias,sensor_noise,quantisation", "--seed", "3", "--out", str(path), "--quiet"])
    assert code == 0
    return path


def test_simulate_writes_every_actuator(sim_log):
    frame = pd.read_csv(sim_log)
    assert set(frame["actuator"]) == {"knee", "hip", "ankle"}
    assert {"time", "effort", "temperature", "velocity", "current", "ambient"} <= set(frame.columns)


def test_fit_json_schema(sim_log, capsys, tmp_path):
    code = main(["fit", str(sim_log), "--actuator", "knee", "--json", "--plot", str(tmp_path), "--quiet"])
    assert code == 0
    record = json.loads(capsys.readouterr().out)
    assert set(record) == FIT_KEYS
    assert record["actuator"] == "knee"
    assert record["model"] == ["joule", "effort_bias"]
    assert set(record["params"]) == {"RC_s", "betaR_K_per_effort2", "beta_biasR_K_per_effort", "T_offset_C"}
    for entry in record["params"].values():
        assert set(entry) == {"value", "stderr", "unit"}
    assert set(record["train"]) == METRIC_KEYS and set(record["validation"]) == METRIC_KEYS
    # a first-order plant fitted by the first-order model: validation error near the sensor noise
    assert record["validation"]["rmse_K"] < 0.15
    assert (tmp_path / "fit_knee.png").stat().st_size > 10_000


def test_fit_every_actuator_prints_a_list(sim_log, capsys):
    assert main(["fit", str(sim_log), "--json", "--method", "least_squares"]) == 0
    records = json.loads(capsys.readouterr().out)
    assert [r["actuator"] for r in records] == ["knee", "hip", "ankle"]


def test_fit_text_output_has_units(sim_log, capsys):
    assert main(["fit", str(sim_log), "--actuator", "hip", "--model", "joule"]) == 0
    out = capsys.readouterr().out
    assert "validation  RMSE" in out and "K/(N m)^2" in out


@pytest.mark.parametrize("argv, message", [
    (["fit", "{log}", "--actuator", "elbow"], "no actuator 'elbow'; the log has knee, hip, ankle"),
    (["fit", "{log}", "--model", "joule,copper"], "unknown model term(s) 'copper'"),
    (["fit", "{missing}"], "no such file"),
    (["fit", "/dev/null"], "/dev/null: not a regular file (a device or a pipe)"),
    (["fit", "{folder}"], "a folder that is not a ROS 2 bag (it has no metadata.yaml)"),
    (["fit", "{log}", "--map", "effort=torque"], "--map effort=torque names column 'torque'"),
    (["simulate", "--effects", "magic", "--out", "{tmp}"], "unknown plant effect(s) ['magic']"),
    (["simulate", "--actuators", "knee:X9", "--out", "{tmp}"], "must be NAME:MODEL"),
    (["simulate", "--network", "second_order", "--housing-sensor", "--duration", "60", "--out", "{tmp}"],
     "a housing sensor needs a housing node, and actuator knee's network has winding, frame"),
])
def test_bad_input_is_one_clear_line(argv, message, sim_log, tmp_path, capsys):
    argv = [a.format(log=sim_log, missing=tmp_path / "none.csv", tmp=tmp_path / "x.csv", folder=tmp_path) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.csv").exists()


def test_a_log_with_a_header_and_no_rows_is_said_so(tmp_path, capsys):
    path = tmp_path / "h.csv"
    path.write_text("time,actuator,effort,temperature\n")
    for chosen in ([], ["--actuator", "knee"]):  # the second read only the chosen actuator's rows, and found none
        assert main(["fit", str(path), *chosen]) == 2
        err = capsys.readouterr().err
        assert "the log has no rows with measurements" in err and len(err.strip().splitlines()) == 1


def test_runs_of_one_actuator_in_files_of_their_own_need_its_name_and_a_time_in_hours_is_said(tmp_path, capsys):
    """Two single-actuator files read by one map name their actuators after themselves: given together without
    --actuator, the refusal says so and how to read them as runs of one actuator.  A log whose time reads an hour
    as one second (its temperature moving tens of kelvin per second) is said to be in another unit."""
    t = np.arange(0.0, 1200.0, 2.0)
    effort = np.where((t // 120) % 2 == 0, 8.0, 1.0) * (1.0 + 0.1 * (t // 240))
    for name, load in (("monday", 1.0), ("tuesday", 1.1)):
        pd.DataFrame({"t_s": t, "tau": load * effort, "temp": 25.0 + 0.2 * (load * effort) ** 2
                      * (1 - np.exp(-t / 300.0))}).to_csv(tmp_path / f"{name}.csv", index=False)
    files = [str(tmp_path / "monday.csv"), "--validate-on", str(tmp_path / "tuesday.csv")]
    assert main(["fit", *files, "--map", "time=t_s,effort=tau,temperature=temp"]) == 2
    err = capsys.readouterr().err
    assert (f"tuesday.csv: its actuator is named 'tuesday' after the file, as {tmp_path / 'monday.csv'}'s is "
            f"'monday' (the map names no actuator); to read the files as runs of one actuator, name it: "
            f"--actuator NAME") in err and len(err.strip().splitlines()) == 1
    assert main(["fit", *files, "--map", "time=t_s,effort=tau,temperature=temp", "--actuator", "joint"]) == 0
    assert "joint: model joule,effort_bias" in capsys.readouterr().out
    for name in ("monday", "tuesday"):  # the canonical names, no actuator column: read without a map
        frame = pd.read_csv(tmp_path / f"{name}.csv")
        frame.set_axis(["time", "effort", "temperature"], axis=1).to_csv(tmp_path / f"{name}.csv", index=False)
    assert main(["fit", *files]) == 2
    assert "(the file has no actuator column); to read the files" in capsys.readouterr().err
    assert main(["fit", *files, "--actuator", "joint", "--quiet"]) == 0
    temp = 25.0 + 0.2 * effort**2 * (1 - np.exp(-t / 300.0))
    pd.DataFrame({"t_s": t / 3600.0, "tau": effort, "temp": temp}).to_csv(tmp_path / "hours.csv", index=False)
    main(["fit", str(tmp_path / "hours.csv"), "--map", "time=t_s,effort=tau,temperature=temp"])
    span, hours = np.ptp(temp), t[-1] / 3600.0
    assert (f"the temperature moves {span:.1f} K over the log's {hours:.3g} s ({span / hours:.0f} K/s on average), "
            "faster than any winding heats for long: if the time column counts minutes or hours, state it"
            ) in capsys.readouterr().err
    assert main(["fit", str(tmp_path / "hours.csv"), "--map", "time=t_s:h,effort=tau,temperature=temp"]) == 0
    assert "faster than any winding" not in capsys.readouterr().err


def test_fit_constant_effort_reports_what_is_missing(tmp_path, capsys):
    n = 600
    t = np.arange(n, dtype=float)
    pd.DataFrame({"time": t, "actuator": "a", "effort": 5.0,
                  "temperature": 25 + 8 * (1 - np.exp(-t / 60))}).to_csv(tmp_path / "c.csv", index=False)
    assert main(["fit", str(tmp_path / "c.csv")]) == 2
    assert "cannot identify" in capsys.readouterr().err


def test_installed_script_help_lists_commands_with_units():
    exe = Path(sys.executable).parent / "thermolimb"
    assert exe.is_file(), "the console script is installed beside the interpreter"
    out = subprocess.run([exe, "--help"], capture_output=True, text=True, check=True).stdout
    for command in ("simulate", "fit", "demo", "report"):
        assert command in out
    fit_help = subprocess.run([exe, "fit", "--help"], capture_output=True, text=True, check=True).stdout
    assert "RMSE (K)" in fit_help and "degC" in fit_help


def test_compare_json_and_plot(sim_log, capsys, tmp_path):
    code = main(["compare", str(sim_log), "--actuator", "knee", "--model", "joule", "--model", "joule,effort_bias",
                 "--json", "--plot", str(tmp_path)])
    assert code == 0
    record = json.loads(capsys.readouterr().out)
    assert [m["model"] for m in record["models"]] == [["joule"], ["joule", "effort_bias"]]
    for m in record["models"]:
        assert {"aic", "bic", "params", "validation"} <= set(m)
    # the simulated plant has an effort bias: the model with the bias term wins on held-out data
    assert record["models"][1]["validation"]["rmse_K"] < record["models"][0]["validation"]["rmse_K"]
    assert (tmp_path / "compare_knee.png").is_file()


def test_cv_validates_every_fold(sim_log, capsys):
    assert main(["fit", str(sim_log), "--actuator", "knee", "--cv", "4", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["validation"]["rmse_K"] < 0.15
    with pytest.raises(SystemExit) as refused:  # checked when the options are parsed
        main(["fit", str(sim_log), "--actuator", "knee", "--cv", "1"])
    assert refused.value.code == 2


@pytest.mark.parametrize("command", ["fit", "compare", "diagnose"])
def test_html_page_holds_plotly_once_and_a_figure_per_actuator(sim_log, tmp_path, command):
    page = tmp_path / f"{command}.html"
    extra = ["--model", "joule", "--model", "joule,effort_bias"] if command == "compare" else []
    assert main([command, str(sim_log), "--actuator", "knee", "--html", str(page), "--quiet"] + extra) == 0
    text = page.read_text()
    assert text.count("Plotly.newPlot(") >= 1 and "<script src=" not in text  # plotly.js embedded, nothing fetched
    assert "knee: measured" in text
    assert not list(tmp_path.glob(".*partial*"))


def test_html_target_that_is_a_folder_is_refused_before_any_work(sim_log, tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["diagnose", str(sim_log), "--html", str(tmp_path)])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "--html" in err and "is a directory" in err


def test_diagnose_auto_draws_every_step_over_the_measurement(tmp_path, capsys):
    """The user sees the error fall on the data, not only in a bar chart: one line per step, its residual below."""
    path = tmp_path / "log.csv"
    assert main(["simulate", "--profile", "random", "--duration", "1800", "--dt", "1", "--network", "first_order",
                 "--actuators", "knee:X8-9", "--effects", "sensor_noise,speed_losses", "--out", str(path),
                 "--quiet"]) == 0
    capsys.readouterr()
    assert main(["diagnose", str(path), "--auto", "--plot", str(tmp_path / "plots"), "--html",
                 str(tmp_path / "page.html"), "--json", "--quiet"]) == 0
    steps = json.loads(capsys.readouterr().out)["auto"]
    assert len(steps) > 1
    assert (tmp_path / "plots" / "steps_knee.png").stat().st_size > 10_000
    page = (tmp_path / "page.html").read_text()
    assert all(",".join(step["model"]) in page for step in steps)


@pytest.mark.parametrize("argv, message", [
    (["fit", "{log}", "--table", "{tmp}"], "--table works with --fleet"),
    (["fit", "{log}", "--workers", "2"], "--workers works with --fleet"),
    (["diagnose", "{log}", "--backend", "serial"], "--backend works with --fleet"),
    (["fit", "{log}", "--cv", "3", "--split", "0.5"], "--split and --cv are two ways to validate"),
    (["compare", "{log}", "--actuator", "knee", "--actuator", "hip"], "--actuator given twice ('knee' and 'hip')"),
    (["fit", "{log}", "--limit-C", "90"], "--limit-C is stored in the model file; add --save"),
])
def test_a_flag_that_would_do_nothing_is_refused(argv, message, sim_log, tmp_path, capsys):
    argv = [a.format(log=sim_log, tmp=tmp_path / "t.csv") for a in argv]
    try:
        code = main(argv)
    except SystemExit as exc:  # refused while parsing, as argparse refuses
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "t.csv").exists()


def test_every_command_accepts_quiet():
    """--quiet (no progress bars) is accepted by every command, so a script can pass it to any of them."""
    from thermolimb.cli.main import COMMANDS, build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    missing = [name for name, p in sub.choices.items() if not any("--quiet" in a.option_strings for a in p._actions)]
    assert missing == [] and len(sub.choices) >= len(COMMANDS), missing


def test_a_motor_the_table_lists_but_nothing_drives_is_said_so(sim_log, tmp_path, capsys):
    """A Unitree-like low-state table lists every motor slot; the unused ones read 0 degC at 0 N m throughout.
    Each is not analysed, in a sentence that says why (before, "cannot identify RC_s"), and the others are."""
    frame = pd.read_csv(sim_log)
    table = {"stamp": frame.loc[frame["actuator"] == "knee", "time"].to_numpy()}
    for j, name in enumerate(["knee", "hip", None]):
        rows = frame[frame["actuator"] == name] if name else None
        for field, column in (("temperature", "temperature"), ("tau_est", "effort")):
            table[f"motor_state.{j}.{field}"] = rows[column].to_numpy() if name else np.zeros(table["stamp"].size)
    pd.DataFrame(table).to_csv(path := tmp_path / "lowstate.csv", index=False)
    args = ["fit", str(path), "--map", "time=stamp,temperature=motor_state.{j}.temperature,"
                                       "effort=motor_state.{j}.tau_est", "--quiet"]
    assert main(args) == 1
    out = capsys.readouterr().out
    assert "J0: model joule,effort_bias" in out and "J1: model joule,effort_bias" in out
    assert (f"J2: not analysed: the temperature of J2 reads 0 degC on every one of its {table['stamp'].size} samples "
            f"and its effort 0 throughout: a motor that is not connected") in out
    assert main([*args, "--actuator", "J2"]) == 2
    assert "a model needs a temperature that changes" in capsys.readouterr().err


def test_a_run_written_otherwise_is_validated_on_by_its_own_map(sim_log, tmp_path, capsys):
    """``--validate-on`` reads its logs with ``--validate-map`` where given: the next run of the same joint,
    exported by another tool with other column names, is held out beside a canonical log."""
    other = tmp_path / "sim2.csv"
    assert main(["simulate", "--profile", "random", "--duration", "3600", "--dt", "1", "--network", "first_order",
                 "--effects", "effort_bias,sensor_noise,quantisation", "--seed", "4", "--out", str(other),
                 "--quiet"]) == 0
    knee = pd.read_csv(other).query("actuator == 'knee'")
    knee[["time", "effort", "temperature"]].set_axis(["t_s", "tau", "motor_temp"], axis=1).to_csv(
        wide := tmp_path / "export.csv", index=False)
    args = ["fit", str(sim_log), "--actuator", "knee", "--validate-on", str(wide), "--quiet"]
    assert main(args) == 2  # read by the canonical log's (empty) map, the export has no column named effort
    assert "missing column(s)" in capsys.readouterr().err
    assert main([*args, "--validate-map", "time=t_s,effort=tau,temperature=motor_temp", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert "validated on" in record["validation_scheme"] and record["validation"]["rmse_K"] < 1.0
    assert main([*args, "--validate-map", "time=t_s,effort=torque,temperature=motor_temp"]) == 2
    assert "--validate-map effort=torque names column 'torque', which the file does not have" in capsys.readouterr().err
    assert main(["fit", str(sim_log), "--validate-map", "time=t_s", "--quiet"]) == 2
    assert "--validate-map maps the --validate-on logs" in capsys.readouterr().err


def test_an_option_a_command_does_not_take_is_refused_with_the_one_meant(capsys):
    """``--models`` for ``--model``: the command's own parser refuses it (exit 2, one line) and names the option
    that is close; an option close to none is refused plainly."""
    with pytest.raises(SystemExit) as refused:
        main(["compare", "run.csv", "--models", "joule"])
    err = capsys.readouterr().err
    assert refused.value.code == 2
    assert err.startswith("thermolimb compare: error: unrecognized arguments: --models joule; did you mean --model "
                          "(not --models)?") and len(err.strip().splitlines()) == 1
    with pytest.raises(SystemExit):
        main(["fit", "run.csv", "--nothing"])
    assert "unrecognized arguments: --nothing (see --help)" in capsys.readouterr().err
