"""The model-versus-measurement loop on logs shaped like real ones: short, several runs, a second sensor.

Plants here are richer than the model (the default three-node X8 network, or a
two-mass network), with 0.05 K noise and 0.1 degC quantisation, so the model
is wrong from the start: these tests show robustness, not selection among
candidates that include the truth.
"""

import json
from dataclasses import replace

import numpy as np
import pytest

from thermolimb.cli.main import main
from thermolimb.effects.slow_masses import SecondNode
from thermolimb.model import ThermalModel
from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS
from thermolimb.workbench.diagnosis import auto_diagnose, diagnose
from thermolimb.workbench.diagnosis.candidates import Candidate
from thermolimb.workbench.diagnosis.judgement import refit_failure
from thermolimb.workbench.flags import parameter_flags, uncertainty_cause
from thermolimb.workbench.validation import Scheme, burn_in, fit_and_validate, validate_model

SENSOR = ["sensor_noise", "quantisation"]


def plant_log(profile, duration_s, dt_s, network="x8", seed=0, effects=(), **kw):
    fx = PlantEffects.from_names(SENSOR + list(effects))
    return simulate_profile(profile, duration_s, dt_s, list(CASE_NAMES[:2]), list(CASE_SPECS[:2]), fx, seed=seed,
                            network=NETWORKS[network], **kw).log


# ------------------------------------------------------------------ never fail on a readable log
# the two longest (20 s each on two cores) are slow, so that the default run stays well under ten minutes
SHORT = [("stairs", 30, 1.0), ("pulses", 30, 100.0), pytest.param("stairs", 200, 100.0, marks=pytest.mark.slow),
         pytest.param("pulses", 600, 1.0, marks=pytest.mark.slow), ("random", 60, 10.0)]
COMMANDS = [["fit"], ["compare", "--model", "joule", "--model", "joule,second_node"], ["diagnose"],
            ["diagnose", "--auto"], ["diagnose", "--cv", "3"]]


@pytest.mark.parametrize("profile, n, hz", SHORT)
def test_short_logs_never_fail_internally(tmp_path, capsys, profile, n, hz):
    """Every window, lag range and fold adapts to the log; what it cannot support is refused in one sentence."""
    path = plant_log(profile, (n - 1) / hz, 1.0 / hz, seed=n).write(tmp_path / "short.csv")
    for command in COMMANDS:
        code = main(command[:1] + [str(path), "--actuator", "knee", "--quiet"] + command[1:])
        err = capsys.readouterr().err.strip().splitlines()
        assert code in (0, 2), command
        if code == 2:
            assert len(err) == 1 and err[0].startswith("thermolimb"), err


def test_an_internal_error_is_not_reported_as_a_user_error(tmp_path, monkeypatch):
    path = plant_log("stairs", 120, 1.0).write(tmp_path / "log.csv")

    def broken(*args, **kwargs):
        raise ValueError("a bug in the suite")

    monkeypatch.setattr("thermolimb.cli.fit.validate_model", broken)
    with pytest.raises(ValueError, match="a bug in the suite"):
        main(["fit", str(path), "--actuator", "knee"])


def test_compare_fits_the_largest_submodel_the_log_identifies_and_says_what_it_set_aside(tmp_path, capsys):
    # current follows torque on this log: current heating cannot be told from Joule heating
    path = plant_log("pulses", 480, 1.0).write(tmp_path / "log.csv")
    code = main(["compare", str(path), "--actuator", "knee", "--json", "--model", "joule,second_node",
                 "--model", "joule,effort_bias,current_heating"])
    assert code == 0
    models = json.loads(capsys.readouterr().out)["models"]
    assert "rmse_K" in models[0]["validation"] and models[0]["set_aside"] == []
    assert "current_heating" not in models[1]["model"] and "joule" in models[1]["model"]
    [aside] = [a for a in models[1]["set_aside"] if a.get("term") == "current_heating"]
    assert "cannot" in aside["reason"] and "needs" in aside["reason"]


# ------------------------------------------------------------------ slow states, validated fairly
@pytest.fixture(scope="module")
def step_test():
    """A bench step test: 8 min at 1 Hz, three load pulses, a winding on a slower mass (two-mass plant)."""
    return plant_log("pulses", 480.0, 1.0, network="second_order", seed=1).series("knee")


