"""An output never lands on a file the same command reads (a recording is the one thing a user cannot make
again): refused in one sentence, exit 2, nothing written; an output that replaces something else says so."""

import os

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
