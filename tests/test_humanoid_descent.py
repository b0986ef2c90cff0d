"""Thermal IK: the potential falls, contacts stay fixed; thermal-aware and minimum-effort choices (Eq. 33)."""

import numpy as np
import pytest

from humanoid_pb.constants import ACTUATORS, CONTACT_MODES, JOINTS, leg_actuators
from humanoid_pb.ik.descent import naive_descent, potential_of
from humanoid_pb.ik.potential import MinimumEffort, ThermalPotential
from humanoid_pb.model.actuation import effort_limits
from humanoid_pb.model.statics import WholeBody
from humanoid_pb.params import VALKYRIE
from humanoid_pb.thermal import datasheet_bank


@pytest.fixture(scope="module")
def body():
    return WholeBody()


@pytest.fixture(scope="module")
def q0(body):
    from humanoid_pb.ik.poses import crouch_angles, standing

    return standing(body, crouch_angles())


def bank():
    return datasheet_bank(VALKYRIE)


def hot_right_leg(temperature=78.0):
    T = np.full(len(ACTUATORS), 40.0)
    for a in leg_actuators("right"):
        T[ACTUATORS.index(a)] = temperature
    return T


@pytest.mark.parametrize("mode", CONTACT_MODES)
def test_descent_lowers_the_potential_and_keeps_contacts_fixed(body, q0, mode):
    pot = ThermalPotential.from_measurement(bank(), hot_right_leg())
    result = naive_descent(body, q0, mode, pot, max_iter=40)
    assert potential_of(body, result.q, mode, pot) == pytest.approx(result.potential, rel=1e-9)
    assert result.potential < potential_of(body, q0, mode, pot)  # lower at the returned configuration than at the start
    assert result.contact_drift_m < 2e-3  # first-order null-space steps: mm-level drift (m)


def test_thermal_aware_and_minimum_effort_agree_when_cool_and_differ_when_one_leg_is_hot(body, q0):
    from humanoid_pb.control.planner import best_mode

    def choose(potential):  # Eq. 33 over Jorgensen et al.'s descent from one start
        return best_mode({m: naive_descent(body, q0, m, potential, max_iter=40) for m in CONTACT_MODES})

    limits = effort_limits(VALKYRIE)
    effort = choose(MinimumEffort(limits))
    cool = choose(ThermalPotential.from_measurement(bank(), np.full(len(ACTUATORS), 40.0)))
    hot = choose(ThermalPotential.from_measurement(bank(), hot_right_leg()))
    # as Jorgensen et al. observe: with equal temperatures the thermal minimiser coincides with minimum effort...
    assert cool == effort == "double"
    # ...and with a hot right leg it leans on the left leg
    assert hot == "left"


@pytest.mark.parametrize("mode", CONTACT_MODES)
def test_fast_ik_keeps_contacts_exact_and_is_never_worse_than_the_seeds_descent(body, mode):
    from humanoid_pb.ik.fast_ik import FastThermalIK
    from humanoid_pb.ik.poses import crouch_angles, single_support, standing

    q_double = standing(body, crouch_angles())
    start = q_double if mode == "double" else single_support(body, q_double, mode)
    pot = ThermalPotential.from_measurement(bank(), hot_right_leg())
    naive = naive_descent(body, start, mode, pot, max_iter=300)
    fast = FastThermalIK(body).solve(start, mode, pot)
    assert fast.potential <= naive.potential * (1 + 1e-9)  # its own objective: balancing torques chosen freely
    if mode != "double":  # one support: Eq. 23's Gamma(q) is the only balance, so the comparison is like for like
        assert potential_of(body, fast.q, mode, pot) == pytest.approx(fast.potential, rel=1e-9)
    assert fast.contact_drift_m < 1e-8  # m: the contacts are held exactly, not to first order
    # the torques balance gravity with the wrenches found, which respect the contact constraints
    Jc = body.contact_jacobian(fast.q, mode)
    np.testing.assert_allclose(body.S_a.T @ fast.torques_Nm + Jc.T @ fast.contact_wrenches.ravel(),
                               body.gravity(fast.q), atol=1e-5)
    w = fast.contact_wrenches
    lx, ly = np.array(VALKYRIE.sole_m) / 2
    assert np.all(w[:, 2] > 0)  # unilateral
    assert np.all(np.abs(w[:, 3]) <= ly * w[:, 2] + 1e-6) and np.all(np.abs(w[:, 4]) <= lx * w[:, 2] + 1e-6)  # CoP in the sole
    angles = body.joint_angles(fast.q)
    limits = np.array([VALKYRIE.limits(j) for j in JOINTS])
    assert np.all(angles >= limits[:, 0] - 1e-6) and np.all(angles <= limits[:, 1] + 1e-6)


