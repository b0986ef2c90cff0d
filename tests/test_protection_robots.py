"""Thermal protection acts in both robots through the rig's one protection call (the control period included).

Each robot is driven well past its actuators' continuous effort with hot
windings and a thermistor that lags its winding by 15 s: the hexapod standing
with 80 kg on its back, the humanoid balancing on its right foot.  With
protection on the observer's winding estimate no true winding passes its
limit; with protection on the lagging thermistor alone it does (measured:
+27.6 K in the hexapod's hottest winding, +14.7 K in the humanoid's stance ankle rod),
so these tests fail if the robots' protection stops using the observer.
Both robots may sink once protection takes their torque away: that is the
protection working, and what happens to the windings is what is checked.
"""


import numpy as np
import pytest

from thermolimb.plant import PlantEffects, SensorLag, ThermalProtection

LAGGING_THERMISTOR = PlantEffects.realistic_sensor().replace(sensor_lag=SensorLag(time_constant_s=15.0))


def hexapod_excess_K(estimator: str, duration_s: float = 20.0) -> float:
    """Hottest true winding above its limit (K) standing with 80 kg, windings and housings 20 K under the limit."""
    from hexapod_pb.control import cpg
    from hexapod_pb.control.controller import ControllerState, control_step
    from hexapod_pb.params import DAISY
    from hexapod_pb.sim import HexapodSim, SimConfig

    config = SimConfig(payload_kg=80.0)
    with HexapodSim(config=config, plant_effects=LAGGING_THERMISTOR, seed=0,
                    protection=ThermalProtection(estimator=estimator)) as sim:
        limit_C = sim.plant.winding_limits_C
        sim.plant.set_temperatures(limit_C - 20.0)
        gait = cpg.CPGParams()
        state = ControllerState(cpg.initial_state(None, gait))
        reading = sim.read()
        excess = -np.inf
        for _ in range(int(duration_s * config.control_hz)):
            tau, state, _ = control_step(reading, state, DAISY, gait, "vertical_only", config.control_dt_s,
                                         config.payload_kg, walking=False)
            reading = sim.step(tau)
            excess = max(excess, float(np.max(sim.plant.winding_C - limit_C)))
    return excess


def humanoid_excess_K(estimator: str, duration_s: float = 30.0) -> float:
    """Hottest true winding above its limit (K) balancing on the right foot, whose leg's windings are put 16 K
    under the limit (where derating starts: 1 K inside its margin) once the weight is on it, over ``duration_s``
    from then."""
    from humanoid_pb.constants import ACTUATORS, leg_actuators
    from humanoid_pb.control.executor import ENTRY_S, Executor
    from humanoid_pb.ik.poses import crouch_angles
    from humanoid_pb.sim import HumanoidSim

    hot = np.array([a in leg_actuators("right") for a in ACTUATORS])
    with HumanoidSim(crouch_angles(), plant_effects=LAGGING_THERMISTOR, seed=0,
                     protection=ThermalProtection(estimator=estimator)) as sim:
        limit_C = sim.plant.winding_limits_C
        executor = Executor(sim)
        reading = sim.read()
        executor.go("right")
        heated_at = 2 * ENTRY_S + 0.5  # s: the weight is on the right foot
        excess = -np.inf
        while sim.time_s < heated_at:
            reading = executor.tick(reading)
        sim.plant.set_temperatures(np.where(hot, limit_C - 16.0, 40.0), np.where(hot, limit_C - 40.0, 30.0))
        for _ in range(int(duration_s / sim.config.control_dt_s)):
            reading = executor.tick(reading)
            excess = max(excess, float(np.max(sim.plant.winding_C - limit_C)))
    return excess


def test_the_hexapod_under_a_heavy_payload_never_passes_the_winding_limit_with_the_observer():
    assert hexapod_excess_K("observer") < 0.0
    assert hexapod_excess_K("measured") > 5.0  # the lagging thermistor alone lets the winding through


@pytest.mark.slow
def test_the_humanoid_on_one_leg_never_passes_the_winding_limit_with_the_observer():
    assert humanoid_excess_K("observer") < 0.0
    assert humanoid_excess_K("measured") > 5.0


def test_the_rig_caps_the_current_over_its_control_period():
    """At a 10 s control period the derating curve alone cannot react in time: the rig passes the period to the
    plant's protection, whose observer caps the current so the winding predicted at the period's end stays under
    the limit (the plant's own cap is tested in tests/test_observer.py; this is the robots' path to it)."""
    from hexapod_pb.sim import HexapodSim, SimConfig

    config = SimConfig(fixed_base=True, physics_hz=100.0, control_hz=0.1)
    with HexapodSim(config=config, plant_effects=PlantEffects(), seed=0) as sim:
        limit_C = sim.plant.winding_limits_C
        sim.plant.set_temperatures(limit_C - 16.0)
        q, qd = sim.joint_states()
        allowed = sim.protected_torques(q, qd, sim.effort_limit.copy())
        # full derating-curve share at 16 K under the limit is 1: anything less is the period's cap
        assert np.all(allowed < sim.effort_limit)
        sim.step_torques(sim.effort_limit.copy())
        assert np.all(sim.plant.winding_C < limit_C)


if __name__ == "__main__":  # the numbers docs/reliability.md quotes
    for robot, excess in (("hexapod", hexapod_excess_K), ("humanoid", humanoid_excess_K)):
        for estimator in ("observer", "measured"):
            print(f"{robot:8s} protection on the {estimator:8s}: hottest true winding {excess(estimator):+.1f} K "
                  f"from its limit")
