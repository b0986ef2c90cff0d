"""Tests that pin down the slips a careful reader could make: units, signs, scales, thresholds.

Each one fails under a plausible one-character bug (found by mutating the code by hand): a copper
coefficient's sign, the sampling interval in a filter or a derivative, a variance for a standard deviation,
the recommendation threshold, the deg/s conversion, the thermal prediction's discount, a reward's sign.
"""

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from thermolimb.identification import FreeRunLeastSquares, LeastSquares
from thermolimb.identification.regression import lowpass, lowpass_derivative
from thermolimb.logs import from_frame
from thermolimb.model import ModelArrays
from thermolimb.plant import FIRST_ORDER_NETWORK, X8_9, PlantEffects, ThermalPlant, run_profile
from thermolimb.plant.profiles import random_holds
from thermolimb.workbench.diagnosis.candidates import Candidate
from thermolimb.workbench.diagnosis.residuals import Z95, bartlett_band, cross_correlation

FIRST_ORDER = replace(X8_9, network=FIRST_ORDER_NETWORK)
RC, BETA_R = FIRST_ORDER.first_order(lumped_nodes=1)


def plant_log(dt_s: float, effects: str = "", seed: int = 0, duration_s: float = 7200.0, scale: float = 1.0):
    rng = np.random.default_rng(seed)
    profile = random_holds(duration_s, dt_s, 1, rng, motion_probability=0.4)
    plant = ThermalPlant(["knee"], [FIRST_ORDER], PlantEffects.from_names(effects) if effects else PlantEffects(),
                         rng=rng)
    return run_profile(plant, replace(profile, load=profile.load * scale)).log.series("knee")


@pytest.mark.parametrize("dt_s", [0.5, 2.0])
@pytest.mark.parametrize("estimator", [LeastSquares, FreeRunLeastSquares])
def test_identification_at_sampling_intervals_other_than_one_second(dt_s, estimator):
    fitted = estimator(model="joule").fit(plant_log(dt_s)).params_
    assert fitted["RC_s"] == pytest.approx(RC, rel=0.03)
    assert fitted["betaR_K_per_effort2"] == pytest.approx(BETA_R, rel=0.03)


def test_copper_coefficient_round_trip_against_the_plant():
    """Run hot so that copper's 0.39 %/K shows; the fit returns the plant's physical coefficient."""
    series = plant_log(1.0, "winding_tempco", duration_s=4 * 3600.0, scale=1.8)
    fitted = FreeRunLeastSquares(model="joule,winding_tempco").fit(series).params_
    assert fitted["alpha_per_K"] == pytest.approx(0.0039, rel=0.15)


@pytest.mark.parametrize("dt_s", [0.1, 1.0, 5.0])
def test_lowpass_cutoff_is_in_hertz_whatever_the_sampling(dt_s):
    t = np.arange(0.0, 4000.0, dt_s)
    cutoff = 0.01
    slow, at_cutoff, fast = (np.sin(2 * np.pi * f * t) for f in (cutoff / 10, cutoff, cutoff * 5))
    middle = slice(t.size // 4, 3 * t.size // 4)
    gain = lambda x: np.std(lowpass(x, cutoff, dt_s)[middle]) / np.std(x[middle])  # noqa: E731
    assert gain(slow) == pytest.approx(1.0, abs=0.02)
    assert gain(at_cutoff) == pytest.approx(0.5, abs=0.03)  # second order, applied forwards and backwards: -6 dB
    assert gain(fast) < 0.02


@pytest.mark.parametrize("dt_s", [0.1, 2.0])
def test_filtered_derivative_is_per_second(dt_s):
    t = np.arange(0.0, 600.0, dt_s)
    _, slope = lowpass_derivative(3.0 + 0.25 * t, 0.05, dt_s)
    assert np.median(slope) == pytest.approx(0.25, rel=1e-3)


def test_bartlett_band_is_the_white_noise_band_for_white_series():
    rng = np.random.default_rng(0)
    x, e = rng.normal(size=20000), rng.normal(size=20000)
    band = bartlett_band(x, e, 50)
    assert band == pytest.approx(Z95 / np.sqrt(x.size), rel=0.05)
    _, r = cross_correlation(x, e, 50)
    assert 0.01 < np.mean(np.abs(r) > band) < 0.10  # about 5 % outside, as a 95 % band should


def test_bartlett_band_from_the_residual_s_own_correlation_is_the_same_band():
    """analyse_residuals passes the residual's autocorrelation it already has: the band is the one computed afresh."""
    rng = np.random.default_rng(2)
    x, e = np.cumsum(rng.normal(size=5000)), np.convolve(rng.normal(size=5000), np.ones(20) / 20, mode="same")
    _, ree = cross_correlation(e, e, 80)
    assert bartlett_band(x, e, 80, ree) == bartlett_band(x, e, 80)


def test_bartlett_band_widens_for_coloured_series():
    rng = np.random.default_rng(1)
    kernel = np.ones(50) / 50
    x = np.convolve(rng.normal(size=20000), kernel, mode="same")
    e = np.convolve(rng.normal(size=20000), kernel, mode="same")
    assert bartlett_band(x, e, 200) > 3 * Z95 / np.sqrt(x.size)


@pytest.mark.parametrize("improvement, delta_bic, helps", [
    (0.11, -11.0, True), (0.09, -50.0, False), (0.30, -9.0, False), (0.10, -10.0, True)])
def test_an_added_effect_needs_ten_percent_and_ten_bic(improvement, delta_bic, helps):
    cand = Candidate("speed_losses", ("joule", "speed_losses"), rmse_K=1.0, improvement=improvement,
                     delta_bic=delta_bic)
    assert cand.helps is helps


@pytest.mark.parametrize("improvement, delta_bic, helps", [(0.05, 5.0, True), (0.0, -1.0, True), (0.0, 1.0, False),
                                                           (-0.01, -5.0, False)])
def test_a_drop_needs_to_be_no_worse(improvement, delta_bic, helps):
    cand = Candidate("effort_bias", ("joule",), kind="drop", rmse_K=1.0, improvement=improvement, delta_bic=delta_bic)
    assert cand.helps is helps


@pytest.mark.parametrize("unit, factor", [("deg/s", np.pi / 180.0), ("rpm", 2 * np.pi / 60.0), ("rad/s", 1.0)])
def test_velocity_units_convert_to_radians_per_second(unit, factor):
    t = np.arange(30.0)
    frame = pd.DataFrame({"t": t, "tau": 1.0 + np.sin(t), "T": 30 + 0.1 * t, "v": np.full(t.size, 180.0)})
    log = from_frame(frame, mapping={"time": "t", "effort": "tau", "temperature": "T", "velocity": "v"},
                     velocity_unit=unit, actuator_name="m")
    assert log.series("m").signals.channel("velocity")[0] == pytest.approx(180.0 * factor)


def test_prediction_discounts_by_the_horizon_over_the_time_constant():
    bank = ModelArrays.of(RC_s=np.array([40.0, 400.0]), betaR_K_per_effort2=np.array([0.02, 0.01]),
                          beta_biasR_K_per_effort=np.array([0.1, 0.0]), T_offset_C=np.array([25.0, 30.0]))
    T0, effort, h = np.array([60.0, 50.0]), np.array([12.0, -7.0]), 20.0
    expected = bank.equilibrium_C(effort) + (T0 - bank.equilibrium_C(effort)) * np.exp(-h / bank.RC_s)
    np.testing.assert_allclose(bank.ahead(T0, effort, h), expected)
    a, b, c = bank.ahead_coefficients(T0, h)
    np.testing.assert_allclose(a + b * effort + c * effort**2, expected)
