"""What the data can carry: the evidence every verdict states, and the largest sub-model a log identifies."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from conftest import first_order_log, first_order_truth

from thermolimb.cli.main import main
from thermolimb.data import WX200_BAG
from thermolimb.identification import IdentifiabilityError
from thermolimb.logs import read_log
from thermolimb.plant import X8_9, PlantEffects, simulate_profile
from thermolimb.util.numbers import significant
from thermolimb.workbench.evidence import MIN_SAMPLES_TO_RANK, THIN_SAMPLES, Evidence
from thermolimb.workbench.validation import Scheme, Segment, validate_model


def step_test(path, levels=(0.0, 15.0, 15.0, 0.0), duration_s=3600.0, dt_s=1.0, rc_s=600.0, beta_r=0.1,
              ambient=False, seed=0):
    """A first-order actuator driven through ``levels`` (N m) in equal parts, written with units in its header."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration_s, dt_s)
    effort = np.concatenate([np.full(len(part), level) for part, level in
                             zip(np.array_split(t, len(levels)), levels)])
    decay = np.exp(-dt_s / rc_s)
    winding = np.full(t.size, 25.0)
    for k in range(1, t.size):
        winding[k] = 25.0 + (winding[k - 1] - 25.0) * decay + (1 - decay) * beta_r * effort[k - 1] ** 2
    frame = pd.DataFrame({"time [s]": t, "actuator": "knee", "effort [N m]": effort,
                          "temperature [degC]": np.round(winding + rng.normal(0, 0.05, t.size), 1)})
    if ambient:
        frame["ambient [degC]"] = 25.0
    frame.to_csv(path, index=False)
    return path


def test_a_canonical_log_may_carry_units_in_its_header(tmp_path):
    log = read_log(step_test(tmp_path / "step.csv"))
    assert log.units["effort"] == "N m" and log.series("knee").n == 3600


def test_a_header_in_kelvin_or_milliseconds_is_converted_and_said(tmp_path):
    path = step_test(tmp_path / "step.csv")
    frame = pd.read_csv(path)
    frame = frame.rename(columns={"time [s]": "time [ms]", "temperature [degC]": "temperature [K]"})
    frame["time [ms]"] *= 1000.0
    frame["temperature [K]"] += 273.15
    frame.to_csv(path, index=False)
    log = read_log(path)
    series = log.series("knee")
    assert series.time_s[1] == pytest.approx(1.0) and 20.0 < series.temperature_C.min() < 30.0
    assert any("converted to s" in n for n in log.notes) and any("converted to degC" in n for n in log.notes)


@pytest.mark.parametrize("header", ["temperature [degF]", "temperature (°F)", "temperature (ºF)", "temperature [F]"])
def test_a_header_in_fahrenheit_is_converted_and_said(tmp_path, header):
    """A thrust stand's 'Temp (ºF)' (an ordinal sign, not a degree sign) and its kin."""
    path = step_test(tmp_path / "step.csv")
    frame = pd.read_csv(path)
    celsius = frame["temperature [degC]"].to_numpy()
    frame = frame.rename(columns={"temperature [degC]": header})
    frame[header] = celsius * 1.8 + 32.0
    frame.to_csv(path, index=False, encoding="utf-8")
    log = read_log(path)
    got = log.series("knee").temperature_C
    assert np.allclose(got, celsius[frame["actuator"].to_numpy() == "knee"][: got.size], atol=1e-9)
    assert any("degrees Fahrenheit" in n and "converted to degC" in n for n in log.notes), log.notes


