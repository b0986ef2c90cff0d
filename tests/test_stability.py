"""Verdicts that hold (issue 37): refits that do not depend on where they start, stability over perturbed
replicates, the sensor's floor, and advice that names the real cause of large standard errors."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from thermolimb.cli.main import main
from thermolimb.data import REAL_LOGS
from thermolimb.plant import NETWORKS, PlantEffects, SpeedLosses, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS
from thermolimb.workbench import flags
from thermolimb.workbench.diagnosis import Search, diagnose
from thermolimb.workbench.diagnosis.refit import ordered_starts, refit
from thermolimb.workbench.diagnosis.replicate import replicate
from thermolimb.workbench.diagnosis.stability import Stability, perturbations, selection_frequencies
from thermolimb.workbench.floor import quantisation_step, sensor_floor
from thermolimb.workbench.validation import Scheme, validate_model


def plant(effects: str, seed: int = 0, duration_s: float = 3600.0, speed_scale: float | None = None):
    fx = PlantEffects.from_names(f"sensor_noise,quantisation{',' + effects if effects else ''}")
    if speed_scale is not None:
        fx = fx.replace(speed_losses=SpeedLosses(*(speed_scale * np.array(list(vars(SpeedLosses()).values())))))
    return simulate_profile("random", duration_s, 1.0, list(CASE_NAMES), list(CASE_SPECS), fx, seed=seed,
                            network=NETWORKS["first_order"]).log


@pytest.fixture(scope="module")
def speed_log():
    return plant("speed_losses")


@pytest.fixture(scope="module")
def step_test():
    """A bench step test: 8 min at 1 Hz, three load pulses, a winding on a slower mass (two-mass plant)."""
    fx = PlantEffects.from_names("sensor_noise,quantisation")
    return simulate_profile("pulses", 480.0, 1.0, list(CASE_NAMES[:2]), list(CASE_SPECS[:2]), fx, seed=1,
                            network=NETWORKS["second_order"]).log.series("knee")


def test_a_refit_ends_where_it_ends_whatever_start_the_screen_ranks_first(step_test):
    """The profile searches the slow mass's time constant over the log's time scales: the refit from the
    score's starts in any order, or from starts scaled by 0.5 and 2, ends within 1 % of the same error."""
    d = diagnose([step_test], model="joule", refit="all")
    cand = next(c for c in d.candidates if c.effect == "second_node")
    base = d.base
    ends = []
    for order in (lambda s: s, lambda s: s[::-1], lambda s: [{k: 0.5 * v for k, v in x.items()} for x in s],
                  lambda s: [{k: 2.0 * v for k, v in x.items()} for x in s]):
        trial = replace(cand, starts=order(list(cand.starts)), rmse_K=None, report=None)

        def evaluate(model, initial, fixed):
            return _evaluate(step_test, model, initial, fixed)

        trial = refit(trial, base, d.base_bic, evaluate)
        ends.append(trial.rmse_K)
    assert max(ends) <= 1.01 * min(ends), ends


def _evaluate(series, model, initial, fixed):
    from thermolimb.identification import FreeRunLeastSquares

    return validate_model([series], model, Scheme(),
                          make=lambda: FreeRunLeastSquares(model=model, initial=initial, max_nfev=12, fixed=fixed or None))


def test_the_profile_looks_slower_than_the_log_and_orders_by_training_error(step_test):
    d = diagnose([step_test], model="joule", refit="all")
    cand = next(c for c in d.candidates if c.effect == "second_node")
    ordered = ordered_starts(cand, d.base, list(d.base.train_series))
    costs = [cost for cost, _ in ordered]
    assert costs == sorted(costs) and len(ordered) >= 5
    assert max(start["frame_tau_s"] for _, start in ordered) >= step_test.duration_s


