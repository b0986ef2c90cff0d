"""Exact tests of the arithmetic the newest code rests on (issue 82, item 9): a plausible one-line slip in each
fails here, where the behavioural tests passed it.

* the forecast band's half-width is the two-sided normal quantile times the draws' spread (a one-sided
  quantile, 1.28 where 1.64 belongs at 90 %, fails);
* beyond the model's experience the band widens by the square of the effort's ratio (in proportion to it, or by
  its cube, fails), by 2 for a velocity, an air or a start beyond;
* leave-one-run-out trains each fold on every run but its own (a fold fitted on its own held-out run fails);
* the scan carries its state across chunks: a series long and fast enough for several chunks equals the plain
  loop (a chunk that restarts from zero, or from the previous chunk's first value, fails).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy.stats import norm

from thermolimb.forecast import forecast, parameter_draws, spread_of
from thermolimb.model.experience import beyond
from thermolimb.model.scan import Recursion, first_order_scan
from thermolimb.model.signals import Signals
from thermolimb.plant import X8_9, PlantEffects, simulate_profile
from thermolimb.workbench.saving import saved_from_report
from thermolimb.workbench.validation import RUNS, Scheme, scheme_folds, validate_model


@pytest.fixture(scope="module")
def runs():
    fx = PlantEffects.from_names(("sensor_noise",))
    return [simulate_profile("random", 1200.0, 1.0, ["knee"], [X8_9], fx, seed=seed).log.series("knee")
            for seed in (11, 12, 13)]


@pytest.mark.parametrize("level", [0.5, 0.9, 0.99])
def test_the_band_is_the_two_sided_quantile_times_the_draws_spread(runs, level):
    """A model file without a held-out residual: the band is the parameters' spread alone, its half-width
    ``z_{(1 + level) / 2}`` times the standard deviation of the draws' runs, at every sample."""
    report = validate_model(runs[:1], ("joule", "effort_bias"), Scheme())
    saved = replace(saved_from_report(report, []), residual=None, provenance={})
    signals, start = runs[1].signals, float(runs[1].temperature_C[0])
    f = forecast(saved, signals, start, 500.0, level=level, draws=32, seed=4)
    assert not f.notes  # within its experience: no widening, no floor on the band
    draws = parameter_draws(saved, 32, 4, "jackknife")
    spread = spread_of(lambda m: m.simulate(signals, start), draws, f.predicted_C)
    assert spread[1:].min() > 0
    np.testing.assert_allclose(f.high_C - f.predicted_C, norm.ppf(0.5 + level / 2.0) * spread, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(f.predicted_C - f.low_C, f.high_C - f.predicted_C, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("ratio", [1.5, 2.0, 3.0])
def test_the_band_widens_by_the_square_of_the_effort_s_ratio(ratio):
    """Asked for ``ratio`` times the largest effort the model saw, the band's model error is widened by ``ratio**2``
    (the heat goes as the effort's square); a velocity beyond its range by 2, whatever the ratio."""
    ranges = {"effort": [-10.0, 20.0], "velocity": [0.0, 2.0]}
    t = np.arange(11.0)
    asked = Signals(t, np.full(t.size, 20.0 * ratio), np.zeros(t.size))
    notes, factor = beyond(ranges, asked, 30.0, False)
    assert factor == pytest.approx(ratio**2, rel=1e-12) and len(notes) == 1
    assert f"{ratio:.2g} times the largest the model was identified on (20)" in notes[0]
    fast = Signals(t, np.full(t.size, 5.0), np.full(t.size, 2.0 * ratio))
    assert beyond(ranges, fast, 30.0, False)[1] == 2.0
    within = Signals(t, np.full(t.size, 20.0), np.full(t.size, 2.0))
    assert beyond(ranges, within, 30.0, False) == ([], 1.0)


def test_each_leave_one_run_out_fold_trains_on_every_other_run(runs):
    """Fold k holds out run k whole and is fitted on the others, in their order."""
    folds = scheme_folds(runs, Scheme(kind=RUNS))
    assert len(folds) == len(runs)
    for k, (fit_on, scored) in enumerate(folds):
        assert [id(s) for s in fit_on] == [id(s) for i, s in enumerate(runs) if i != k]
        assert [(id(s), pieces) for s, pieces in scored] == [(id(runs[k]), [(0, runs[k].n)])]


@pytest.mark.parametrize("low, high", [(0.99, 0.999), (0.995, 0.995)])
def test_a_scan_of_several_chunks_equals_the_plain_loop(low, high):
    """Decaying by about 100 e-folds over the series, the scan runs in several chunks (at most 30 e-folds each),
    the state carried from one to the next: the varying factors' chunks and the constant factor's alike."""
    rng = np.random.default_rng(9)
    a = rng.uniform(low, high, 20000)
    b = rng.normal(size=a.size) + 0.5
    recursion = Recursion(a)
    if low != high:
        assert recursion.chunks is not None and len(recursion.chunks) >= 3  # the chunked path, several chunks
    else:
        assert isinstance(recursion.a, float) and -np.log(high) * a.size > 3 * 30  # constant, several chunks' decay
    expected = np.empty(a.size + 1)
    expected[0] = 2.0
    for k in range(a.size):
        expected[k + 1] = a[k] * expected[k] + b[k]
    np.testing.assert_allclose(first_order_scan(a, b, 2.0), expected, rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(recursion.run(b, 2.0), expected, rtol=1e-10, atol=1e-9)


@pytest.mark.parametrize("count, k, low, high", [(8, 10, 0.4902, 0.9433), (10, 10, 0.7225, 1.0), (0, 10, 0.0, 0.2775),
                                                 (14, 20, 0.4810, 0.8545)])
def test_a_share_of_replicates_is_said_with_its_wilson_interval(count, k, low, high):
    """How far a share of replicates is from certain (issue 81, item 7): the 95 % Wilson score interval, as
    published tables give it (8 of 10: 0.490 to 0.943)."""
    from thermolimb.workbench.diagnosis.stability import share_interval

    assert share_interval(count, k) == pytest.approx([low, high], abs=5e-5)
