"""Proof on data with hidden effects: the plant hides one physical effect, diagnose must name it.

Each log: 2 h at 1 Hz, three actuators (knee X8-9, hip X8-16, ankle X8-9), 0.05 K noise, 0.1 degC
quantisation, a first-order plant (so the base model is exact without the hidden effect), except for
``second_node`` (a two-mass plant).  The copper temperature coefficient is only visible when the
actuators run hot, so its logs carry a 1.8x heavier load (windings reach 80-120 degC).
"""

import json
from dataclasses import replace

import numpy as np
import pytest

from thermolimb.cli.main import main
from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS, HIDDEN_CASES
from thermolimb.workbench.diagnosis import auto_diagnose, diagnose

SENSOR = ["sensor_noise", "quantisation"]
HIDDEN = {  # model term -> (plant effect, network, load scale)
    "winding_tempco": ("winding_tempco", "first_order", 1.8),
    "speed_losses": ("speed_losses", "first_order", 1.0),
    "current_heating": ("field_weakening", "first_order", 1.0),
    "neighbor_coupling": ("neighbor_coupling", "first_order", 1.0),
    "ambient_variation": ("ambient_variation", "first_order", 1.0),
    "motion_cooling": ("motion_cooling", "first_order", 1.0),
    "second_node": (None, "second_order", 1.0),
    "sensor_lag": ("sensor_lag", "first_order", 1.0),
}


def hidden_log(effects, network="first_order", load_scale=1.0, seed=0, profile="random"):
    fx = PlantEffects.from_names(SENSOR + [e for e in effects if e])
    return simulate_profile(profile, 2 * 3600.0, 1.0, list(CASE_NAMES), list(CASE_SPECS), fx,
                            seed=seed, network=NETWORKS[network], load_scale=load_scale).log


def check_hidden(term, seed, actuator, profile="random"):
    effect, network, scale = HIDDEN[term]
    d = diagnose([hidden_log([effect], network, scale, seed, profile).series(actuator)])
    if term == "current_heating" and d.heat_source is not None:
        # a log with both channels: heat from the current is chosen before any term is added, on held-out data
        h = d.heat_source
        assert h["chosen"] == "current" and "current_heating" in d.model, h
        assert h["current_rmse_K"] <= 0.5 * h["effort_rmse_K"], h
        return d
    assert d.recommended is not None and d.recommended.effect == term, [c.effect for c in d.candidates]
    assert d.candidates[0].effect == term
    # adding the hidden effect at least halves the validation error
    assert d.recommended.improvement >= 0.5, d.recommended.improvement
    # the share of the residual an added term explains (it ranks what is refitted) is a share
    assert all(0.0 <= c.partial_r2 <= 1.0 for c in d.candidates if c.kind == "add"), [c.partial_r2 for c in d.candidates]
    assert d.recommended.kind != "add" or d.recommended.partial_r2 > 0.0  # a swap is not scored
    return d


@pytest.mark.parametrize("term", sorted(HIDDEN))
def test_hidden_effect_is_ranked_first_and_halves_the_error(term):
    check_hidden(term, seed=0, actuator="knee")


@pytest.mark.slow
@pytest.mark.parametrize("term", sorted(HIDDEN))
@pytest.mark.parametrize("seed, actuator", [(1, "hip"), (2, "ankle")])
def test_hidden_effect_over_seeds_and_actuators(term, seed, actuator):
    check_hidden(term, seed, actuator)


@pytest.mark.parametrize("seed", [0, 1])
def test_no_hidden_effect_adds_nothing(seed):
    """The plant has no effort bias: dropping that term may be recommended, adding anything may not."""
    d = diagnose([hidden_log([], seed=seed).series("hip")])
    assert d.recommended is None or d.recommended.label == "- effort_bias", d.recommended


def test_auto_finds_two_hidden_effects():
    log = hidden_log(["speed_losses", "neighbor_coupling"])
    first, steps = auto_diagnose([log.series("hip")])
    added = {t for s in steps[1:] for t in s.model} - set(steps[0].model)
    assert added == {"speed_losses", "neighbor_coupling"}
    assert steps[-1].recommended is None
    rmse = [s["rmse_K"] for s in first.auto]
    assert rmse == sorted(rmse, reverse=True) and rmse[-1] < 0.1  # down to the sensor noise


