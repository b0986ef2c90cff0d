"""A model file is data, checked on load as a log is: units read (converted or refused), values within what they
can be, a covariance that is one; loading one never runs code; its standard errors do not depend on the unit the
effort was logged in."""

import json
import warnings

import numpy as np
import pandas as pd
import pytest

from thermolimb.cli.main import main
from thermolimb.identification import FreeRunLeastSquares
from thermolimb.logs import read_log
from thermolimb.model import ThermalModel, load_model
from thermolimb.model.generated import Feature, Spec, define
from thermolimb.model.saved import ModelFile, ModelFileError
from thermolimb.model.terms import TERMS
from thermolimb.util.errors import ModelSpecError


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """A 30-minute simulated log and the model ``fit --save`` wrote from it."""
    folder = tmp_path_factory.mktemp("model_file")
    log, model = folder / "log.csv", folder / "m.json"
    assert main(["simulate", "--profile", "random", "--duration", "1800", "--dt", "1", "--network", "first_order",
                 "--seed", "2", "--out", str(log), "--quiet"]) == 0
    assert main(["fit", str(log), "--actuator", "knee", "--save", str(model), "--limit-C", "90", "--quiet"]) == 0
    return log, model


def edited(model, tmp_path, edit):
    document = json.loads(model.read_text())
    edit(document["actuators"][0], document)
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(document))
    return path


def param(name, **fields):
    return lambda entry, _: entry["params"][name].update(fields)