def test_step_test_finds_the_second_mass_and_cuts_the_error_below_a_third(step_test):
    first, steps = auto_diagnose([step_test])
    assert "second_node" in steps[-1].model
    first_order = fit_and_validate([step_test], "joule")
    assert steps[-1].base.validation["rmse_K"] <= 0.3 * first_order.validation["rmse_K"]


def test_validation_carries_hidden_states_through_the_split(step_test):
    """Restarting at the split puts the slow mass at rest there, which it is not: the carried run is fairer."""
    model = "joule,second_node"
    carried = fit_and_validate([step_test], model)
    restarted = fit_and_validate([step_test], model, restart_at_split=True)
    assert carried.validation["rmse_K"] < restarted.validation["rmse_K"]
    assert "carried" in carried.scheme and "restarted" in restarted.scheme


def test_slow_mass_refits_start_from_the_log_time_scales(step_test):
    d = diagnose([step_test], model="joule", refit="all")
    cand = next(c for c in d.candidates if c.effect == "second_node")
    taus = sorted(point["frame_tau_s"] for point, _ in cand.scan)  # the score's scan, which the refit profiles
    assert taus[0] <= 0.25 * 480.0 and taus[-1] >= 480.0  # over the log's time scales and slower, not one guess
    assert cand.refitted and cand.failure is None
    assert 0.05 < cand.params["frame_fraction"]["value"] < 0.95


# ------------------------------------------------------------------ the search's decision pieces
def test_drop_rule_follows_held_out_error():
    def drop(improvement, delta_bic):
        return Candidate("effort_bias", ("joule",), kind="drop", rmse_K=1.0, improvement=improvement,
                         delta_bic=delta_bic, identifiable=True, plausible=True)

    assert drop(0.06, +50.0).helps  # held-out data rejects the term: it extrapolated badly
    assert not drop(0.02, +5.0).helps  # training prefers it and held-out barely differs: keep it
    assert drop(0.0, -3.0).helps  # simpler and no worse
    assert not drop(-0.01, -3.0).helps


def test_an_implausible_or_failed_candidate_is_never_recommended():
    good = dict(rmse_K=0.5, improvement=0.5, delta_bic=-100.0, identifiable=True)
    assert Candidate("x", ("joule", "x"), plausible=True, **good).eligible
    assert not Candidate("x", ("joule", "x"), plausible=False, **good).eligible
    assert not Candidate("x", ("joule", "x"), plausible=True, failure="collapsed", **good).eligible
    assert not Candidate("x", ("joule", "x"), plausible=True, confounded="moves with y", **good).eligible


def test_refit_failures_say_why():
    base = {"RC_s": 50.0, "T_offset_C": 25.0, "betaR_K_per_effort2": 0.1}
    assert "collapsed to frame_fraction = 0" in refit_failure(SecondNode, {**base, "frame_fraction": 0.0,
                                                                           "frame_tau_s": 300.0})
    assert "frame_tau_s ran to its bound" in refit_failure(SecondNode, {**base, "frame_fraction": 0.4,
                                                                        "frame_tau_s": 1e6})
    assert refit_failure(SecondNode, {**base, "frame_fraction": 0.4, "frame_tau_s": 300.0}) is None


def test_flags_name_vanishing_terms_far_offsets_and_unseen_time_constants(step_test):
    model = ThermalModel(("joule", "effort_bias"), {"RC_s": 1e6, "betaR_K_per_effort2": 0.0,
                                                    "beta_biasR_K_per_effort": 0.1, "T_offset_C": 200.0})
    flags = " | ".join(parameter_flags(model, {}, [step_test]))
    assert "betaR_K_per_effort2 vanishes" in flags
    assert "RC_s = 1e+06 s is 3x the log or longer" in flags
    assert "T_offset_C = 200.0 degC is" in flags


