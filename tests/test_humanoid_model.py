"""The Valkyrie-like humanoid: generated URDF, push rods, and Jorgensen et al.'s statics (Eqs. 21-24) with Pinocchio."""

import numpy as np
import pytest

from humanoid_pb.constants import ACTUATORS, CONTACT_MODES, JOINTS
from humanoid_pb.ik.poses import crouch_angles, standing
from humanoid_pb.model.pushrods import RodPair
from humanoid_pb.model.statics import WholeBody
from humanoid_pb.model.valkyrie_urdf import generate, urdf_path
from humanoid_pb.params import VALKYRIE, ValkyrieParams
from thermolimb.constants import GRAVITY_M_S2


@pytest.fixture(scope="module")
def body():
    return WholeBody()


def test_committed_urdf_matches_the_generator():
    assert urdf_path().read_text() == generate(), "run: python -m humanoid_pb.model.valkyrie_urdf"


def test_mass_is_valkyries(body):
    # facts.md: about 129-134 kg with hands and head; this model has no hands
    assert sum(i.mass for i in body.model.inertias) == pytest.approx(VALKYRIE.mass_kg, abs=0.01)  # + sole frames
    assert 125.0 < VALKYRIE.mass_kg < 134.0


def test_ankle_rods_reproduce_the_published_map():
    rods = RodPair(VALKYRIE.ankle_rod_m, *VALKYRIE.ankle_rod_arm_m)
    np.testing.assert_allclose(rods.torque_map(0.0, 0.0), [[-0.0367, -0.0367], [-0.0341, 0.0341]], atol=1e-4)
    tau = np.array([120.0, -40.0])
    np.testing.assert_allclose(rods.torque_map(0.2, -0.1) @ rods.rod_forces_N(0.2, -0.1, tau), tau, atol=1e-8)


@pytest.mark.parametrize("mode", CONTACT_MODES)
def test_statics_balance_gravity(body, mode):
    q = standing(body, crouch_angles())
    s = body.statics(q, mode)
    Jc = body.contact_jacobian(q, mode)
    # Eq. 18 at rest: S_a^T Gamma + J_c^T F_r = g (N and N m)
    np.testing.assert_allclose(body.S_a.T @ s.torques_Nm + Jc.T @ s.contact_wrenches.ravel(), body.gravity(q), atol=1e-6)
    total_mass = sum(i.mass for i in body.model.inertias)  # the params' mass plus 1 g per sole frame
    assert s.contact_wrenches[:, 2].sum() == pytest.approx(total_mass * GRAVITY_M_S2, rel=1e-9)
    assert s.efforts.shape == (len(ACTUATORS),)


def test_impossible_parameters_are_refused():
    with pytest.raises(ValueError, match="mass must be positive"):
        ValkyrieParams(torso_kg=0.0)


def hold(torques_of, seconds):
    from humanoid_pb.sim import HumanoidSim

    angles = crouch_angles()
    with HumanoidSim(angles) as sim:
        reading = sim.read()
        torques = torques_of(sim, reading)
        for _ in range(int(round(seconds / sim.config.control_dt_s))):
            reading = sim.step(torques)
        return np.abs(reading.q_rad - angles).max(), reading


def test_gamma_holds_the_configuration_still_in_pybullet():
    """Feed-forward Gamma(q) alone: the equilibrium is unstable (an inverted pendulum), so it holds for a
    moment and then drifts; 0.2 s is long enough to tell it from anything else."""
    drift, reading = hold(lambda sim, r: sim.body.statics(sim.pinocchio_q(r), "double").torques_Nm, 0.2)
    assert drift < 2e-3  # rad after 0.2 s
    # and the feet carry the weight as Eq. 21 says, half each in this symmetric crouch
    np.testing.assert_allclose(reading.foot_force_N[:, 2], VALKYRIE.mass_kg * GRAVITY_M_S2 / 2, rtol=0.02)
    zero_drift, _ = hold(lambda sim, r: np.zeros(len(JOINTS)), 0.2)
    assert zero_drift > 50 * drift


