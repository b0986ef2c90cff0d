"""Hexapod model and kinematics, cross-checked against PyBullet's link states and Jacobians."""

import numpy as np
import pytest

from hexapod_pb.constants import JOINTS, LEGS
from hexapod_pb.model.daisy_urdf import generate, urdf_path
from hexapod_pb.model.kinematics import UnreachableError, foot_jacobian, foot_position, inverse_kinematics
from hexapod_pb.model.legs import leg_gravity_torque, leg_mass_matrix
from hexapod_pb.params import DAISY, DaisyParams
from hexapod_pb.sim import HexapodSim, SimConfig


@pytest.fixture(scope="module")
def hung_sim():
    sim = HexapodSim(config=SimConfig(fixed_base=True))
    yield sim
    sim.close()


def test_committed_urdf_matches_the_generator():
    assert urdf_path().read_text() == generate(), "run: python -m hexapod_pb.model.daisy_urdf"


def test_robot_weighs_about_210_newtons():
    # Nair et al.: 75 N body + 135 N legs
    assert DAISY.robot_weight_N == pytest.approx(210.0, abs=0.5)


@pytest.mark.parametrize("trial", range(3))
def test_forward_kinematics_and_jacobian_match_pybullet(hung_sim, trial):
    rng = np.random.default_rng(trial)
    q = hung_sim.stance_angles() + rng.uniform(-0.3, 0.3, len(JOINTS))
    hung_sim.reset_stance(q)
    body_pos, world_R_body = hung_sim.body_pose()
    feet = hung_sim.foot_positions_world()
    for leg in range(len(LEGS)):
        qi = q[3 * leg : 3 * leg + 3]
        # PyBullet works in single precision (~1e-7 relative on metre-sized numbers): 1e-5 m, 1e-5 m/rad
        np.testing.assert_allclose(body_pos + world_R_body @ foot_position(DAISY, leg, qi), feet[leg], atol=1e-5)
        np.testing.assert_allclose(world_R_body @ foot_jacobian(DAISY, leg, qi), hung_sim.foot_jacobian_world(leg),
                                   atol=1e-5)


@pytest.mark.parametrize("trial", range(2))
def test_leg_mass_matrix_and_gravity_torque_match_pybullet(hung_sim, trial):
    """The controller's point-mass-plus-inertia leg model against PyBullet's dynamics of the URDF (legs hung)."""
    rng = np.random.default_rng(10 + trial)
    q = hung_sim.stance_angles() + rng.uniform(-0.3, 0.3, len(JOINTS))
    hung_sim.reset_stance(q)
    M, g = hung_sim.joint_space_dynamics()
    _, world_R_body = hung_sim.body_pose()
    for leg in range(len(LEGS)):
        sl = slice(3 * leg, 3 * leg + 3)
        np.testing.assert_allclose(leg_gravity_torque(DAISY, leg, q[sl], world_R_body), g[sl], atol=1e-4)
        np.testing.assert_allclose(leg_mass_matrix(DAISY, leg, q[sl]), M[sl, sl], atol=1e-4)
        assert np.abs(np.delete(M[sl], np.arange(3 * leg, 3 * leg + 3), axis=1)).max() < 1e-9  # legs are decoupled


def test_inverse_kinematics_round_trip_and_finite_differences():
    rng = np.random.default_rng(4)
    for leg in range(len(LEGS)):
        q = np.array([0.0, 0.3, -1.2]) + rng.uniform(-0.4, 0.4, 3)
        np.testing.assert_allclose(inverse_kinematics(DAISY, leg, foot_position(DAISY, leg, q)), q, atol=1e-10)
        h = 1e-7
        numeric = np.column_stack([(foot_position(DAISY, leg, q + h * e) - foot_position(DAISY, leg, q - h * e)) / (2 * h)
                                   for e in np.eye(3)])
        np.testing.assert_allclose(foot_jacobian(DAISY, leg, q), numeric, atol=1e-7)


def test_unreachable_target_and_impossible_parameters():
    with pytest.raises(UnreachableError, match="out of reach"):
        inverse_kinematics(DAISY, 0, np.array([2.0, 0.0, 0.0]))
    with pytest.raises(ValueError, match="more than the leg's"):
        DaisyParams(nominal_foot_reach_m=0.7)
    with pytest.raises(ValueError, match="whole multiple"):
        SimConfig(physics_hz=500.0, control_hz=60.0)
