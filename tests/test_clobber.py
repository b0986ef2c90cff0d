"""An output never lands on a file the same command reads (a recording is the one thing a user cannot make
again): refused in one sentence, exit 2, nothing written; an output that replaces something else says so."""

import json
import os

import numpy as np
import pytest

from thermolimb.cli.main import main


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("clobber")
    assert main(["simulate", "--profile", "random", "--duration", "1200", "--dt", "1", "--network", "first_order",
                 "--seed", "1", "--out", str(folder / "run.csv"), "--quiet"]) == 0
    assert main(["fit", str(folder / "run.csv"), "--actuator", "knee", "--save", str(folder / "knee.json"),
                 "--quiet"]) == 0
    os.symlink(folder / "run.csv", folder / "soft.csv")
    os.link(folder / "run.csv", folder / "hard.csv")
    (folder / "terms.py").write_text("from thermolimb.model import Term, register_term\n")
    return folder


@pytest.mark.parametrize("argv", [
    ["fit", "{f}/run.csv", "--actuator", "knee", "--html", "{f}/run.csv"],
    ["fit", "{f}/run.csv", "--actuator", "knee", "--html", "{f}/soft.csv"],  # a symbolic link to the log
    ["fit", "{f}/run.csv", "--actuator", "knee", "--html", "{f}/hard.csv"],  # a hard link: the same inode
    ["fit", "{f}/soft.csv", "--actuator", "knee", "--save", "{f}/run.csv"],
    ["fit", "{f}/run.csv", "--fleet", "--table", "{f}/run.csv"],
    ["compare", "{f}/run.csv", "--actuator", "knee", "--validate-on", "{f}/hard.csv", "--html", "{f}/hard.csv"],
    ["diagnose", "{f}/run.csv", "--actuator", "knee", "--discover", "--terms", "{f}/terms.py",
     "--propose", "{f}/terms.py"],
    ["monitor", "{f}/knee.json", "--follow", "{f}/run.csv", "--mcap", "{f}/hard.csv"],
    ["monitor", "{f}/knee.json", "--follow", "{f}/run.csv", "--layout", "{f}/knee.json"],
    ["fit", "{f}", "--fleet", "--table", "{f}/run.csv"],  # a folder of logs: each of its files is an input
    ["export", "{f}/knee.json", "--to", "mujoco", "--motor-const", "0.1", "--resistance", "1", "--out", "{f}/knee.json"],
])
def test_an_output_onto_an_input_is_refused_and_nothing_changes(folder, argv, capsys):
    before = {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()}
    assert main([a.format(f=folder) for a in argv]) == 2
    err = capsys.readouterr().err
    assert "an output never replaces an input" in err and len(err.strip().splitlines()) == 1
    assert {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()} == before


def test_an_output_that_replaces_another_file_says_replaced(folder, capsys):
    out = folder / "page.html"
    argv = ["fit", str(folder / "run.csv"), "--actuator", "knee", "--html", str(out), "--quiet"]
    assert main(argv) == 0
    assert f"wrote {out}" in capsys.readouterr().err
    assert main(argv) == 0
    assert f"replaced {out}" in capsys.readouterr().err


@pytest.mark.parametrize("argv, said", [
    (["fit", "{f}/run.csv", "--actuator", "knee", "--validate-on", "{f}/run.csv"], "run.csv is given twice"),
    (["diagnose", "{f}/run.csv", "{f}/copy.csv", "--actuator", "knee"], "copy.csv holds the same readings of 'knee'"),
    (["fit", "{f}/run.csv", "{f}/hard.csv", "--save", "{f}/twice.json"], "hard.csv holds the same readings"),
])
def test_a_run_given_twice_is_refused_where_it_would_be_held_out_beside_itself(folder, argv, said, capsys):
    """The same log named twice, a link to it or a copy: fitted on and held out at once, a run would be judged on
    the readings it was fitted on (leave one run out "helping on 2 of 2 held-out runs" on one run)."""
    (folder / "copy.csv").write_bytes((folder / "run.csv").read_bytes())
    assert main([a.format(f=folder) for a in argv]) == 2
    err = capsys.readouterr().err
    assert said in err and "give each run once" in err and len(err.strip().splitlines()) == 1
    assert not (folder / "twice.json").exists()
    assert main(["fit", str(folder / "run.csv"), "--actuator", "knee", "--quiet"]) == 0  # once is fine