def test_parameters_are_frozen_all_the_way_down():
    with pytest.raises(TypeError):
        VALKYRIE.effort_limit_Nm["knee"] = 1.0  # would change every user's default
    assert VALKYRIE.effort_limit("left_knee") == 350.0
    assert hash(VALKYRIE) == hash(ValkyrieParams())  # usable as a cache key


def test_calibration_to_jorgensen_et_al_follows_from_statics(body):
    """The derivation in humanoid_pb.thermal: on one leg the stance ankle's rods are the hottest (then the knee,
    then the hip roll), and on the datasheet models they reach the 75 degC warning from 25 degC in about 100 s
    (Jorgensen et al.: under two minutes), with a 40 s time constant (Jorgensen et al.'s 20 s horizon is RC/2)."""
    from humanoid_pb.constants import leg_actuators
    from humanoid_pb.ik.poses import single_support
    from humanoid_pb.limits import LIMITS, OPERATING_C
    from humanoid_pb.thermal import TIME_TO_WARNING_S, actuator_specs, datasheet_bank
    from thermolimb.plant import ThermalProtection

    q = single_support(body, standing(body, crouch_angles()), "right")
    efforts = body.statics(q, "right").efforts
    bank = datasheet_bank(VALKYRIE, ambient_C=25.0)
    rise_K = bank.betaR_K_per_effort2 * efforts**2
    order = [ACTUATORS[i] for i in np.argsort(-rise_K)]
    assert set(order[:2]) == {"right_ankle_rod_a", "right_ankle_rod_b"}
    assert order[2:4] == ["right_knee", "right_hip_roll"]
    assert set(order[:4]) <= set(leg_actuators("right"))
    hottest = rise_K.max()
    time_to_warning_s = bank.RC_s[0] * np.log(hottest / (hottest - (LIMITS.warning_C - 25.0)))
    assert time_to_warning_s == pytest.approx(TIME_TO_WARNING_S, rel=0.05)
    assert np.all(bank.RC_s == 40.0)
    limits = {s.winding_limit_C for s in actuator_specs(VALKYRIE)}
    assert limits == {OPERATING_C + ThermalProtection().margin_K}  # derating starts at 90 degC


def test_rod_jacobian_and_effort_matrix_agree_with_their_definitions():
    """The analytic rod-length Jacobian against central differences of the lengths, and Eq. 24 as a matrix
    against the rod forces solved pair by pair, at random joint angles."""
    from humanoid_pb.model.actuation import effort_matrix, efforts, rod_pairs

    rods = rod_pairs(VALKYRIE)
    rng = np.random.default_rng(0)
    pair = rods["left_ankle"]
    for pitch, roll in rng.uniform(-0.5, 0.5, (5, 2)):
        h = 1e-6
        numeric = np.column_stack([(pair.lengths_m(pitch + h, roll) - pair.lengths_m(pitch - h, roll)) / (2 * h),
                                   (pair.lengths_m(pitch, roll + h) - pair.lengths_m(pitch, roll - h)) / (2 * h)])
        np.testing.assert_allclose(pair.length_jacobian(pitch, roll), numeric, atol=1e-8)
    for _ in range(5):
        angles, tau = rng.uniform(-0.3, 0.3, len(JOINTS)), rng.normal(0.0, 50.0, len(JOINTS))
        np.testing.assert_allclose(effort_matrix(rods, angles) @ tau, efforts(rods, angles, tau), rtol=1e-9, atol=1e-9)


