from dataclasses import replace

import numpy as np
import pytest

from thermolimb.plant import (
    FIRST_ORDER_NETWORK,
    X8_9,
    X8_16,
    X8_NETWORK,
    PlantEffects,
    ThermalPlant,
    ThermalProtection,
    simulate_profile,
)
from thermolimb.plant.blocks import free_block
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS


def hold(plant, effort, velocity, seconds, dt):
    for _ in range(int(round(seconds / dt))):
        plant.step(np.asarray(effort, float), np.asarray(velocity, float), dt)


def test_steady_state_is_heat_times_total_resistance():
    plant = ThermalPlant(["a"], [replace(X8_9, driver=None)])
    effort = 12.0
    heat = (effort / X8_9.effort_per_amp) ** 2 * X8_9.winding_resistance_ohm
    hold(plant, [effort], [0.0], 400_000.0, 500.0)  # 40 body time constants: exp(-40) is negligible
    expected = 25.0 + heat * X8_NETWORK.total_resistance_K_per_W
    assert plant.winding_C[0] == pytest.approx(expected, rel=1e-9)
    assert plant.steady_state_rise_K(heat) == pytest.approx(expected - 25.0)


def test_x8_time_constants_match_reference():
    # facts.md: X8 network time constants about 1.4 s, 25 s and 10 100 s
    np.testing.assert_allclose(X8_NETWORK.time_constants_s, [1.4, 25.0, 10100.0], rtol=0.05)


def test_exact_integration_is_independent_of_the_control_rate():
    """Zero-order hold is exact: 60 s steps (40x the winding time constant) land on the 0.01 s trajectory."""
    coarse = ThermalPlant(["a"], [X8_9])
    fine = ThermalPlant(["a"], [X8_9])
    hold(coarse, [15.0], [0.0], 600.0, 60.0)
    hold(fine, [15.0], [0.0], 600.0, 0.01)
    np.testing.assert_allclose(coarse.winding_C, fine.winding_C, rtol=1e-8)


@pytest.mark.parametrize("effect, direction", [
    ("winding_tempco", +1), ("speed_losses", +1), ("field_weakening", +1), ("motion_cooling", -1),
    ("effort_bias", -1),  # positive effort minus a positive bias: less current
])
def test_each_effect_moves_the_winding_temperature_the_expected_way(effect, direction):
    base = ThermalPlant(["a"], [X8_9])
    other = ThermalPlant(["a"], [X8_9], PlantEffects.from_names([effect]))
    for plant in (base, other):
        hold(plant, [15.0], [2.0], 1800.0, 0.5)
    assert np.sign(other.winding_C[0] - base.winding_C[0]) == direction
    assert abs(other.winding_C[0] - base.winding_C[0]) > 0.5


def test_neighbor_coupling_warms_the_idle_neighbour():
    names, specs = ["hot", "idle"], [X8_9, X8_9]
    base = ThermalPlant(names, specs)
    coupled = ThermalPlant(names, specs, PlantEffects.from_names("neighbor_coupling"))
    for plant in (base, coupled):
        hold(plant, [18.0, 0.0], [0.0, 0.0], 3600.0, 1.0)
    assert coupled.winding_C[1] > base.winding_C[1] + 1.0
    assert coupled.winding_C[0] < base.winding_C[0]


def test_sensor_lag_noise_and_quantisation():
    rng = np.random.default_rng(3)
    plant = ThermalPlant(["a"], [replace(X8_9, network=FIRST_ORDER_NETWORK)],
                         PlantEffects.from_names("sensor_lag,sensor_noise,quantisation"), rng=rng)
    lags = []
    for _ in range(200):
        plant.step(np.array([18.0]), None, 0.1)
        lags.append(plant.winding_C[0] - plant.measured_C[0])
        assert np.allclose(plant.measured_C / 0.1, np.round(plant.measured_C / 0.1))
    assert np.mean(lags) > 0.3  # while heating, the lagged thermistor reads low


