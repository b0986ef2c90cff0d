"""A user's broken Term is named in one sentence -- the term, the method, what it returned -- by fit and
compare (exit 2), and set aside by diagnose, which goes on; a term may not replace a built-in, nor declare
bounds that cannot hold; a --terms file that is not Python is refused before it runs."""

import json

import numpy as np
import pytest

from thermolimb.cli.main import main
from thermolimb.model import Parameter, Term, register_term, unregister_term

BROKEN = '''
import sys
import numpy as np
from thermolimb.model import Parameter, Term, register_term


def make(name, body):
    register_term(type(name, (Term,), {"name": name, "description": "broken " + name, "columns": ("effort",),
                                       "parameters": (Parameter(name + "_K", "K", -10.0, 10.0, 1.0, "a gain"),),
                                       "contribution": body}))


make("u_raises", lambda self, p, s: 1 / 0)
make("u_nan", lambda self, p, s: (np.full(s.n, np.nan), 0.0))
make("u_inf", lambda self, p, s: (p["u_inf_K"] * np.full(s.n, np.inf), 0.0))
make("u_shape", lambda self, p, s: (np.zeros(3), 0.0))
make("u_none", lambda self, p, s: None)
make("u_missing", lambda self, p, s: (p["u_missing_K"] * s.channel("torque_sensor"), 0.0))
make("u_nan_gain", lambda self, p, s: (0.0, float("nan")))
make("u_exits", lambda self, p, s: sys.exit(3))
make("u_prints", lambda self, p, s: (print("hello from a term") or p["u_prints_K"] * np.abs(s.effort), 0.0))
'''

CASES = {"u_raises": "failed in contribution: ZeroDivisionError", "u_nan": "values not finite",
         "u_inf": "values not finite", "u_shape": "an array of shape (3,) for its rise",
         "u_none": "contribution returned None", "u_missing": "KeyError: 'torque_sensor'",
         "u_nan_gain": "returned nan for its gain", "u_exits": "called sys.exit(3)"}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("terms")
    assert main(["simulate", "--profile", "random", "--duration", "2400", "--dt", "1", "--network", "first_order",
                 "--effects", "sensor_noise,quantisation,speed_losses", "--seed", "2", "--out",
                 str(folder / "run.csv"), "--quiet"]) == 0
    (folder / "broken.py").write_text(BROKEN)
    return folder


@pytest.mark.parametrize("term", sorted(CASES))
def test_fit_names_the_broken_term_in_one_sentence(files, term, capsys):
    argv = ["fit", str(files / "run.csv"), "--actuator", "knee", "--terms", str(files / "broken.py"), "--model",
            f"joule,{term}", "--quiet"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"term {term!r}" in err and CASES[term] in err, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_compare_names_it_too(files, capsys):
    assert main(["compare", str(files / "run.csv"), "--actuator", "knee", "--terms", str(files / "broken.py"),
                 "--model", "joule", "--model", "joule,u_raises", "--quiet"]) == 2
    assert "term 'u_raises' failed in contribution" in capsys.readouterr().err


def test_diagnose_sets_broken_terms_aside_and_goes_on(files, capsys):
    assert main(["diagnose", str(files / "run.csv"), "--actuator", "knee", "--terms", str(files / "broken.py"),
                 "--quiet", "--json", "--stability", "0"]) == 0
    out = capsys.readouterr()
    record = json.loads(out.out)  # a term that prints does not corrupt the JSON
    by_effect = {c["effect"]: c for c in record["candidates"]}
    for term in CASES:
        assert by_effect[term]["status"] == "set aside" and f"term {term!r}" in by_effect[term]["set_aside"]
    assert record["recommended_change"] == "+ speed_losses"  # the search went on to what the log holds


def test_a_term_may_not_replace_a_built_in_or_declare_bounds_that_cannot_hold():
    with pytest.raises(ValueError, match="would replace the built-in term of that name"):
        register_term(type("Mine", (Term,), {"name": "joule", "description": "mine", "parameters": ()}))
    with pytest.raises(ValueError, match="needs lower < upper"):
        register_term(type("Bad", (Term,), {"name": "u_bounds", "description": "bad",
                                            "parameters": (Parameter("u_bounds_K", "K", 5.0, -5.0, 1.0, "x"),)}))
    with pytest.raises(ValueError, match="needs lower < upper"):
        register_term(type("Bad", (Term,), {"name": "u_nan_typical", "description": "bad",
                                            "parameters": (Parameter("u_nt_K", "K", 0.0, 5.0, np.nan, "x"),)}))
    assert "u_bounds" not in __import__("thermolimb.model", fromlist=["TERMS"]).TERMS


def test_a_terms_file_that_is_not_python_is_refused_before_it_runs(files, capsys):
    assert main(["fit", str(files / "run.csv"), "--terms", str(files / "run.csv")]) == 2
    err = capsys.readouterr().err
    assert "not a Python file (.py)" in err and len(err.strip().splitlines()) == 1


def teardown_module():
    from thermolimb.model import TERMS

    for name in [n for n in TERMS if n.startswith("u_")]:
        unregister_term(name)