def test_a_mapped_column_named_in_fahrenheit_without_a_unit_is_refused_and_inspect_suggests_degf(tmp_path, capsys):
    """'motor_temp_F' logged in degF with no header unit: 68-250 degF would pass for degC, so the mapping must say
    which; inspect's suggestion says degF, and the log read so holds degrees Celsius."""
    path = step_test(tmp_path / "step.csv")
    frame = pd.read_csv(path)
    frame = frame[frame["actuator"] == "knee"].drop(columns="actuator")
    celsius = frame.pop("temperature [degC]").to_numpy()
    frame["motor_temp_F"] = celsius * 1.8 + 32.0
    frame.rename(columns={"time [s]": "t", "effort [N m]": "tau"}).to_csv(path, index=False)
    assert main(["fit", str(path), "--map", "time=t,effort=tau,temperature=motor_temp_F", "--actuator", "k"]) == 2
    err = capsys.readouterr().err
    assert "may say degrees Fahrenheit" in err and "temperature=motor_temp_F:degF" in err
    assert main(["inspect", str(path), "--json"]) == 0
    suggested = json.loads(capsys.readouterr().out)["suggested_map"]
    assert suggested["temperature"] == "motor_temp_F:degF"
    log = read_log(path, mapping={"time": "t", "effort": "tau", "temperature": suggested["temperature"]},
                   actuator_name="k")
    assert np.allclose(log.series("k").temperature_C, celsius, atol=1e-9)
    assert main(["fit", str(path), "--map", "time=t,effort=tau,temperature=motor_temp_F:degC", "--actuator", "k",
                 "--quiet"]) == 0  # a user who knows it is Celsius says so