@pytest.mark.parametrize("names", [("NA", "None"), ("1", "01"), ("nan", "null")])
def test_actuator_names_are_names(tmp_path, names, capsys):
    """NA, None and nan are names, not missing values; 1 and 01 are two actuators."""
    rows = ["time,actuator,effort,temperature"]
    for name in names:
        rows += [f"{t},{name},{5 + 3 * np.sin(t / 20):.3f},{30 + 0.02 * t + 0.5 * np.sin(t / 30):.3f}"
                 for t in range(300)]
    (tmp_path / "log.csv").write_text("\n".join(rows) + "\n")
    assert main(["fit", str(tmp_path / "log.csv"), "--quiet", "--json"]) == 0
    assert [r["actuator"] for r in json.loads(capsys.readouterr().out)] == list(names)


@pytest.mark.parametrize("mapping, message", [
    ("time=time,effort=effort:furlong,temperature=temperature", "'furlong' is not a unit this suite knows"),
    ("time=time,effort=effort,temperature=effort", "maps column 'effort' to both effort and temperature"),
    ("effort=e{j}{j},temperature=temperature", "uses {j} 2 times"),
])
def test_a_map_mistake_is_named_for_what_it_is(tmp_path, mapping, message, capsys):
    rows = ["time,effort,temperature"] + [f"{t},{5 + np.sin(t / 9):.3f},{30 + 0.01 * t:.3f}" for t in range(300)]
    (tmp_path / "one.csv").write_text("\n".join(rows) + "\n")
    assert main(["fit", str(tmp_path / "one.csv"), "--actuator", "a", "--map", mapping, "--quiet"]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("argv, target", [
    (["export", "{f}/knee.json", "--to", "mujoco", "--motor-const", "0.1", "--resistance", "1", "--out", "{o}/robot.xml"],
     "robot.xml"),
    (["monitor", "{f}/knee.json", "--follow", "{f}/run.csv", "--json-lines", "--idle-exit", "0.2", "--limit-C", "90",
      "--layout", "{o}/layout.json"], "layout.json"),
    (["audit", "--env", "Ant-v5", "--duration", "0.1", "--plant", "x8-9", "--plot", "{o}"], "audit.png"),
])
def test_a_file_the_suite_did_not_write_is_never_replaced_and_its_own_is_said_replaced(folder, tmp_path, argv,
                                                                                       target, capsys):
    """The user's MJCF, layout or figure where an output would go: refused in one sentence, exit 2, the file as
    it was; once the suite's own file is there, a second run replaces it and says so."""
    if argv[0] == "audit":
        pytest.importorskip("mujoco")
    mine = tmp_path / target
    mine.write_bytes(b"<mujoco model='my whole robot'/>\n")
    filled = [a.format(f=folder, o=tmp_path) for a in argv]
    assert main(filled) == 2
    err = capsys.readouterr().err
    assert "was not written by thermolimb" in err and len(err.strip().splitlines()) == 1
    assert mine.read_bytes() == b"<mujoco model='my whole robot'/>\n"
    mine.unlink()
    assert main(filled) == 0
    assert f"wrote {mine}" in capsys.readouterr().err
    assert main(filled) == 0
    assert f"replaced {mine}" in capsys.readouterr().err


def test_a_summary_the_demo_did_not_write_is_not_replaced(tmp_path, capsys):
    (tmp_path / "thermal-fit").mkdir()
    (tmp_path / "thermal-fit" / "summary.json").write_text('{"mine": 1}')
    assert main(["demo", "thermal-fit", "--quick", "--quiet", "--out", str(tmp_path)]) == 2
    assert "summary.json exists and was not written by thermolimb" in capsys.readouterr().err
    assert (tmp_path / "thermal-fit" / "summary.json").read_text() == '{"mine": 1}'


def test_an_actuator_named_with_dashes_writes_well_formed_xml(tmp_path):
    """An XML comment may not hold '--': a name that does is written so that the snippet still parses."""
    import xml.etree.ElementTree as ET

    from thermolimb.mujoco_export import commented

    assert "--" not in commented("a--b---") and not commented("x-").endswith("-")
    ET.fromstring(f"<r><!-- {commented('left--knee-')}: note --></r>")