def test_diagnose_json_schema(tmp_path, capsys):
    path = hidden_log(["speed_losses"]).write(tmp_path / "log.csv")
    assert main(["diagnose", str(path), "--actuator", "knee", "--json", "--auto", "--plot", str(tmp_path)]) == 0
    d = json.loads(capsys.readouterr().out)
    assert {"actuator", "model", "base", "candidates", "recommended", "auto"} <= set(d)
    assert set(d["base"]) >= {"rmse_K", "max_abs_K", "fit_percent", "bic"}
    for c in d["candidates"]:
        assert {"effect", "rmse_K", "fit_percent", "improvement", "delta_bic", "params", "identifiable",
                "evidence"} <= set(c)
        assert isinstance(c["evidence"], str) and c["evidence"].endswith(".") and len(c["evidence"]) > 20, c
    refitted = [c for c in d["candidates"] if c["rmse_K"] is not None and c["plausible"]]
    assert [c["rmse_K"] for c in refitted] == sorted(c["rmse_K"] for c in refitted)  # best plausible first
    assert d["recommended"] == "speed_losses"
    assert d["auto"][0]["model"] == ["joule", "effort_bias"] and d["auto"][1]["change"] == "+ speed_losses"
    assert all(step["change"].startswith("- ") for step in d["auto"][2:])  # then, at most, terms the plant lacks go
    assert {p.name for p in tmp_path.glob("*.png")} >= {"residuals_knee.png", "candidates_knee.png",
                                                       "waterfall_knee.png"}


VISIBLE_ON = {  # profile -> hidden effects that still leave a trace the base model cannot absorb
    "walking": ["winding_tempco", "neighbor_coupling", "ambient_variation", "second_node", "sensor_lag"],
    "squat": ["winding_tempco", "ambient_variation", "second_node", "sensor_lag"],
}


@pytest.mark.slow
@pytest.mark.parametrize("profile, term", [(p, t) for p, terms in VISIBLE_ON.items() for t in terms])
def test_hidden_effect_on_other_profiles(profile, term):
    check_hidden(term, seed=3, actuator="hip", profile=profile)


@pytest.mark.slow
@pytest.mark.parametrize("term", ["speed_losses", "current_heating", "motion_cooling"])
def test_effects_that_move_with_effort_leave_nothing_to_find_on_squats(term):
    """On squats speed rises with load, so the effort terms absorb these effects: the base model is already
    at the sensor's noise floor and nothing is (rightly) added; dropping a term that does not help is allowed."""
    effect, network, scale = HIDDEN[term]
    d = diagnose([hidden_log([effect], network, scale, 3, "squat").series("hip")])
    assert d.base.validation["rmse_K"] < 0.07
    assert d.recommended is None or d.recommended.kind == "drop"


# ---------------------------------------------------------------- on the default three-node X8 network
# The model is wrong from the start here (one mass against three): the search has to find the slow masses as
# well as the hidden effect, from the default start (cases: thermolimb.plant.cases).
NOISE_FLOOR_K = 0.1  # 0.05 K noise and 0.1 degC steps validate at about 0.06 K


def x8_walk(case: str, seed: int):
    hidden = HIDDEN_CASES[case]
    first, steps = auto_diagnose([hidden.log(seed).series("knee")])
    return hidden, first, steps


# ambient variation's walk takes half a minute on two cores: slow, so that the default run stays well under ten minutes
@pytest.mark.parametrize("case", [pytest.param("ambient_variation", marks=pytest.mark.slow), "sensor_lag",
                                  "housing_sensor"])
def test_hidden_effect_found_on_the_x8_from_the_default_start(case):
    hidden, first, steps = x8_walk(case, seed=0)
    assert hidden.found_in(steps[-1].model), first.auto
    assert first.auto[-1]["rmse_K"] < 0.5 * first.auto[0]["rmse_K"]


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0])  # seed 0 finds 9 of 10, seed 1 8 (its copper refit is a local optimum)
def test_x8_hidden_effect_found_in_at_least_eight_of_ten_cases(seed):
    """The issue's target.  Every walk, found or not, must at least halve the validation error."""
    missed = []
    for case in HIDDEN_CASES:
        hidden, first, steps = x8_walk(case, seed)
        if not hidden.found_in(steps[-1].model):
            missed.append(case)
        assert first.auto[-1]["rmse_K"] < 0.5 * first.auto[0]["rmse_K"], (case, first.auto)
    assert len(HIDDEN_CASES) - len(missed) >= 8, missed


@pytest.mark.parametrize("seed", [0, 1])
def test_x8_with_nothing_hidden_adds_only_the_slow_masses(seed):
    _, first, steps = x8_walk("slow_masses", seed)
    assert set(steps[-1].model) <= {"joule", "effort_bias", "second_node", "third_node"}, first.auto
    assert steps[-1].base.validation["rmse_K"] < NOISE_FLOOR_K


@pytest.mark.parametrize("seed", [0, 1])
def test_airflow_on_the_housing_is_found_once_the_slow_mass_is_taken(seed):
    """A two-node plant (winding and a heavier housing) whose housing is cooled by airflow while moving: the
    winding's motion cooling cannot stand in for it, the housing's can, with the plant's gain (measured
    0.332 -> 0.089 K and 1.456 -> 0.061 K after the slow mass, seeds 0 and 1)."""
    fx = PlantEffects.from_names(SENSOR + ["motion_cooling"])
    log = simulate_profile("random", 3600.0, 0.5, ["knee"], [CASE_SPECS[0]], fx, seed=seed,
                           network=NETWORKS["second_order"]).log
    first, steps = auto_diagnose([log.series("knee")])
    walk = [s.get("change") for s in first.auto]
    assert "+ second_node" in walk and "+ housing_motion_cooling" in walk, first.auto
    after_mass = next(s["rmse_K"] for s in first.auto if s.get("change") == "+ second_node")
    assert first.auto[-1]["rmse_K"] < min(0.35 * after_mass, NOISE_FLOOR_K + 0.05), first.auto
    # the plant's gain, 0.6 per rad/s (measured 0.557 and 0.579)
    assert steps[-1].base.model.params["housing_cooling_per_rad_s"] == pytest.approx(0.6, rel=0.15)