def test_perturbations_and_frequencies_are_the_same_for_a_seed_and_on_any_backend(speed_log):
    runs = speed_log.runs("knee")
    split = Scheme.at_split(0.7)
    a = perturbations(Stability(seed=3), runs, split)
    assert a == perturbations(Stability(seed=3), runs, split)
    assert a != perturbations(Stability(seed=4), runs, split)
    assert all(0 <= start <= 5 and 0 <= end <= 5 for p in a for start, end in p.trims)
    assert any(start > 0 for p in a for start, _ in p.trims)  # runs are cut at their start too
    assert all(abs(p.split - 0.7) <= 0.1 for p in a)
    assert min(p.split for p in a) < 0.66 and max(p.split for p in a) > 0.74  # stratified over the range
    blocks = perturbations(Stability(seed=3), runs, Scheme.interleaved())
    assert all(abs(p.phase) <= 0.5 for p in blocks) and min(p.phase for p in blocks) < -0.3 < 0.3 < max(
        p.phase for p in blocks)  # the held-out blocks moved by up to half a block
    d = diagnose(runs)
    serial, n, shared = selection_frequencies(d.candidates, d.recommended, d.model, d.base, runs,
                                              Search(stability=Stability(replicates=4, workers=1)))
    pooled, m, _ = selection_frequencies(d.candidates, d.recommended, d.model, d.base, runs,
                                         Search(stability=Stability(replicates=4, workers=2)))
    assert (serial, n) == (pooled, m) and serial["+ speed_losses"] == 1.0 and n == 4  # unanimous: no second batch
    far = next(c for c in shared if c.label == "- effort_bias")
    assert far.eligible and far.rmse_K > 2.0 * d.recommended.rmse_K  # eligible, and far behind the best: it could
    assert "- effort_bias" not in serial and far.selection_frequency is None  # not outrank it (stability.BEHIND)


def test_refits_on_two_workers_end_as_refits_here_bit_for_bit(step_test):
    """A diagnosis's refits go to the pool when one places a hidden state (here the second mass and the sensor's
    lag, on a log of 480 samples): every candidate ends as it does refitted in this process, to the bit."""
    runs = {w: diagnose([step_test], model="joule", refit="all", stability=Stability(replicates=2, workers=w))
            for w in (1, 2)}
    ends = {w: [(c.label, c.rmse_K, c.status, dict(c.params), c.evidence) for c in d.candidates]
            for w, d in runs.items()}
    assert ends[1] == ends[2]
    assert sum(c.refitted for c in runs[2].candidates) >= 3
    assert any(c.effect == "second_node" and c.refitted for c in runs[2].candidates)


def test_an_effect_on_the_edge_is_reported_unstable_not_recommended(monkeypatch):
    """The UR3's J2 (real): motion cooling passes every gate on the whole log and helps on both held-out runs, but
    the replicates do not all take it (measured: 9 of 10).  Asked for every replicate (min_frequency 1.0), it is
    shown with its frequency and not recommended; the default rule (0.8) would take it.  No pair is tried here
    (together.MEMBERS 0): with the sensor's lag, motion cooling is taken in 10 of 10 (tests/test_together.py)."""
    from thermolimb.workbench.diagnosis import together

    monkeypatch.setattr(together, "MEMBERS", 0)
    runs = REAL_LOGS["ur3"].read()[0].runs("J2")
    d = diagnose(runs, stability=Stability(replicates=10, min_frequency=1.0))
    edge = d.unstable
    assert edge is not None and edge.eligible and edge.selection_frequency < 1.0
    assert d.recommended is None and edge.status == "unstable"
    assert f"taken in {round(10 * edge.selection_frequency)} of 10 replicates" in edge.evidence.lower()
    assert "not recommended" in edge.evidence
    record = d.to_json()
    assert record["unstable"] == edge.label and record["recommended"] is None
    row = next(c for c in record["candidates"] if c["label"] == edge.label)
    assert row["selection_frequency"] == edge.selection_frequency and row["status"] == "unstable"


