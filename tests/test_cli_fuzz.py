"""Fuzz of every command's options (hypothesis): whatever a user types, the command either works or says in one
line what is wrong (exit 2); never a traceback, never a temporary file left behind."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from thermolimb.cli.main import main
from thermolimb.logs import from_frame

NUMBERS = st.sampled_from(["0", "-1", "1", "0.5", "2", "1e15", "-1e15", "nan", "inf", "-inf", "1e-300", "x", "",
                           "3.7", "20", "100", "1,5", "0x10", "1e3"])
WORDS = st.sampled_from(["", "knee", "hip", "a,b", "joule", "joule,effort_bias", "copper", "=", "a=b", "time=t",
                         "effort=torque", "runs", "{j}", "*", "none", "all", "../x", "ray", "process", "mode"])


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fuzz")
    t = np.arange(300.0)
    frame = pd.DataFrame({"time": t, "actuator": "knee", "effort": 5 + 3 * np.sin(t / 20),
                          "temperature": 30 + 0.02 * t + 0.5 * np.sin(t / 50)})
    from_frame(frame).write(folder / "log.csv")
    (folder / "afile").write_text("x")
    return folder


def value(draw, workspace):
    kind = draw(st.sampled_from(["number", "word", "path"]))
    if kind == "number":
        return draw(NUMBERS)
    if kind == "word":
        return draw(WORDS)
    return str(workspace / draw(st.sampled_from(["log.csv", "afile", "missing.csv", "out", "out/x.csv", "afile/x",
                                                 "x.parquet", "x.txt", "."])))


OPTIONS = {
    "simulate": ["--profile", "--duration", "--dt", "--actuators", "--network", "--effects", "--load-scale",
                 "--ambient", "--seed", "--out"],
    "fit": ["--map", "--velocity-unit", "--sep", "--decimal", "--actuator", "--model", "--method", "--split", "--cv",
            "--plot"],
    "compare": ["--map", "--actuator", "--model", "--split", "--cv", "--plot"],
    "diagnose": ["--map", "--actuator", "--model", "--split", "--cv", "--refit", "--plot"],
    "compare-strategies": ["--env", "--episodes", "--seed", "--max-time", "--backend", "--workers", "--plot"],
    "demo": ["--out"],
    "report": [],
}
FLAGS = {"simulate": ["--drivers", "--housing-sensor", "--quiet"], "fit": ["--json", "--drop-incomplete"],
         "compare": ["--json"], "diagnose": ["--json", "--restart-at-split"], "compare-strategies": ["--json"],
         "demo": ["--json", "--quick"], "report": []}
SAFE_DURATIONS = {"--duration": ["600", "1e15", "nan", "-5", "0"], "--dt": ["1", "0", "nan", "1e-9"]}


@st.composite
def command_line(draw, workspace):
    command = draw(st.sampled_from(sorted(OPTIONS)))
    argv = [command]
    if command in ("fit", "compare", "diagnose"):
        argv.append(draw(st.sampled_from([str(workspace / "log.csv"), str(workspace / "afile"),
                                          str(workspace / "missing.csv")])))
    if command == "demo":
        argv.append(draw(st.sampled_from(["nosuchdemo", "", "all "])))
    if command == "report":
        argv.append(value(draw, workspace))
    for option in draw(st.lists(st.sampled_from(OPTIONS[command]), max_size=4, unique=True)) if OPTIONS[command] \
            else []:
        if option in SAFE_DURATIONS:  # keep what does run short
            argv += [option, draw(st.sampled_from(SAFE_DURATIONS[option]))]
        elif option == "--env":
            argv += [option, draw(st.sampled_from(["", "thermolimb/Nothing-v0", "x"]))]
        elif option in ("--plot", "--out"):  # a bare number or word would be written into the working folder
            argv += [option, str(workspace / value(draw, workspace))]
        else:
            argv += [option, value(draw, workspace)]
    if command == "simulate" and "--out" not in argv:
        argv += ["--out", str(workspace / "out" / "sim.csv")]
    if command == "simulate":
        argv += ["--duration", "600"] if "--duration" not in argv else []
    argv += draw(st.lists(st.sampled_from(FLAGS[command]), max_size=2, unique=True)) if FLAGS[command] else []
    return argv + (["--quiet"] if command not in ("report",) and "--quiet" not in argv else [])


@pytest.mark.slow
@settings(max_examples=250, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                  HealthCheck.too_slow])
@given(data=st.data())
def test_every_command_works_or_says_what_is_wrong(data, workspace, capsys):
    argv = data.draw(command_line(workspace))
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse
        code = exc.code
    err = capsys.readouterr().err
    assert code in (0, 2), (argv, err)
    assert "Traceback" not in err, (argv, err)
    if code == 2:
        assert len(err.strip().splitlines()) == 1, (argv, err)
    assert not [p for p in workspace.rglob("*") if "partial" in p.name], argv