def test_one_step_per_control_tick_retraces_the_descent(body, q0):
    """Jorgensen et al.'s final form runs one bounded step (Eqs. 30-32) per control step: iterated, it is the descent."""
    from humanoid_pb.ik.descent import descent_step

    pot = ThermalPotential.from_measurement(bank(), hot_right_leg())
    whole = naive_descent(body, q0, "left", pot, max_iter=12)
    q, f = q0.copy(), potential_of(body, q0, "left", pot)
    for _ in range(12):
        q, f, moved = descent_step(body, q, "left", pot, f)
        assert moved
    np.testing.assert_array_equal(q, whole.q)
    assert f == whole.potential < potential_of(body, q0, "left", pot)


@pytest.mark.parametrize("mode", CONTACT_MODES)
def test_eq23_torques_are_the_minimum_norm_balance(body, q0, mode):
    """Eq. 23's Gamma(q) (mass matrix, two pseudo-inverses) equals the least-norm torque that balances gravity
    with free contact wrenches, and the like-for-like mode's analytic derivative matches finite differences."""
    import pinocchio as pin

    from humanoid_pb.ik.like_for_like import efforts_and_jacobian, min_norm_balance
    from humanoid_pb.ik.poses import single_support

    rng = np.random.default_rng(3)
    start = q0 if mode == "double" else single_support(body, q0, mode)
    for _ in range(3):
        q = pin.integrate(body.model, start, 0.05 * rng.standard_normal(body.nv))
        eq23 = body.statics(q, mode)
        Gamma, F, _, _ = min_norm_balance(body, q, mode)
        np.testing.assert_allclose(Gamma, eq23.torques_Nm, atol=1e-8)
        np.testing.assert_allclose(F.reshape(-1, 6), eq23.contact_wrenches, atol=1e-7)
        efforts, J = efforts_and_jacobian(body, q, mode)
        direction = rng.standard_normal(body.nv)
        h = 1e-6
        ahead = body.statics(pin.integrate(body.model, q, h * direction), mode).efforts
        behind = body.statics(pin.integrate(body.model, q, -h * direction), mode).efforts
        np.testing.assert_allclose(J @ direction, (ahead - behind) / (2 * h), rtol=1e-4,
                                   atol=1e-6 * np.max(np.abs(J @ direction)))


@pytest.mark.parametrize("seed", [0, 1])
def test_the_like_for_like_mode_ends_no_higher_than_the_descent_on_its_own_objective(body, q0, seed):
    """The descent's problem solved by the fast method's like-for-like mode, from the same start, on random
    temperature profiles in every mode: no higher under Eq. 23's Gamma(q), contacts held exactly, joints within
    the robot's limits."""
    from humanoid_pb.ik.fast_ik import FastThermalIK
    from humanoid_pb.ik.poses import single_support

    solver = FastThermalIK(body)
    pot = ThermalPotential.from_measurement(bank(), np.random.default_rng(seed).uniform(30.0, 85.0, len(ACTUATORS)))
    limits = np.array([VALKYRIE.limits(j) for j in JOINTS])
    for mode in CONTACT_MODES:
        start = q0 if mode == "double" else single_support(body, q0, mode)
        naive = naive_descent(body, start, mode, pot, max_iter=300)
        same = solver.solve(start, mode, pot, like_for_like=True)
        assert same.potential == pytest.approx(potential_of(body, same.q, mode, pot), rel=1e-9)
        assert same.potential <= naive.potential, mode
        assert same.contact_drift_m < 1e-8
        angles = body.joint_angles(same.q)
        assert np.all(angles >= limits[:, 0] - 1e-9) and np.all(angles <= limits[:, 1] + 1e-9)
        again = solver.solve(start, mode, pot, like_for_like=True)
        np.testing.assert_array_equal(again.q, same.q)