def test_where_the_replicates_overturn_the_whole_logs_best_change_the_change_they_take_is_recommended():
    """Stability selection keeps what most perturbed copies take: where the whole log's best change is taken in too
    few replicates and another eligible change in enough, that one is recommended (the most often taken, then the
    lower error); an implausible or harmful change is not, however often taken, and with none the walk stops."""
    from thermolimb.workbench.diagnosis.candidates import Candidate
    from thermolimb.workbench.diagnosis.stability import steadier

    def change(effect, rmse_K, share, kind="add", **kw):
        model = ("joule",) if kind == "drop" else ("joule", "effort_bias", effect)
        return Candidate(effect, model, kind=kind, rmse_K=rmse_K, improvement=1.0 - rmse_K / 5.808, delta_bic=-100.0,
                         **{"plausible": True, "identifiable": True, "selection_frequency": share, **kw})

    best = change("effort_bias", 4.545, 0.0, kind="drop")
    speed, lag = change("speed_losses", 4.605, 1.0), change("sensor_lag", 4.7, 0.8)
    odd, worse = change("winding_tempco", 4.0, 1.0, plausible=False), change("motion_cooling", 5.9, 1.0)
    assert steadier([best, lag, speed, odd, worse], best, Stability()) is speed
    assert steadier([best, lag], best, Stability()) is lag
    assert steadier([best, lag], best, Stability(min_frequency=0.9)) is None
    assert steadier([best, odd, worse], best, Stability()) is None


