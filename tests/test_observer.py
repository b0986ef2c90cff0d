"""The winding observer: exact where its model is, close where the plant is richer, and protection that protects."""

from dataclasses import replace

import numpy as np
import pytest

from thermolimb.model.saved import bare
from thermolimb.monitor import ActuatorMonitor
from thermolimb.plant import (
    FIRST_ORDER_NETWORK,
    PLANT_EFFECTS,
    X8_9,
    X8_16,
    PlantEffects,
    ThermalPlant,
    ThermalProtection,
    run_profile,
)
from thermolimb.plant.observer import WindingObserver
from thermolimb.plant.profiles import PROFILES, Profile
from thermolimb.workbench.validation import make_estimator


def drive(plant, profile, scale=1.0):
    """Run ``profile`` through ``plant`` with its protection: true, measured and estimated windings."""
    run = run_profile(plant, replace(profile, load=profile.load * scale))
    return run.true_winding_C, run.measured_C, run.estimated_C


def test_with_the_plants_own_model_the_estimate_is_exact():
    rng = np.random.default_rng(0)
    profile = PROFILES["random"](1800.0, 1.0, 1, rng)
    plant = ThermalPlant(["a"], [X8_9], PlantEffects.from_names("sensor_lag"))
    observer = WindingObserver([X8_9], sensor_tau_s=plant.effects.sensor_lag.time_constant_s, initial_C=25.0,
                               copper_alpha_per_K=0.0)
    for k in range(profile.time_s.size - 1):
        effort = profile.load[k] * X8_9.continuous_effort
        plant.step(effort, profile.velocity_rad_s[k], 1.0)
        observer.update(plant.current_A, plant.measured_C, plant.ambient_C, 1.0)
        assert observer.winding_C[0] == pytest.approx(plant.winding_C[0], abs=1e-6)


def test_on_a_richer_plant_the_estimate_tracks_the_winding_the_thermistor_lags():
    """Copper tempco, speed losses, a drifting ambient, a lagging, noisy, quantised thermistor."""
    effects = PlantEffects.from_names("sensor_lag,sensor_noise,quantisation,winding_tempco,speed_losses,"
                                      "ambient_variation")
    rng = np.random.default_rng(0)
    profile = PROFILES["random"](3600.0, 1.0, 2, rng)
    plant = ThermalPlant(["a", "b"], [X8_9, X8_16], effects, rng=rng)
    true, measured, estimate = drive(plant, profile, scale=1.5)
    rms = lambda e: np.sqrt(np.mean(e**2, axis=0))  # noqa: E731
    assert rms(estimate - true).max() < 1.5  # measured 1.03 and 1.04 K
    assert rms(measured - true).min() > 4.0  # the thermistor: 6.0 and 6.6 K
    assert np.abs(estimate - true)[60:].max() < 8.0  # after its first minute; the thermistor is 51 K off


def test_time_to_limit_matches_the_plant_at_constant_current():
    plant = ThermalPlant(["a"], [X8_16], PlantEffects(), protection=ThermalProtection(estimator="measured"))
    observer = WindingObserver([X8_16], initial_C=25.0, copper_alpha_per_K=0.0)
    effort = np.array([3.0 * X8_16.continuous_effort])
    plant.step(effort, None, 1.0)
    observer.update(plant.current_A, plant.measured_C, 25.0, 1.0)
    predicted = observer.time_to_limit_s(plant.current_A, 120.0, 25.0, step_s=1.0)[0]
    assert predicted is not None
    elapsed = 0.0
    while plant.winding_C[0] < 120.0:
        plant.step(effort, None, 1.0)
        elapsed += 1.0
    assert predicted == pytest.approx(elapsed, abs=2.0)
    assert observer.time_to_limit_s(np.zeros(1), 120.0, 25.0)[0] is None  # never: the one meaning of it


def test_current_cap_puts_the_predicted_winding_on_the_limit():
    observer = WindingObserver([X8_9], initial_C=140.0, copper_alpha_per_K=0.0039)
    current = np.array([12.0])
    share = observer.current_fraction_cap(current, 150.0, 25.0, 1.0)[0]
    assert 0.0 < share < 1.0
    trial = WindingObserver([X8_9], initial_C=140.0, copper_alpha_per_K=0.0039)
    assert trial.predict(share * current, 25.0, 1.0)[0] == pytest.approx(150.0, abs=0.05)
    assert observer.current_fraction_cap(current, 139.0, 25.0, 1.0)[0] == 0.0


def test_observing_a_log_with_an_identified_model_sees_through_the_thermistor_lag():
    spec = replace(X8_9, network=FIRST_ORDER_NETWORK)
    rng = np.random.default_rng(4)
    profile = PROFILES["random"](3600.0, 1.0, 1, rng)
    plant = ThermalPlant(["knee"], [spec], PlantEffects.from_names("sensor_lag,sensor_noise"), rng=rng,
                         protection=ThermalProtection(estimator="measured"))
    run = run_profile(plant, replace(profile, load=profile.load * 1.5))
    series = run.log.series("knee")
    model = make_estimator("output_error", "joule,sensor_lag").fit(series).model_
    monitor = ActuatorMonitor(bare(model, "knee"), limit_C=155.0)
    ends = np.arange(10, series.n, 10)  # the log read ten samples at a time, as a monitor follows it
    estimate = np.array([monitor.update(series.signals.slice(lo, hi + 1), series.temperature_C[lo:hi + 1]).winding_C
                         for lo, hi in zip(np.r_[0, ends[:-1]], ends)])
    true = run.true_winding_C[ends, 0]
    assert np.sqrt(np.mean((estimate - true) ** 2)) < 0.5 * np.sqrt(np.mean((series.temperature_C[ends] - true) ** 2))


@pytest.mark.parametrize("dt_s", [2.0, 10.0])
def test_peak_current_at_a_slow_control_rate_stops_on_the_limit(dt_s):
    """At its effort limit a winding gains kelvins per control period: the observer's cap over the interval the effort
    will be held for, not the derating curve alone, keeps it at its limit."""
    t = np.arange(0.0, 1200.0 + dt_s, dt_s)
    profile = Profile(t, np.full((len(t), 1), 4.0), np.zeros((len(t), 1)))
    plant = ThermalPlant(["a"], [X8_9], PlantEffects(), ambient_C=80.0, protection=ThermalProtection(estimator="observer"))
    winding = run_profile(plant, profile).true_winding_C
    assert winding.max() <= X8_9.winding_limit_C + 1e-6
    assert winding.max() > X8_9.winding_limit_C - ThermalProtection().margin_K  # it did get there


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_ten_hour_soak_with_every_effect_never_lets_the_winding_exceed_its_limit(seed):
    effects = PlantEffects.from_names(",".join(PLANT_EFFECTS))
    specs = [X8_9, X8_16, X8_9]

    def soak(estimator):
        rng = np.random.default_rng(seed)
        profile = PROFILES["random"](36000.0, 1.0, 3, rng)
        plant = ThermalPlant(["a", "b", "c"], specs, effects, rng=rng,
                             protection=ThermalProtection(estimator=estimator))
        return drive(plant, profile, scale=3.0)[0].max(axis=0)

    limits = np.array([s.winding_limit_C for s in specs])
    assert np.all(soak("observer") <= limits)  # measured: 152.8-154.5 degC
    assert np.any(soak("measured") > limits + 20.0)  # protection on the lagged thermistor: 215-335 degC