def test_a_step_test_sets_the_bias_aside_and_identifies_joule_heating(tmp_path, capsys):
    """Effort at two levels cannot tell a bias from Joule heating: the bias goes, βR is found within 2 %."""
    path = step_test(tmp_path / "step.csv")
    assert main(["fit", str(path), "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["model"] == ["joule"]
    assert [a["term"] for a in record["set_aside"]] == ["effort_bias"]
    assert "three or more distinct levels" in record["set_aside"][0]["reason"]
    assert record["params"]["betaR_K_per_effort2"]["value"] == pytest.approx(0.1, rel=0.02)
    assert record["params"]["RC_s"]["value"] == pytest.approx(600.0, rel=0.02)
    for command in (["compare"], ["diagnose"], ["diagnose", "--auto"], ["fit", "--fleet"]):
        assert main([command[0], str(path), *command[1:]]) == 0, command
        assert "set aside: effort_bias" in capsys.readouterr().out or command == ["fit", "--fleet"]


@pytest.fixture(scope="module")
def steady_squat():
    """120 s at 50 Hz of squatting (effort never low) on the plant, with its ambient channel."""
    return simulate_profile("squat", 120.0, 0.02, ["knee"], [X8_9],
                            PlantEffects.from_names(["sensor_noise", "quantisation"]), seed=0).log


def test_an_offset_the_log_cannot_tell_from_heating_is_held_at_the_logged_ambient(steady_squat, tmp_path, capsys):
    """Fitted on its first 70 %, where the effort never drops low (interleaved blocks would reach the lower
    efforts of its end)."""
    with pytest.raises(IdentifiabilityError, match="T_offset_C"):
        validate_model(steady_squat.runs("knee"), "joule,effort_bias", Scheme.at_split(0.7))
    path = steady_squat.write(tmp_path / "squat.csv")
    assert main(["fit", str(path), "--split", "0.7", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    [held] = [a for a in record["set_aside"] if a.get("parameter") == "T_offset_C"]
    assert held["held_at"] == pytest.approx(25.0) and "periods at low effort" in held["reason"]
    assert record["params"]["T_offset_C"] == {"value": held["held_at"], "stderr": 0.0, "unit": "degC"}
    assert main(["diagnose", str(path), "--split", "0.7"]) == 0
    assert "held: T_offset_C = 25.00 degC" in capsys.readouterr().out


def test_a_time_constant_the_log_leaves_loose_is_held_at_its_datasheet_value():
    """15 s of a plant whose winding takes 80 s: the fitted RC is 93 ± 114 s and βR 0.26 ± 0.30. Held at the
    datasheet's RC (said, with the reason), βR comes within 10 % of the truth with a fifth of the error."""
    truth = first_order_truth()
    series = first_order_log(0, duration_s=15.0, dt_s=0.1).runs("knee")
    split = Scheme.at_split(0.7)  # the first 10.5 s fitted on
    free = validate_model(series, "joule,effort_bias", split, reduce=True)
    held = validate_model(series, "joule,effort_bias", split, reduce=True, datasheet={"RC_s": truth["RC_s"]})
    assert any(f.startswith("RC_s = ") for f in free.flags)  # loose without the datasheet
    assert held.held["RC_s"] == truth["RC_s"] and held.stderr["RC_s"] == 0.0
    entry = next(a for a in held.set_aside if a.get("parameter") == "RC_s")
    assert entry["unit"] == "s" and "datasheet" in entry["reason"] and "loose" in entry["reason"]
    assert not any(f.startswith("RC_s = ") for f in held.flags)  # a held value is not judged as a fitted one
    beta = "betaR_K_per_effort2"
    assert held.model.params[beta] == pytest.approx(truth[beta], rel=0.1)
    assert held.stderr[beta] < 0.2 * free.stderr[beta]


def test_a_datasheet_value_is_used_only_where_the_log_needs_it(plant_log):
    """On two hours of the plant the log identifies RC itself: a (wrong) datasheet value changes nothing."""
    series = plant_log.runs("knee")
    free = validate_model(series, "joule,effort_bias", reduce=True)
    given = validate_model(series, "joule,effort_bias", reduce=True, datasheet={"RC_s": 3 * free.model.params["RC_s"]})
    assert given.set_aside == () and given.model.params == free.model.params


def test_a_log_at_one_effort_level_identifies_nothing_and_says_what_would(tmp_path):
    """Effort held at one level: heating cannot be told from the offset, and there is no ambient to hold it at."""
    path = step_test(tmp_path / "flat.csv", levels=(15.0,))
    with pytest.raises(IdentifiabilityError, match="a log needs"):
        validate_model(read_log(path).runs("knee"), "joule,effort_bias", reduce=True)


def _segment(n, span_s, values=None):
    t = np.linspace(0.0, span_s, n)
    y = np.arange(n, dtype=float) if values is None else values
    return Segment(t, y, y, np.zeros(n))


@pytest.mark.parametrize("n, span_s, rc_s, verdict", [
    (MIN_SAMPLES_TO_RANK - 1, 1000.0, 10.0, "too thin"),
    (THIN_SAMPLES - 1, 1000.0, 10.0, "thin"),
    (500, 5.0, 10.0, "thin"),
    (500, 1000.0, 10.0, "enough"),
])
def test_evidence_verdicts_follow_their_stated_thresholds(n, span_s, rc_s, verdict):
    evidence = Evidence.of([_segment(n, span_s)], rc_s)
    assert evidence.verdict == verdict
    sentence = evidence.sentence()
    assert sentence.startswith(f"evidence: {n} validation samples over {significant(span_s, 3)} s")
    assert ("too thin" in sentence) == (verdict == "too thin") and ("thin (" in sentence) == (verdict == "thin")


def test_compare_refuses_to_rank_on_a_handful_of_held_out_readings(capsys):
    """The WidowX bag: 6 held-out temperature readings; the two models are listed, not ranked."""
    path = WX200_BAG.paths[0]
    assert main(["compare", str(path), "--actuator", "waist", "--model", "joule,effort_bias", "--model", "joule",
                 "--json"]) == 0
    ranking = json.loads(capsys.readouterr().out)["ranking"]
    assert ranking["best"] is None and ranking["verdict"] == "too thin"
    assert ranking["evidence"]["validation_samples"] < MIN_SAMPLES_TO_RANK
    assert main(["compare", str(path), "--actuator", "waist", "--model", "joule,effort_bias", "--model", "joule"]) == 0
    assert "not ranked: evidence: " in capsys.readouterr().out


def test_compare_ranks_with_enough_evidence():
    run = simulate_profile("random", 1800.0, 1.0, ["knee"], [X8_9], PlantEffects.from_names(["sensor_noise"]),
                           seed=2)
    from thermolimb.workbench.compare import compare_models, rank_models

    fitted = compare_models(run.log.runs("knee"), [("joule",), ("joule", "second_node")])
    ranking = rank_models(fitted)
    best = min(fitted, key=lambda x: x[0].validation["rmse_K"])[0]
    assert ranking["best"] == list(best.model.terms) and ranking["verdict"] in ("enough", "thin")
    assert ranking["sentence"].startswith(f"lowest held-out RMSE: {','.join(best.model.terms)}")