def test_with_no_heat_every_node_stays_within_the_ambient_it_has_seen_and_follows_its_drift():
    """A passive network at rest cannot leave the range of its boundary temperature, and it warms as that drifts."""
    plant = ThermalPlant(["a"], [X8_9], PlantEffects.from_names("ambient_variation"), ambient_C=20.0)
    assert plant.ambient_at(0.0) == pytest.approx(20.0)
    ambient, nodes = [20.0], []
    for _ in range(2000):  # 2000 x 10 s = 5.6 h: several oscillation periods and 11 K of drift
        plant.step(np.zeros(1), None, 10.0)
        ambient.append(plant.ambient_C)
        nodes.append([plant.node_C(name)[0] for name in X8_9.network.node_names])
    nodes = np.array(nodes)
    assert min(ambient) - 1e-9 <= nodes.min() and nodes.max() <= max(ambient) + 1e-9
    assert max(ambient) - min(ambient) > 8.0  # the drift really moved the boundary
    assert nodes[-1].mean() > nodes[len(nodes) // 2].mean() + 2.0  # and the network followed it up


def test_thermal_protection_derates_near_the_limit():
    protection = ThermalProtection(margin_K=15.0)
    np.testing.assert_allclose(protection.fraction([100.0, 147.5, 160.0], X8_9.winding_limit_C), [1.0, 0.5, 0.0])
    plant = ThermalPlant(["a"], [X8_9], initial_C=150.0, protection=ThermalProtection(estimator="measured"))
    assert plant.derate(np.array([10.0]))[0] == pytest.approx(10.0 / 3.0)
    observed = ThermalPlant(["a"], [X8_9], initial_C=150.0)  # the observer adds its uncertainty: derates more
    assert observed.derate(np.array([10.0]))[0] < 10.0 / 3.0


def test_same_seed_same_log_and_other_seed_differs():
    args = ("random", 600.0, 0.5, ["a", "b"], [X8_9, X8_16], PlantEffects.realistic_sensor())
    one = simulate_profile(*args, seed=7).log.frame
    two = simulate_profile(*args, seed=7).log.frame
    three = simulate_profile(*args, seed=8).log.frame
    assert one.equals(two)
    assert not one.equals(three)


def test_bad_plant_parameters_are_refused():
    with pytest.raises(ValueError, match="positive and finite"):
        replace(X8_9, winding_resistance_ohm=-1.0)
    with pytest.raises(ValueError, match="sensor_noise is on"):
        ThermalPlant(["a"], [X8_9], PlantEffects.from_names("sensor_noise"))
    with pytest.raises(ValueError, match="unknown plant effect"):
        PlantEffects.from_names("copper")


def test_set_temperatures_can_leave_the_housings_cool():
    """A winding heated for a minute sits on a housing near ambient: it cools on its own time constant, not the
    housing's (an actuator soaked through, the default, cannot)."""
    from thermolimb.plant import ACTUATOR_SPECS, ThermalPlant

    specs = [ACTUATOR_SPECS["X8-9"]]
    soaked, fresh = (ThermalPlant(["j"], specs, ambient_C=25.0) for _ in range(2))
    soaked.set_temperatures([80.0])
    fresh.set_temperatures([80.0], rest_C=[25.0])
    assert soaked.measured_C[0] == fresh.measured_C[0] == 80.0
    for _ in range(60):
        soaked.step(np.zeros(1), None, 1.0)
        fresh.step(np.zeros(1), None, 1.0)
    assert fresh.winding_C[0] < 60.0 < soaked.winding_C[0]
    with pytest.raises(ValueError, match="is outside the range expected"):
        fresh.set_temperatures([np.nan])


def test_driver_boards_are_logged_as_their_own_channels():
    """``--drivers``: each driver board is an actuator ``<name>/driver`` with the motor's effort, its own sensor."""
    run = simulate_profile("squat", 600.0, 1.0, ["knee", "hip"], [X8_16, replace(X8_9, driver=None)],
                           PlantEffects(), seed=0, include_drivers=True)
    assert set(run.log.actuators) == {"knee", "hip", "knee/driver"}
    motor, driver = run.log.series("knee"), run.log.series("knee/driver")
    np.testing.assert_array_equal(driver.signals.effort, motor.signals.effort)
    assert not np.allclose(driver.temperature_C, motor.temperature_C)  # the board has a thermal mass of its own
    assert driver.temperature_C.max() > 25.0 + 0.5  # and heats with the current


# the observer's run: 41 s on two cores, slow (the default run stays under ten minutes)
@pytest.mark.parametrize("estimator", [pytest.param("observer", marks=pytest.mark.slow), "measured"])
def test_a_run_in_blocks_is_the_run_stepped_one_interval_at_a_time(estimator):
    """Blocks between protection's decisions change nothing but the speed: the same efforts, temperatures,
    readings (the same noise draws) and estimates as stepping every interval, here with protection acting on a
    good share of the run (a 60 K margin), so blocks are cut where it starts to act and resumed after."""
    from thermolimb.plant import run_profile
    from thermolimb.plant.profiles import PROFILES

    effects = PlantEffects.from_names("sensor_noise,quantisation,sensor_lag,speed_losses,neighbor_coupling,"
                                      "ambient_variation")
    runs = []
    for in_blocks in (True, False):
        rng = np.random.default_rng(7)
        profile = PROFILES["random"](1500.0, 0.1, len(CASE_NAMES), rng)
        profile = replace(profile, load=profile.load * 3.0)
        plant = ThermalPlant(list(CASE_NAMES), list(CASE_SPECS), effects, rng=rng,
                             protection=ThermalProtection(margin_K=60.0, estimator=estimator))
        assert plant.steps_in_blocks
        runs.append(run_profile(plant, profile, in_blocks=in_blocks))
    blocks, steps = runs
    continuous = np.array([s.continuous_effort for s in CASE_SPECS])
    limit = np.array([s.effort_limit for s in CASE_SPECS])
    commanded = np.clip(profile.load * continuous, -limit, limit)
    derated = np.mean(np.abs(steps.effort) < np.abs(commanded) - 1e-9)
    assert 0.05 < derated < 0.95, derated  # protection acts on part of the run, not all of it
    np.testing.assert_allclose(blocks.effort, steps.effort, rtol=0, atol=1e-8)
    np.testing.assert_allclose(blocks.true_winding_C, steps.true_winding_C, rtol=0, atol=1e-8)
    np.testing.assert_array_equal(blocks.measured_C, steps.measured_C)
    if estimator == "observer":
        np.testing.assert_allclose(blocks.estimated_C, steps.estimated_C, rtol=0, atol=1e-8)
    np.testing.assert_allclose(blocks.log.frame["current"], steps.log.frame["current"], rtol=0, atol=1e-8)


def test_a_plant_whose_heat_follows_its_state_steps_one_interval_at_a_time():
    """Copper resistance makes the heat depend on the temperature: no fixed map over a block, so no blocks."""
    plant = ThermalPlant(list(CASE_NAMES), list(CASE_SPECS), PlantEffects.from_names("winding_tempco"))
    assert not plant.steps_in_blocks
    with pytest.raises(ValueError, match="free_block needs"):
        free_block(plant, np.ones((3, 3)), np.zeros((3, 3)), 0.1)


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_a_run_in_pieces_is_the_whole_run_and_its_file_reads_back_as_the_whole_log(tmp_path, suffix):
    """Windows of a run carry the plant from one to the next (the same samples as one window), and their logs
    written a piece at a time read back as the whole run's log."""
    from thermolimb.logs import read_log, write_pieces
    from thermolimb.plant.run import simulate_profile_in_pieces

    effects = PlantEffects.from_names("sensor_noise,quantisation,sensor_lag,speed_losses")
    args = ("random", 1200.0, 0.2, list(CASE_NAMES), list(CASE_SPECS), effects)
    whole = simulate_profile(*args, seed=3, load_scale=3.0)
    pieces = list(simulate_profile_in_pieces(*args, seed=3, load_scale=3.0, piece_samples=1000))
    assert [len(p.time_s) for p in pieces] == [1000] * 5 + [1001]  # 6001 samples; none shorter than half
    for field in ("time_s", "effort", "true_winding_C", "measured_C", "estimated_C"):
        np.testing.assert_allclose(np.concatenate([getattr(p, field) for p in pieces]), getattr(whole, field),
                                   rtol=0, atol=1e-9, err_msg=field)
    path = write_pieces((p.log for p in pieces), tmp_path / f"log{suffix}")
    back, alone = read_log(path), read_log(whole.log.write(tmp_path / f"whole{suffix}"))
    assert back.actuators == alone.actuators
    for name in back.actuators:
        a, b = back.series(name), alone.series(name)
        np.testing.assert_allclose(a.time_s, b.time_s, rtol=0, atol=1e-9)
        np.testing.assert_allclose(a.temperature_C, b.temperature_C, rtol=0, atol=1e-9)
        np.testing.assert_allclose(a.signals.effort, b.signals.effort, rtol=0, atol=1e-9)
