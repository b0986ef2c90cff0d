"""Thermal IK: the potential falls, contacts stay fixed; thermal-aware and minimum-effort choices (Eq. 33)."""

import numpy as np
import pytest

from humanoid_pb.actuators import datasheet_bank, effort_limits
from humanoid_pb.constants import ACTUATORS, CONTACT_MODES, JOINTS, leg_actuators
from humanoid_pb.descent import naive_descent, potential_of
from humanoid_pb.params import VALKYRIE
from humanoid_pb.potential import MinimumEffort, ThermalPotential
from humanoid_pb.statics import WholeBody


@pytest.fixture(scope="module")
def body():
    return WholeBody()


@pytest.fixture(scope="module")
def q0(body):
    from humanoid_pb.poses import crouch_angles, standing

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
    from humanoid_pb.planner import best_mode

    def choose(potential):  # Eq. 33 over the seed's descent from one start
        return best_mode({m: naive_descent(body, q0, m, potential, max_iter=40) for m in CONTACT_MODES})

    limits = effort_limits(VALKYRIE)
    effort = choose(MinimumEffort(limits))
    cool = choose(ThermalPotential.from_measurement(bank(), np.full(len(ACTUATORS), 40.0)))
    hot = choose(ThermalPotential.from_measurement(bank(), hot_right_leg()))
    # as the seed observes: with equal temperatures the thermal minimiser coincides with minimum effort...
    assert cool == effort == "double"
    # ...and with a hot right leg it leans on the left leg
    assert hot == "left"


@pytest.mark.parametrize("mode", CONTACT_MODES)
def test_fast_ik_keeps_contacts_exact_and_is_never_worse_than_the_seeds_descent(body, mode):
    from humanoid_pb.fast_ik import FastThermalIK
    from humanoid_pb.poses import crouch_angles, single_support, standing

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
    """The seed's final form runs one bounded step (Eqs. 30-32) per control step: iterated, it is the descent."""
    from humanoid_pb.descent import descent_step

    pot = ThermalPotential.from_measurement(bank(), hot_right_leg())
    whole = naive_descent(body, q0, "left", pot, max_iter=12)
    q, f = q0.copy(), potential_of(body, q0, "left", pot)
    for _ in range(12):
        q, f, moved = descent_step(body, q, "left", pot, f)
        assert moved
    np.testing.assert_array_equal(q, whole.q)
    assert f == whole.potential < potential_of(body, q0, "left", pot)