def test_the_floor_is_said_when_the_model_is_already_good(tmp_path, capsys):
    """A first-order plant with 0.1 degC steps and nothing hidden: the first-order model is already at the
    sensor's floor, so nothing is recommended, and the text and the JSON say why with the same numbers."""
    path = tmp_path / "good.csv"
    plant("").write(path)
    assert main(["diagnose", str(path), "--actuator", "knee", "--quiet", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    floor = record["floor"]
    assert floor["reached"] and record["recommended"] is None
    assert abs(floor["step_K"] - 0.1) < 1e-6
    assert "nothing more can be told apart here" in floor["sentence"]
    assert f"{record['base']['rmse_K']:.3f} K" in floor["sentence"] and f"{floor['floor_K']:.3f} K" in floor["sentence"]
    assert main(["diagnose", str(path), "--actuator", "knee", "--quiet"]) == 0
    text = capsys.readouterr().out  # the answer first, with the JSON's numbers
    assert text.startswith("knee: nothing to add to joule,effort_bias")
    assert f"next: none: {record['base']['rmse_K']:.3f} K is at the sensor's floor, a {floor['floor_K']:.3f} K" in text
    assert main(["diagnose", str(path), "--actuator", "knee", "--quiet", "--explain"]) == 0
    text = capsys.readouterr().out
    assert floor["sentence"] in text and "recommended: none (the model is already at the sensor's floor)" in text


def test_the_quantisation_step_is_read_from_the_readings():
    rng = np.random.default_rng(0)
    readings = np.round((30 + np.cumsum(rng.normal(0, 0.05, 2000))) * 16) / 16
    assert quantisation_step(readings) == pytest.approx(0.0625)
    assert quantisation_step(30 + np.cumsum(rng.normal(0, 0.05, 2000))) == 0.0


def test_large_standard_errors_name_the_missing_effect_not_the_excitation(tmp_path, capsys):
    """The README's tour log (ten effort levels, many transients, speed losses hidden): fit says the model misses
    something and to run diagnose; a two-level step test says what excitation it lacks, with its counts."""
    path = tmp_path / "run.csv"
    plant("speed_losses").write(path)
    assert main(["fit", str(path), "--actuator", "knee", "--json", "--quiet"]) == 0
    flags = json.loads(capsys.readouterr().out)["flags"]
    loose = [f for f in flags if "standard error is" in f]
    assert loose and all("the model misses something, not for lack of excitation" in f and "run diagnose" in f
                         for f in loose)
    # the text says the shared reason once, the parameters it holds for named in one line
    assert main(["fit", str(path), "--actuator", "knee", "--quiet"]) == 0
    text = capsys.readouterr().out
    assert text.count("the model misses something") == 1
    assert all(f.split(" = ")[0] in text.split("the model misses something")[0].splitlines()[-1] for f in loose)


def test_a_replicate_s_flags_start_as_said_and_leave_their_causes_unread(speed_log, monkeypatch):
    """A stability replicate says nothing, so its flags' causes (the log's excitation and sensor floor, read on each
    trimmed copy) are not worked out; what a flag starts with, which the datasheet's hold reads, is the same."""
    runs = speed_log.runs("knee")
    said = validate_model(runs, "joule,effort_bias", Scheme.at_split(0.7)).flags
    read = []
    monkeypatch.setattr(flags, "sensor_floor", lambda *a: read.append(a) or sensor_floor(*a))
    with flags.unread():
        unread = validate_model([r.slice(3, r.n) for r in runs], "joule,effort_bias", Scheme.at_split(0.7)).flags
    loose = [f for f in said if "standard error is" in f]
    assert loose and not read and len(unread) == len(said)
    assert [f.split(" = ")[0] for f in unread] == [f.split(" = ")[0] for f in said]  # the same values flagged
    assert all(f.endswith("(its cause not worked out)") for f in unread if "standard error is" in f)
    assert all("the model misses something" in f for f in loose)  # outside, the cause is worked out and said


def test_a_step_test_lacking_levels_is_told_so(step_test):
    report = validate_model([step_test], "joule,effort_bias", Scheme(), reduce=True)
    said = " ".join(report.flags) + " ".join(str(a) for a in report.set_aside)
    assert "misses something" not in said


@pytest.mark.slow  # 42 s: four walks with their stability checks on a real log
def test_a_real_log_trimmed_by_a_few_rows_gives_the_same_verdict():
    """The UR3's J5 (real): trimmed by up to 5 rows at either end, the search with stability recommends the same
    change (its neighbours' heat), taken in every replicate each time."""
    runs = REAL_LOGS["ur3"].read()[0].runs("J5")
    verdicts = set()
    for a, b in [(0, 0), (5, 0), (0, 5), (3, 2)]:
        d = diagnose([s.slice(a, s.n - b) for s in runs], stability=Stability(replicates=5))
        verdicts.add(d.recommended.label if d.recommended else None)
        assert d.recommended is None or d.recommended.selection_frequency >= 0.8
        # two masses at once, where refitted here, fit implausibly or fail: a failed repair, not re-judged by the
        # replicates (a single change implausible on the whole log still is: a replicate might find it plausible)
        by = {c.label: c for c in d.candidates}
        pair = by["+ second_node with third_node"]
        assert not pair.eligible and pair.selection_frequency is None  # implausible, failed or not refitted
        # the second mass alone: implausible, its held-out error over twice the neighbours' heat's: it cannot
        # outrank that change in a replicate, and is not re-judged (stability.BEHIND)
        mass = by["+ second_node"]
        assert not mass.eligible and mass.selection_frequency is None
    # (whether the pair and the mass are refitted on some copy, or only scored, moves with the OpenBLAS kernel --
    # OpenBLAS's Haswell kernel refits neither on these four copies -- and the verdict does not)
    assert verdicts == {"+ neighbor_coupling"}, verdicts


def test_sensor_floor_of_a_residual_is_its_noise():
    rng = np.random.default_rng(1)
    noise = rng.normal(0, 0.05, 5000)
    floor = sensor_floor([_Series(np.round((40 + noise) * 10) / 10)], [noise])
    assert floor.noise_K == pytest.approx(0.05, rel=0.1) and floor.step_K == pytest.approx(0.1)


class _Series:
    def __init__(self, temperature_C):
        self.temperature_C = temperature_C


def test_a_replicate_s_warm_refit_moved_past_the_plausible_share_returns_where_the_whole_log_s_ended():
    """A replicate refits a change from where the whole log's search ended, jittered.  On a log that shows only
    the start of a slow mass's rise (the X8's body over 2 h), a share and a time constant slower than the run
    traded along a valley, and a start moved past the share's plausible bound stayed there: only searching
    afresh, where the whole log's refit was plausible (``settled_plausible``), brought it back.  With the time
    constant kept within three runs (``identification.bounds``) the valley is closed: the warm refit from a share
    of 0.97 returns to the whole log's error either way."""
    from thermolimb.plant.cases import HIDDEN_CASES
    from thermolimb.workbench.diagnosis.refit import evaluate as evaluate_as_diagnose
    from thermolimb.workbench.diagnosis.split_or_blocks import judging_scheme

    series = HIDDEN_CASES["slow_masses"].log(1).series("knee")
    d = diagnose([series], stability=None)
    cand = next(c for c in d.candidates if c.effect == "second_node")
    assert cand.plausible, cand.report.model.params
    assert cand.report.model.params["frame_tau_s"] <= 3.0 * 0.7 * series.duration_s * (1 + 1e-6)
    warm = {**cand.report.model.params, "frame_fraction": 0.97}
    scheme = judging_scheme(Scheme(), [series])
    for settled in (False, True):
        trial = replace(cand, rmse_K=None, report=None, plausible=None, settled_plausible=settled)
        trial = refit(trial, d.base, d.base_bic,
                      lambda m, i, f: evaluate_as_diagnose([series], m, scheme, i, f), warm)
        assert trial.plausible and trial.rmse_K == pytest.approx(cand.rmse_K, rel=1e-3), settled


def test_a_count_on_the_threshold_is_settled_by_a_second_batch(monkeypatch):
    """The UR3's J2 (real): motion cooling is taken in 9 of the first 10 replicates.  Asked for 0.9, that count sits
    on the threshold, where one replicate's throw decides: 10 more are drawn afresh and the verdict rests on all 20
    (``stability.undecided``); asked for every replicate, 9 of 10 has failed already and no second batch runs.  No
    pair is tried (together.MEMBERS 0), whose own check would decide after it (tests/test_together.py)."""
    from thermolimb.workbench.diagnosis import together

    monkeypatch.setattr(together, "MEMBERS", 0)
    runs = REAL_LOGS["ur3"].read()[0].runs("J2")
    d = diagnose(runs, stability=Stability(replicates=10, min_frequency=0.9))
    c = next(c for c in d.candidates if c.label == "+ motion_cooling")
    assert d.stability["replicates"] == 20 and round(20 * c.selection_frequency) >= 17  # its 9 of 10, and more
    assert f"taken in {round(20 * c.selection_frequency)} of 20 replicates" in c.evidence.lower()
    assert "10 more, as the first 10 left the best change within one replicate of its share" in c.evidence
    assert (d.recommended is c) == (c.selection_frequency >= 0.9)


def test_a_replicate_whose_base_sets_a_term_aside_takes_no_change_built_on_it():
    """A replicate refits the whole log's model on its perturbed copy, and that fit may set aside a term the copy
    cannot identify; a contender built on the whole log's model (the term in it) is then another change, and the
    replicate takes none of it. It raised a ValueError from inside the worker (a walk on the plant's walking duty
    whose replicate's base lost speed losses)."""
    from thermolimb.logs import from_frame
    from thermolimb.workbench.diagnosis.candidates import Candidate

    log = simulate_profile("pulses", 1800.0, 1.0, list(CASE_NAMES[:2]), list(CASE_SPECS[:2]),
                           PlantEffects.realistic_sensor(), seed=4, network=NETWORKS["second_order"]).log
    frame = log.frame.copy()
    frame["velocity"] = 0.0  # motion cooling cannot be identified: the base fit sets it aside
    still = from_frame(frame).series("knee")
    assert validate_model([still], "joule,motion_cooling", reduce=True).model.terms == ("joule",)
    contender = Candidate("second_node", ("joule", "motion_cooling", "second_node"))
    assert replicate([still], ("joule", "motion_cooling"), Search(), None, [contender.spec()], [{}]) is None


def test_a_replicate_s_fits_compare_fewer_samples_and_validate_at_the_full_rate(speed_log, monkeypatch):
    """Replicates fit on at most ``REPLICATE_SAMPLES`` compared samples (the thinning long fits use: every k-th
    sample, simulated on blocks of k where the time constants allow) and judge on every held-out sample: on a log
    thinned to a third, the held-out error is the same to a thousandth of a kelvin and the replicates take the same
    change."""
    from thermolimb.workbench.diagnosis import stability
    from thermolimb.workbench.diagnosis.refit import compared_on, evaluate

    runs = speed_log.runs("knee")
    split = Scheme.at_split(0.7)
    full = evaluate(runs, ("joule", "effort_bias", "speed_losses"), split)
    with compared_on(1000):
        thin = evaluate(runs, ("joule", "effort_bias", "speed_losses"), split)
    assert full.estimator.stride_ == 1 and thin.estimator.stride_ == 3
    assert sum(s.time_s.size for s in thin.validation_segments) == sum(s.time_s.size for s in full.validation_segments)
    assert abs(thin.validation["rmse_K"] - full.validation["rmse_K"]) < 0.001  # 0.05925 and 0.05924 K
    monkeypatch.setattr(stability, "REPLICATE_SAMPLES", 1000)
    d = diagnose(runs)
    frequencies, *_ = selection_frequencies(d.candidates, d.recommended, d.model, d.base, runs,
                                       Search(stability=Stability(replicates=4, workers=1)))
    assert frequencies["+ speed_losses"] == 1.0


@pytest.mark.slow  # half a minute or more on two cores (the default run stays under ten minutes)
def test_replicates_that_agree_on_adding_but_not_on_the_order_let_the_walk_go_on():
    """benchmarks/forecast.py's seed-1 calibration log (a winding on a heavier housing, speed losses, copper's
    coefficient and a lagging thermistor hidden): most replicates take speed losses first, the others the second
    mass, which helps on the whole log too. Before, the walk stopped at Jorgensen et al.'s model; it now takes the
    whole log's best, says why, and each later step is taken in 10 of 10 (the mass, the sensor's lag, the friction
    on the housing), the model the walk without its check ends with.  How the replicates split sits on fits that
    end in one valley or the other: 6 and 4 of 10 with scipy.signal's filters, 14 and 6 of 20 with the suite's own
    (ten more drawn, as the first ten left it within one replicate of its share), which differ from them by 1e-13;
    the test holds what the rule rests on, not the split."""
    from thermolimb.plant import X8_9
    from thermolimb.workbench.diagnosis import auto_diagnose

    spec = replace(X8_9, network=NETWORKS["second_order"])
    fx = PlantEffects.from_names(["sensor_noise", "quantisation", "speed_losses", "winding_tempco", "sensor_lag"])
    series = simulate_profile("random", 7200.0, 1.0, ["knee"], [spec], fx, seed=1).log.series("knee")
    first, steps = auto_diagnose([series], stability=Stability())
    shares = first.stability["frequencies"]
    assert set(shares) == {"+ speed_losses", "+ second_node", "none"} and shares["none"] == 0.0, shares
    # 6 of 10 with scipy.signal's filters, 14 of 20 with the suite's, 9 of 10 under another OpenBLAS kernel: the
    # verdict, the walk and the sentence's words are the same on either side of the 80 % line
    assert 0.5 <= shares["+ speed_losses"] < 1.0
    assert shares["+ second_node"] == pytest.approx(1.0 - shares["+ speed_losses"])
    assert first.recommended.effect == "speed_losses" and first.unstable is None
    # where the second mass also helps on the whole log, the sentence says the replicates agree on adding, on
    # either side of the 80 % line (under OpenBLAS's Haswell kernel its whole-log refit lands implausible instead)
    mass = next(c for c in first.candidates if c.label == "+ second_node")
    said = f"the others take + second_node ({100 * shares['+ second_node']:.0f}%), which helps too"
    assert (said in first.recommended.evidence) == mass.eligible
    assert [s.get("change") for s in first.auto][1:] == ["+ speed_losses", "+ second_node", "+ sensor_lag",
                                                        "+ housing_friction"], first.auto
    assert all(s.recommended is None or s.recommended.selection_frequency == 1.0 for s in steps[1:])


def test_a_best_addition_fewer_replicates_take_than_another_is_not_taken_for_the_order():
    """UR3 J0's second part (near steady state): the whole log's best, + sensor_lag, is taken in 3 of 10 replicates,
    + speed_losses in 5, nothing in 2. Additions make 8 of 10, but the replicates do not agree that the best comes
    first: the walk stops at the start, as before the order rule. Taken, its model missed the first part by 1.487 K
    where Jorgensen et al.'s misses by 1.404 K (benchmarks/transfer.py)."""
    from thermolimb.workbench.diagnosis import auto_diagnose

    run = REAL_LOGS["ur3"].read()[0].runs("J0")[1]
    first, steps = auto_diagnose([run], stability=Stability())
    assert first.stability["frequencies"]["+ sensor_lag"] == 0.3 and first.stability["frequencies"]["none"] == 0.2
    assert first.recommended is None and first.unstable.effect == "sensor_lag" and len(steps) == 1


def test_replicates_that_all_take_some_change_that_cuts_the_error_many_fold_let_the_walk_take_the_most_taken():
    """A dynamometer run (issue 81, item 7): the default model 33.3 K off held out, 14 of 20 replicates take
    ``- effort_bias`` (3.5 K) and 6 take ``+ sensor_lag`` (4.8 K); neither alone reaches 0.8, but every replicate
    agrees that the model lacks something that cuts the error many-fold, so the walk takes the most taken and
    names the other.  Where a fifth or more take nothing, or a change taken cuts the error less than twice, it
    does not."""
    from thermolimb.workbench.diagnosis.candidates import Candidate
    from thermolimb.workbench.diagnosis.stability import agreed

    def change(label_effect, kind, rmse, share):
        model = ("joule",) if kind == "drop" else ("joule", "effort_bias", label_effect)
        return Candidate(label_effect, model, kind=kind, rmse_K=rmse, improvement=1.0 - rmse / 33.3, delta_bic=-50.0,
                         plausible=True, identifiable=True, selection_frequency=share)

    drop, lag = change("effort_bias", "drop", 3.5, 0.7), change("sensor_lag", "add", 4.8, 0.3)
    assert drop.eligible and lag.eligible
    chosen, words = agreed([drop, lag], {"- effort_bias": 0.7, "+ sensor_lag": 0.3, "none": 0.0}, 20, Stability())
    assert chosen is drop
    assert words == ("; 20 of 20 replicates take a change that cuts the held-out error at least 2-fold, this one the "
                     "most (+ sensor_lag in 6 the others): the walk takes it")
    assert agreed([drop, lag], {"none": 0.25}, 20, Stability()) is None  # a quarter take nothing: no agreement
    weak = change("sensor_lag", "add", 20.0, 0.3)  # cuts 33.3 K to 20 K: not many-fold
    assert agreed([drop, weak], {"none": 0.0}, 20, Stability()) is None


@pytest.mark.slow  # two diagnoses with their stability checks, in two processes: about a minute each
def test_a_split_verdict_is_the_same_under_two_blas_kernels_and_thread_counts(tmp_path):
    """The seed-1 calibration log above, whose replicates split between two valleys next to the rule's line
    (6, 9 or 14 of 10 or 20 with the kernel and the filters): ``diagnose --json`` under OpenBLAS's Haswell kernel
    on one thread and an older generic one on two gives the same verdict, the same held-back change and the
    same first line (issue 81, item 7).  The shares may differ; what is said of them may not."""
    import os
    import platform
    import subprocess
    import sys

    from thermolimb.plant import X8_9

    spec = replace(X8_9, network=NETWORKS["second_order"])
    fx = PlantEffects.from_names(["sensor_noise", "quantisation", "speed_losses", "winding_tempco", "sensor_lag"])
    simulate_profile("random", 7200.0, 1.0, ["knee"], [spec], fx, seed=1).log.write(tmp_path / "log.csv")
    older = "Prescott" if platform.machine() in ("x86_64", "AMD64") else "ARMV8"
    said = []
    for kernel, threads in (("Haswell" if older == "Prescott" else "ARMV8", "1"), (older, "2")):
        env = {**os.environ, "OPENBLAS_CORETYPE": kernel, "OPENBLAS_NUM_THREADS": threads,
               "OMP_NUM_THREADS": threads}
        argv = [sys.executable, "-m", "thermolimb", "diagnose", str(tmp_path / "log.csv"), "--actuator", "knee"]
        record = json.loads(subprocess.run(argv + ["--json"], env=env, capture_output=True, text=True,
                                           check=True).stdout)
        text = subprocess.run(argv, env=env, capture_output=True, text=True, check=True).stdout
        said.append((record["recommended_change"], record["unstable"], text.splitlines()[0]))
    assert said[0] == said[1], said