@pytest.mark.parametrize("edit, message", [
    (param("RC_s", value=1e-9), "RC_s = 1e-09 s is outside what it can be"),
    (param("RC_s", value=1e12), "RC_s = 1e+12 s is no actuator's time constant"),
    (param("betaR_K_per_effort2", value=-0.2), "betaR_K_per_effort2 = -0.2 K/(N m)^2 is outside what it can be"),
    (param("RC_s", unit="fortnight"), "RC_s is in 'fortnight' where its log's channels make it 's'"),
    (param("betaR_K_per_effort2", unit="K/(mA)^2"), "is in 'K/(mA)^2' where its log's channels make it 'K/(N m)^2'"),
    (param("RC_s", stderr=-1.0), "RC_s's standard error is negative"),
    (param("RC_s", value=float("nan")), "RC_s needs a finite value"),
    (lambda e, _: e["params"].update(extra_K={"value": 1.0, "stderr": 0.0, "unit": "K"}),
     "parameter 'extra_K' is not one of model"),
    (lambda e, d: d["actuators"].append(dict(e)), "actuator 'knee' is in the file twice"),
    (lambda e, _: e["covariance"]["matrix"][0].__setitem__(0, -1.0), "is not a covariance"),
    (lambda e, _: e["covariance"]["matrix"][0].__setitem__(1, 5.0), "not symmetric"),
    (lambda e, _: e.update(term_sources={"evil": "open('pwned', 'w')"}), "thermolimb never runs code from one"),
    (lambda e, _: e.update(generated_terms={"joule": {}}), "a generated term needs name"),
    (lambda e, _: e["provenance"]["ranges"].update(offset_air_C=[30, "x"]), '"offset_air_C" must be [low, high]'),
    (lambda e, _: e["provenance"]["ranges"].update(ambient_C=[40.0, 20.0]), '"ambient_C" must be [low, high]'),
    (lambda e, _: e.update(limit_C=1e9), '"limit_C" must be a number of degC between -60 and 400'),
    (param("betaR_K_per_effort2", value=1e308), "is no actuator's (more than 1e+09 times its typical size"),
    (lambda e, _: e["validation"].update(rmse_K=-1.0), '"validation" rmse_K is -1.0; an error in K is zero or more'),
])
def test_a_hand_edited_model_file_is_refused_in_one_sentence(fitted, tmp_path, capsys, edit, message):
    bad = edited(fitted[1], tmp_path, edit)
    with pytest.raises(ModelFileError) as caught:
        ModelFile.load(bad)
    assert message in str(caught.value)
    capsys.readouterr()
    assert main(["predict", str(bad), "--hold", "10", "--duration", "60", "--start-C", "30"]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_a_unit_the_suite_knows_is_converted_and_said(fitted, tmp_path, capsys):
    original = ModelFile.load(fitted[1])["knee"]
    rc = original.model.params["RC_s"]

    def in_minutes_and_kelvin(entry, _):
        entry["params"]["RC_s"].update(value=rc / 60.0, stderr=entry["params"]["RC_s"]["stderr"] / 60.0, unit="min")
        entry["params"]["T_offset_C"].update(value=entry["params"]["T_offset_C"]["value"] + 273.15, unit="K")

    path = edited(fitted[1], tmp_path, in_minutes_and_kelvin)
    loaded = ModelFile.load(path)
    assert loaded["knee"].model.params["RC_s"] == pytest.approx(rc, rel=1e-12)
    assert loaded["knee"].stderr["RC_s"] == pytest.approx(original.stderr["RC_s"], rel=1e-12)
    assert loaded["knee"].model.params["T_offset_C"] == pytest.approx(original.model.params["T_offset_C"], abs=1e-9)
    assert any("RC_s saved in min, converted to s" in n for n in loaded.notes)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_model(path)
    assert any("converted to degC" in str(w.message) for w in caught)
    assert main(["predict", str(path), "--hold", "10", "--duration", "60", "--start-C", "30", "--quiet"]) == 0
    assert "note:" in capsys.readouterr().err


def test_a_limit_below_the_calibration_log_s_own_readings_is_said(fitted, tmp_path):
    path = edited(fitted[1], tmp_path, lambda e, _: e.update(limit_C=30.0))
    notes = ModelFile.load(path).notes
    assert len(notes) == 1 and "below the" in notes[0] and "check the limit" in notes[0]


def test_loading_a_model_file_never_runs_code(fitted, tmp_path, monkeypatch):
    """A file carrying Python source (as files of an earlier version did) is refused before anything runs: the
    source would have written a file."""
    monkeypatch.chdir(tmp_path)
    witness = tmp_path / "witness.txt"
    source = f"open({str(witness)!r}, 'w').write('ran')\nfrom thermolimb.model.terms import Term\n"

    def with_source(entry, document):
        document["version"] = 1
        entry["term_sources"] = {"joule": source}

    path = edited(fitted[1], tmp_path, with_source)
    with pytest.raises(ModelFileError, match="never runs code"):
        ModelFile.load(path)
    assert main(["predict", str(path), "--hold", "10", "--duration", "60", "--start-C", "30"]) == 2
    assert not witness.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["edited.json"]


def test_a_generated_term_travels_as_data(fitted, tmp_path):
    """A discovered form is saved as its features and rebuilt by the suite's own library on load."""
    spec = Spec("discovered_test_velocity", "heat from |velocity|^1.5", ("velocity",),
                (Feature("discovered_test_velocity_c0", "K/({velocity})^1.5", "velocity", "abs_power", "|v|^1.5",
                         "|velocity| to the power 1.5", power=1.5, lower=0.0, typical=0.01),))
    define(spec)
    log = read_log(fitted[0])
    series = log.runs("knee")
    est = FreeRunLeastSquares(model=("joule", "discovered_test_velocity")).fit(series)
    from thermolimb.model.saved import SavedModel
    saved = SavedModel("knee", est.model_, est.stderr_, est.covariance_, None,
                       {p.name: p.unit_in(None) for p in est.model_.parameters}, {}, {}, None,
                       {"files": [], "runs": 1, "samples": 10}, generated={spec.name: spec.to_json()})
    path = ModelFile({"knee": saved}).save(tmp_path / "g.json")
    text = path.read_text()
    assert "import" not in text and "def " not in text
    del TERMS[spec.name]
    loaded = ModelFile.load(path)["knee"].model
    assert np.array_equal(loaded.free_run(series[0]), est.model_.free_run(series[0]))


def test_a_generated_term_on_a_slow_mass_s_conductance_travels_as_data_and_names_a_real_mass(fitted, tmp_path):
    log = read_log(fitted[0])
    series = log.runs("knee")
    spec = Spec("test_housing_flow", "the second mass's conductance grows with |velocity|", ("velocity",),
                (Feature("test_housing_flow_per_rad_s", "1/({velocity})", "velocity", "abs_power", "|v| on second_node",
                         "|velocity| on the second mass", lower=-5.0, upper=5.0, typical=0.5),),
                airflow_on="second_node")
    define(spec)
    model = ThermalModel(("joule", "second_node", "test_housing_flow"),
                         {"RC_s": 40.0, "betaR_K_per_effort2": 0.3, "frame_fraction": 0.6, "frame_tau_s": 900.0,
                          "test_housing_flow_per_rad_s": 0.8, "T_offset_C": 25.0})
    still = model.with_params({**model.params, "test_housing_flow_per_rad_s": 0.0})
    plain = ThermalModel(("joule", "second_node"), {k: v for k, v in still.params.items() if "flow" not in k})
    assert np.array_equal(still.free_run(series[0]), plain.free_run(series[0]))  # no flow: the mass as it was
    before = model.free_run(series[0])
    assert not np.allclose(before, plain.free_run(series[0]))
    # beyond the range it was fitted on a channel may drive 1 + h x below zero: the mass keeps a sliver of its
    # conductance (a --discover walk on the PMSM bench crashed in first_order_scan before)
    beyond = model.with_params({**model.params, "test_housing_flow_per_rad_s": -5.0})
    assert np.isfinite(beyond.free_run(series[0])).all()
    record = json.loads(json.dumps(spec.to_json()))
    assert Spec.from_json(record, "here") == spec
    del TERMS[spec.name]
    define(Spec.from_json(record, "here"))  # as a model file's generated terms are rebuilt on load
    assert np.array_equal(model.free_run(series[0]), before)
    with pytest.raises(ModelSpecError, match="changes the conductance of 'joule'; expected one of the slow masses"):
        Spec.from_json({**record, "airflow_on": "joule"}, "here")
    del TERMS[spec.name]


def test_standard_errors_do_not_depend_on_the_unit_the_effort_is_logged_in(fitted, tmp_path):
    """The same log with its effort in N m, mA and uA: the time constant's standard error is the same, and a heat
    gain's scales with the unit (a plain pseudo-inverse of the Gram matrix cut them to 1e-13 s and 0)."""
    frame = pd.read_csv(fitted[0])
    results = []
    for factor in (1.0, 1e3, 1e6):
        scaled = frame.assign(effort=frame["effort"] * factor)
        path = tmp_path / f"effort_{factor:g}.csv"
        scaled.to_csv(path, index=False)
        est = FreeRunLeastSquares().fit(read_log(path).runs("knee"))
        results.append((factor, est.stderr_))
    base = results[0][1]
    for factor, stderr in results[1:]:
        assert stderr["RC_s"] == pytest.approx(base["RC_s"], rel=1e-3)
        assert stderr["T_offset_C"] == pytest.approx(base["T_offset_C"], rel=1e-3)
        assert stderr["betaR_K_per_effort2"] * factor**2 == pytest.approx(base["betaR_K_per_effort2"], rel=1e-3)


@pytest.mark.parametrize("text, message", [
    ("[" * 100_000 + "]" * 100_000, "nested deeper than Python reads"),
    ('{"format": ' + "9" * 5001 + "}", "holds a number too long to read"),
])
def test_a_model_file_too_deep_or_with_too_long_a_number_is_one_sentence(tmp_path, text, message, capsys):
    path = tmp_path / "odd.json"
    path.write_text(text)
    with pytest.raises(ModelFileError, match=message):
        ModelFile.load(path)
    assert main(["predict", str(path), "--hold", "10", "--duration", "60", "--start-C", "30"]) == 2
    assert message in capsys.readouterr().err


def test_a_model_file_without_the_ranges_of_its_log_says_its_extrapolation_cannot_be_checked(fitted, tmp_path):
    bad = edited(fitted[1], tmp_path, lambda e, _: e.update(provenance={}))
    assert any("holds no ranges of the log it was fitted on" in n for n in ModelFile.load(bad).notes)


def test_a_model_without_standard_errors_says_its_interval_is_the_model_error_alone(fitted, tmp_path, capsys):
    def no_errors(entry, _):
        for record in entry["params"].values():
            record["stderr"] = 0.0
        size = len(entry["covariance"]["matrix"])
        entry["covariance"]["matrix"] = [[0.0] * size for _ in range(size)]
        entry["jackknife"] = None

    bad = edited(fitted[1], tmp_path, no_errors)
    assert main(["predict", str(bad), "--hold", "20", "--duration", "600", "--start-C", "30"]) == 0
    assert "holds no standard errors: the interval is the model's held-out error alone" in capsys.readouterr().out