def test_a_large_relative_error_on_a_log_that_holds_what_it_needs_is_a_small_effect_s():
    """The README tour's log holds 14 effort levels and 6 transients each way: a bias of 0.0005 +- 0.0004 K/(N m)
    there is an effect too small to tell from none, not a want of three effort levels.  With its efforts made one-signed,
    a bias is not told apart so, and the want is said as before; a time constant is never called a small effect.  A
    value whose estimate moves with another's (|correlation| of 0.95 or more) names it."""
    log = plant_log("random", 3600.0, 1.0, effects=["speed_losses"]).series("knee")
    model = ThermalModel(("joule", "effort_bias"), {"RC_s": 60.0, "betaR_K_per_effort2": 0.2,
                                                    "beta_biasR_K_per_effort": 0.0005, "T_offset_C": 25.0})
    stderr = {"beta_biasR_K_per_effort": 0.0004, "RC_s": 40.0}
    flags = parameter_flags(model, stderr, [log])
    bias = next(f for f in flags if f.startswith("beta_biasR"))
    assert "too small an effect for this log to tell from none" in bias and "effort levels" in bias
    assert "so the log does not pin it down" in next(f for f in flags if f.startswith("RC_s"))
    # two estimates that move together: the flag names the partner, from the fit's covariance
    names = [q.name for q in model.parameters]
    sd = np.array([stderr.get(n, 0.1) for n in names])
    corr = np.eye(len(names))
    i, j = names.index("RC_s"), names.index("betaR_K_per_effort2")
    corr[i, j] = corr[j, i] = -0.98
    flags = parameter_flags(model, stderr, [log], covariance=corr * np.outer(sd, sd))
    assert "it trades with betaR_K_per_effort2 (correlation -0.980)" in next(f for f in flags if f.startswith("RC_s"))
    assert "too small an effect" in next(f for f in flags if f.startswith("beta_biasR"))  # its own partner is none
    one_signed = replace(log, signals=replace(log.signals, effort=np.abs(log.signals.effort)))
    bias = next(f for f in parameter_flags(model, stderr, [one_signed]) if f.startswith("beta_biasR"))
    assert "so the log does not pin it down (identifying it needs effort held at three" in bias


def test_a_flag_on_a_log_that_lacks_a_count_says_which_and_names_a_partner():
    """The BLDC bench's two heating runs (effort: the electrical power) hold twelve effort levels and no cooling
    transient: the default model's time constant lacks the cooling, said so (it was once told that its coefficients
    need three effort levels).  The offset is held where the winding started (the log only heats), and then the
    bias, linear in the electrical power, takes the heat: the Joule coefficient vanishes, said with what the log
    lacks, and the bias's error names it as its partner (before the hold both traded, +0.995, beside an offset
    of 180 degC)."""
    from thermolimb.data import REAL_LOGS
    from thermolimb.workbench.excitation import Excitation

    assert Excitation(2, 3, 0).lacking() == ["three effort levels (it holds 2)", "two cooling transients (it holds 0)"]
    runs = [r for log in REAL_LOGS["bldc"].read() for r in log.runs(log.actuators[0])]
    flags = diagnose(runs, stability=None).base.flags  # the default model, fitted as the diagnosis fits it
    rc = next(f for f in flags if f.startswith("RC_s"))
    assert rc.endswith("so the log does not pin it down: it lacks two cooling transients (it holds 0)")
    joule = next(f for f in flags if f.startswith("betaR_K_per_effort2"))
    assert "vanishes" in joule and joule.endswith("it lacks two cooling transients (it holds 0)")
    bias = next(f for f in flags if f.startswith("beta_biasR_K_per_effort"))
    assert "it trades with betaR_K_per_effort2 (correlation +0.9" in bias and "effort levels" not in bias


def test_the_readings_behind_a_flag_are_each_log_s_own_and_not_held():
    """The excitation and floor a flag's sentence cites are kept per log for the next fit of it, by weak reference:
    a second log gets its own, and a log no longer used is freed."""
    import gc
    import weakref

    log = plant_log("random", 3600.0, 1.0).series("knee")
    quiet = replace(log, temperature_C=np.round(log.temperature_C, 0))  # 1 degC steps: another floor
    loud = uncertainty_cause([log], 50.0)
    again = uncertainty_cause([log], 50.0)
    other = uncertainty_cause([quiet], 50.0)
    assert loud == again and other != loud and "floor of" in loud[0] and "floor of" in other[0]
    gone = weakref.ref(quiet)
    del quiet
    gc.collect()
    assert gone() is None


def test_effort_proportional_to_current_is_named_confounded_once_and_never_flips(step_test):
    first, steps = auto_diagnose([step_test])
    swap = [c for c in first.candidates if c.kind == "swap" and c.effect == "current_heating"]
    assert swap and all(c.confounded and "move together" in c.confounded for c in swap)
    assert all("current_heating" not in d.model for d in steps)
    labels = [c.label for d in steps[1:] for c in d.candidates]
    assert "current_heating for joule" not in labels  # not tried again once confounded