def test_potential_derivatives_are_eq_26s():
    """The Newton model the fast IK uses: value, gradient and Hessian of Eq. 26 against central differences."""
    from humanoid_pb.ik.potential import ThermalPotential
    from humanoid_pb.thermal import datasheet_bank

    rng = np.random.default_rng(4)
    T = rng.uniform(35.0, 85.0, len(ACTUATORS))
    potential = ThermalPotential.from_measurement(datasheet_bank(VALKYRIE), T)
    efforts = rng.uniform(-200.0, 200.0, len(ACTUATORS))
    value, gradient, hessian = potential.newton(efforts)
    assert value == pytest.approx(potential.value(efforts))
    h = 0.01  # efforts of hundreds, a potential of millions: a smaller step drowns in rounding
    for i in range(len(ACTUATORS)):
        step = np.zeros(len(ACTUATORS))
        step[i] = h
        up, down = potential.value(efforts + step), potential.value(efforts - step)
        assert gradient[i] == pytest.approx((up - down) / (2 * h), rel=1e-5, abs=1e-6)
        slope = (potential.gradient(efforts + step)[i] - potential.gradient(efforts - step)[i]) / (2 * h)
        assert hessian[i] == pytest.approx(slope, rel=1e-5)
    np.testing.assert_allclose(potential.predicted_C(efforts),
                               potential.bank.ahead(T, efforts, potential.horizon_s), rtol=1e-12)


@pytest.mark.parametrize("fractions", ["by type", "uniform"])
def test_walking_scenario_makes_the_stance_knee_the_hottest_whatever_the_type_margins(body, fractions):
    """humanoid_pb.scenarios' derivation: at the walking stance the stance knee carries 44.5 % of its limit on one
    leg and 27.3 % in double support, and with the scenario's sizing it reaches the 75 degC warning in about the
    100 s of Jorgensen et al.; with one continuous fraction for every actuator type the knee is still the hottest (the type
    margins are an assumption that does not decide the case)."""
    from dataclasses import replace

    from humanoid_pb.ik.poses import single_support
    from humanoid_pb.limits import LIMITS
    from humanoid_pb.model.actuation import effort_limits
    from humanoid_pb.scenarios import SCENARIOS, UNIFORM
    from humanoid_pb.thermal import TIME_TO_WARNING_S, datasheet_bank

    walking = SCENARIOS["walking"]
    if fractions == "uniform":
        walking = replace(walking, continuous_fraction=UNIFORM)
    q = standing(body, crouch_angles(walking.crouch_depth_rad))
    knee = ACTUATORS.index("right_knee")
    one_leg = body.statics(single_support(body, q, "right"), "right").efforts
    both = body.statics(q, "double").efforts
    limits = effort_limits(VALKYRIE)
    assert abs(one_leg[knee]) / limits[knee] == pytest.approx(0.445, abs=0.002)
    assert abs(both[knee]) / limits[knee] == pytest.approx(0.273, abs=0.002)
    bank = datasheet_bank(VALKYRIE, ambient_C=25.0, scenario=walking)
    rise_K = bank.betaR_K_per_effort2 * one_leg**2
    assert ACTUATORS[int(np.argmax(rise_K))] == "right_knee"
    runner_up = np.sort(rise_K)[-2]
    assert runner_up < 0.5 * rise_K[knee]
    time_to_warning_s = bank.RC_s[knee] * np.log(rise_K[knee] / (rise_K[knee] - (LIMITS.warning_C - 25.0)))
    assert time_to_warning_s == pytest.approx(TIME_TO_WARNING_S, rel=0.05)


def test_scenarios_are_checked_and_the_default_is_the_uniform_rule():
    from humanoid_pb.scenarios import UNIFORM, Scenario, scenario
    from humanoid_pb.thermal import actuator_specs

    assert actuator_specs(VALKYRIE) == actuator_specs(VALKYRIE, "ankle")
    assert dict(scenario("ankle").continuous_fraction) == dict(UNIFORM)
    with pytest.raises(ValueError, match="no humanoid scenario 'squat'; expected one of ankle, walking"):
        scenario("squat")
    with pytest.raises(ValueError, match="no continuous fraction for actuator type"):
        Scenario("x", 0.3, 10.0, {"linear": 0.3}, "")
    with pytest.raises(ValueError, match="crouch depth"):
        Scenario("x", 1.5, 10.0, UNIFORM, "")