def test_every_term_at_its_null_runs_as_the_base():
    """At its parameters' null an added term is absent: the score test reuses the base's free run for it."""
    import numpy as np

    from thermolimb.model.model import ThermalModel, model_parameters
    from thermolimb.model.signals import Signals
    from thermolimb.model.terms import TERMS

    rng = np.random.default_rng(3)
    n = 4000
    t = np.arange(n) * 0.5
    effort = np.cumsum(rng.normal(size=n)) * 0.05
    s = Signals(time_s=t, effort=effort, velocity=np.sin(t / 30.0) * 3.0, current_A=effort * 1.7,
                ambient_C=25.0 + np.sin(t / 900.0) * 3.0, neighbor_temperature_C=40.0 + rng.normal(size=(n, 2)),
                neighbor_names=("a", "b"), housing_C=30.0 + np.sin(t / 600.0), power_W=effort**2 * 4.0)
    checked = []
    for name, term in TERMS.items():
        base_terms = ("joule", "effort_bias") + tuple(term.requires)
        if name in base_terms or term.generated:  # a generated term (left by a discovery test) reads its log's extras
            continue
        base_values = {p.name: p.typical for p in model_parameters(base_terms)}
        base = ThermalModel(base_terms, base_values)
        values = {**base_values, **{p.name: p.null for p in term.parameters}}
        extended = ThermalModel(base_terms + (name,), values)
        np.testing.assert_allclose(extended.simulate(s, 31.0, initial_rate_K_per_s=0.01),
                                   base.simulate(s, 31.0, initial_rate_K_per_s=0.01), rtol=0, atol=1e-9,
                                   err_msg=name)
        checked.append(name)
    assert len(checked) >= 12, checked


@pytest.mark.parametrize("n, max_lag", [(10, 2), (10, 9), (1000, 250), (12345, 600), (5, 10)])
def test_cross_correlation_over_the_lags_asked_equals_the_full_correlation(n, max_lag):
    """The FFT over n + max_lag points (not 2n) gives the full correlation's values at every lag asked,
    zero beyond the series' length."""
    from scipy.signal import correlate

    from thermolimb.workbench.diagnosis.residuals import _normalised, cross_correlation

    rng = np.random.default_rng(n)
    x, y = rng.normal(size=n).cumsum(), rng.normal(size=n)
    full = correlate(_normalised(y), _normalised(x), mode="full", method="direct") / n
    lags, r = cross_correlation(x, y, max_lag)
    inside = np.abs(lags) <= n - 1
    assert np.allclose(r[inside], full[n - 1 + lags[inside]], atol=1e-12)
    assert np.all(r[~inside] == 0.0)

X8_9_SECOND_ORDER = replace(X8_9, network=NETWORKS["second_order"])  # a winding on a heavier housing


def test_friction_heat_in_the_housing_is_found_where_its_score_does_not_see_it():
    """The plant's speed losses put their friction into the housing and their iron losses into the winding. On a
    two-node plant that also hides copper's coefficient and a lagging thermistor (benchmarks/forecast.py's
    calibration), the walk takes speed losses and the slow mass, then moves the friction onto the mass: a change
    whose score test does not see it (p = 0.55: the winding's own speed term nearly spans it), refitted because
    it moves a heat the model has into a mass it has, which cuts the held-out error by 64 %. Its refit puts most
    of the plant's friction there (1.5 W per rad/s times the housing's 4 K/W: 6 K per rad/s) and the winding's
    speed term goes to zero."""
    fx = PlantEffects.from_names(SENSOR + ["speed_losses", "winding_tempco", "sensor_lag"])
    log = simulate_profile("random", 7200.0, 1.0, ["knee"], [X8_9_SECOND_ORDER], fx, seed=0).log
    first, steps = auto_diagnose([log.series("knee")], stability=None)
    walk = [s.get("change") for s in first.auto]
    assert walk.index("+ housing_friction") > walk.index("+ second_node"), first.auto
    taken = next(d.recommended for d in steps if d.recommended and d.recommended.effect == "housing_friction")
    assert taken.p_value > 0.01 and taken.improvement > 0.5, (taken.p_value, taken.improvement)
    p = steps[-1].base.model.params
    assert 4.5 < p["housing_speed_K_per_rad_s"] < 7.5 and p["speed_K_per_rad_s"] < 0.5, p