def test_candidates_are_listed_by_held_out_gain_and_the_first_is_the_recommendation(step_test):
    d = diagnose([step_test], model="joule")
    refitted = [c for c in d.candidates if c.refitted]
    eligible = [c for c in refitted if c.eligible]
    assert [c.improvement for c in eligible] == sorted((c.improvement for c in eligible), reverse=True)
    assert d.recommended is d.candidates[0]


# ------------------------------------------------------------------ several runs, several sensors
@pytest.fixture(scope="module")
def two_runs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("runs")
    return [plant_log("stairs", 600.0, 1.0, network="second_order", seed=s).write(folder / f"run{s}.csv")
            for s in (3, 4)]


def test_fit_on_one_run_validate_on_another(two_runs, capsys):
    assert main(["fit", str(two_runs[0]), "--actuator", "knee", "--model", "joule,second_node",
                 "--validate-on", str(two_runs[1]), "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["validation_scheme"].endswith("held-out runs")
    assert record["validation"]["rmse_K"] < 0.5


def test_leave_one_run_out(two_runs, capsys):
    assert main(["fit", *map(str, two_runs), "--actuator", "knee", "--model", "joule,second_node",
                 "--cv", "runs", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["validation_scheme"].startswith("leave one run out")
    assert main(["fit", str(two_runs[0]), "--actuator", "knee", "--cv", "runs"]) == 2
    assert "needs at least two runs" in capsys.readouterr().err


def test_wide_runs_of_one_actuator_fit_jointly(two_runs, tmp_path, capsys):
    wide = []
    for k, path in enumerate(two_runs):
        frame = __import__("pandas").read_csv(path)
        knee = frame[frame["actuator"] == "knee"].rename(columns={"time": "t", "effort": "torque",
                                                                  "temperature": "winding"})
        wide.append(tmp_path / f"bench{k}.csv")
        knee[["t", "torque", "winding"]].to_csv(wide[-1], index=False)
    assert main(["fit", *map(str, wide), "--map", "time=t,effort=torque,temperature=winding",
                 "--actuator", "knee", "--model", "joule,second_node", "--cv", "runs", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["actuator"] == "knee"


def test_a_housing_sensor_is_the_winding_boundary():
    """X8 plant with a housing thermistor: the search uses the measured housing instead of modelling masses."""
    log = simulate_profile("random", 3600.0, 1.0, list(CASE_NAMES[:2]), list(CASE_SPECS[:2]), PlantEffects.from_names(SENSOR),
                           seed=5, network=NETWORKS["x8"], housing_sensor=True).log
    first, steps = auto_diagnose([log.series("knee")])
    assert "housing_boundary" in steps[-1].model
    assert steps[-1].base.validation["rmse_K"] < 0.15
    gain = steps[-1].base.model.params["housing_gain"]
    assert 0.9 < gain < 1.1  # all the winding's heat leaves through the housing


def test_evaluate_with_held_out_runs_scores_only_those(step_test):
    other = plant_log("pulses", 480.0, 1.0, network="second_order", seed=2).series("knee")
    report = validate_model([step_test], "joule,second_node", Scheme.on_runs([other]))
    burn = burn_in(other)  # its first tenth places the hidden slow mass, and is not scored
    assert sum(s.measured_C.size for s in report.validation_segments) == other.n - burn
    np.testing.assert_allclose(report.validation_segments[0].measured_C, other.temperature_C[burn:])


def test_a_value_the_log_does_not_pin_down_is_flagged(step_test):
    """RC = 25 ± 19 s passed silently: a standard error over half the value is flagged, with what would identify it."""
    model = ThermalModel(("joule",), {"RC_s": 25.0, "betaR_K_per_effort2": 0.02, "T_offset_C": 25.0})
    flags = " | ".join(parameter_flags(model, {"RC_s": 19.0, "betaR_K_per_effort2": 0.001, "T_offset_C": 30.0},
                                       [step_test]))
    assert "RC_s = 25 ± 19 s: its standard error is 76 % of it" in flags
    assert "betaR_K_per_effort2" not in flags  # 5 %
    assert "T_offset_C" not in flags or "± 30" not in flags  # a temperature's relative error means nothing