@pytest.mark.parametrize("group", ["ankle rods", "knee", "hip pitch", "hip roll", "torso"])
@pytest.mark.parametrize("depth", [0.15, 0.3, 0.45])
def test_a_switching_map_cell_makes_its_group_the_hottest_at_the_warning(body, group, depth):
    """The map's sizing rule: heating on the right leg (first order, Eq. 5 on the cell's datasheet models) brings
    one of the group's actuators to 75 degC first, in the time asked for, every other actuator well below."""
    from humanoid_pb.experiments.switching_map import GROUPS, map_scenario, stance_fractions
    from humanoid_pb.model.actuation import effort_limits
    from humanoid_pb.thermal import datasheet_bank

    sc = map_scenario(group, depth, body, time_to_warning_s=60.0)
    bank = datasheet_bank(VALKYRIE, scenario=sc)
    limits = effort_limits(VALKYRIE)
    steady = bank.equilibrium_C(stance_fractions(body, depth) * limits)
    at_60_s = steady + (25.0 - steady) * np.exp(-60.0 / bank.RC_s)
    inside = np.array([a in GROUPS[group] for a in ACTUATORS])
    assert at_60_s[inside].max() == pytest.approx(75.0, abs=0.05)
    assert at_60_s[~inside].max() == pytest.approx(50.0, abs=0.05)  # the most loaded other: half the heat


def test_the_switching_map_refuses_unknown_groups_and_depths(body):
    from humanoid_pb.experiments.switching_map import map_scenario

    with pytest.raises(ValueError, match="no actuator group 'elbow'; expected one of ankle rods, knee"):
        map_scenario("elbow", 0.3, body)
    with pytest.raises(ValueError, match="stance depth 0.6 rad is outside 0.15-0.45 rad"):
        map_scenario("knee", 0.6, body)


def test_switching_map_predictions_fill_in_only_where_they_meet_the_measurements():
    """A group's predictions are shown only if they meet every measured cell of it within 10 %; a cell where
    minimum effort had not recovered by the end agrees only with a prediction at least its bound."""
    from humanoid_pb.experiments.switching_map import Cell, agreeing_groups

    def cell(group, depth, source, ta, me, watched=None):
        return Cell(group, depth, source, {"thermal_aware": ta, "minimum_effort": me}, {},
                    {"thermal_aware": False, "minimum_effort": False}, 90.0, watched)

    predicted = {("knee", 0.3): cell("knee", 0.3, "first order", 4.0, 4.4),  # 1.10
                 ("knee", 0.45): cell("knee", 0.45, "first order", 4.0, 4.0),  # 1.00
                 ("hip pitch", 0.3): cell("hip pitch", 0.3, "first order", 4.0, None)}  # never: inf
    close = [cell("knee", 0.3, "measured", 10.0, 10.5), cell("knee", 0.45, "measured", 10.0, 10.2)]  # 1.05, 1.02
    assert agreeing_groups(close, predicted) == {"knee": True}
    far = [cell("knee", 0.3, "measured", 10.0, 13.0)]  # 1.30 against 1.10
    assert agreeing_groups(far, predicted) == {"knee": False}
    bound = [cell("hip pitch", 0.3, "measured", 10.0, None, watched=80.0)]  # at least 8
    assert bound[0].ratio is None and bound[0].ratio_at_least == pytest.approx(8.0)
    assert agreeing_groups(bound, predicted) == {"hip pitch": True}
    fell = Cell("knee", 0.3, "measured", {"thermal_aware": 10.0, "minimum_effort": 10.5}, {},
                {"thermal_aware": True, "minimum_effort": False}, 90.0)
    assert fell.ratio is None and agreeing_groups([fell], predicted) == {"knee": False}
