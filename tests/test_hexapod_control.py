"""Hexapod: CPG, stance-wrench optimisation, walking in PyBullet, determinism."""

from dataclasses import replace

import numpy as np
import pytest

from hexapod_pb.constants import LEGS, TRIPODS
from hexapod_pb.control import cpg
from hexapod_pb.control.controller import ControllerState, Gains, ThermalContext, control_step
from hexapod_pb.control.minimax import minimax, minimax_lex
from hexapod_pb.control.nair import nair_trust_constr
from hexapod_pb.control.stance import StanceProblem, vertical_only
from hexapod_pb.control.thermal_minimax import thermal_minimax
from hexapod_pb.control.wrench import STRATEGIES, distribute
from hexapod_pb.model.kinematics import inverse_kinematics, nominal_foot
from hexapod_pb.params import DAISY, GRAVITY_M_S2
from hexapod_pb.sim import HexapodSim, SimConfig
from hexapod_pb.thermal import datasheet_bank

TRIPOD = tuple(LEGS.index(n) for n in TRIPODS[0])


def random_stance(rng):
    feet = [nominal_foot(DAISY, i) + np.r_[rng.uniform(-0.05, 0.05, 2), 0.0] for i in range(6)]
    return np.concatenate([inverse_kinematics(DAISY, i, feet[i]) for i in range(6)])


@pytest.mark.parametrize("seed", range(5))
def test_cpg_locks_into_the_tripod_from_any_start(seed):
    params = cpg.CPGParams()
    state = cpg.initial_state(np.random.default_rng(seed), params)
    for _ in range(500):
        state = cpg.step(state, params, 0.02)
    assert cpg.phase_locking_error(state) < 0.01  # rad
    stance = cpg.stance(state, params)
    assert len({bool(stance[LEGS.index(n)]) for n in TRIPODS[0]}) == 1


@pytest.mark.parametrize("seed", range(10))
def test_exact_minimax_equals_trust_constr_and_balances(seed):
    problem = StanceProblem.from_configuration(DAISY, random_stance(np.random.default_rng(seed)), TRIPOD,
                                               payload_kg=2.0, include_leg_gravity=False)
    exact = minimax(problem)
    nair_way = nair_trust_constr(problem)
    highs = minimax(problem, solver="highs")
    certificate = exact.residuals()
    assert certificate["equilibrium"] < 1e-8  # N and N m
    assert certificate["stationarity"] < 1e-9 and certificate["complementarity"] < 1e-9  # KKT: optimal
    assert exact.peak <= nair_way.peak + 1e-6  # never worse than Nair et al.'s solver
    assert exact.peak == pytest.approx(highs.peak, abs=1e-7)  # two exact solvers agree
    # trust-constr on the non-smooth max sometimes stops short (benchmarks/wrench.py counts how often);
    # started from the exact optimum it stays there: the LP optimum is its fixed point
    polished = nair_trust_constr(problem, x0=np.r_[exact.forces_N[:, 0], exact.forces_N[:, 1]])
    assert polished.peak == pytest.approx(exact.peak, abs=1e-6)
    assert exact.peak < vertical_only(problem).peak


@pytest.mark.parametrize("n_legs", [3, 4, 5, 6])
def test_friction_cones_and_unilateral_normals_hold_for_any_stance(n_legs):
    legs = {3: TRIPOD, 4: (0, 1, 4, 5), 5: (0, 1, 2, 4, 5), 6: tuple(range(6))}[n_legs]  # around the centre of mass
    problem = StanceProblem.from_configuration(DAISY, random_stance(np.random.default_rng(n_legs)), legs,
                                               payload_kg=5.0, friction=0.3, min_normal_N=5.0)
    for sol in (minimax(problem), minimax_lex(problem)):
        r = sol.residuals()
        assert r["equilibrium"] < 1e-6 and r["friction"] < 1e-6 and r["unilateral"] < 1e-6
    lex = minimax_lex(problem)
    assert lex.peak <= minimax(problem).peak * (1 + 1e-5)
    assert np.sum(problem.normalised(lex.forces_N) ** 2) <= np.sum(problem.normalised(minimax(problem).forces_N) ** 2) + 1e-9


def test_thermal_minimax_lowers_the_hottest_prediction():
    q = random_stance(np.random.default_rng(1))
    problem = StanceProblem.from_configuration(DAISY, q, TRIPOD, payload_kg=2.0)
    full = datasheet_bank()
    joints = np.concatenate([np.arange(3 * i, 3 * i + 3) for i in TRIPOD])

    bank = full.subset(joints)
    temperature = np.full(9, 40.0)
    temperature[1] = 90.0  # one shoulder already hot
    hot = thermal_minimax(problem, bank, temperature, 20.0)
    plain = minimax(problem)
    assert hot.residuals()["equilibrium"] < 1e-6 and hot.strategy == "thermal_aware" and hot.iterations >= 1
    assert np.max(bank.ahead(temperature, hot.torques_Nm, 20.0)) < np.max(bank.ahead(temperature, plain.torques_Nm, 20.0))


def walk(strategy, seconds=10.0, payload_kg=0.0, seed=0, gains=Gains(), rates=None):
    """The body's displacement, heights and path over a walk; ``rates`` (a list) gets the IMU's rates each step."""
    cfg = SimConfig(payload_kg=payload_kg)
    thermal = ThermalContext(datasheet_bank()) if strategy == "thermal_aware" else None
    gait = cpg.CPGParams()
    with HexapodSim(config=cfg, seed=seed) as sim:
        state = ControllerState(cpg.initial_state(None, gait))
        reading = sim.read()
        for _ in range(25):  # settle standing
            tau, state, _ = control_step(reading, state, DAISY, gait, strategy, cfg.control_dt_s, payload_kg,
                                         gains, thermal=thermal, walking=False)
            reading = sim.step(tau)
        start = reading.body_position_m.copy()
        heights, path = [], []
        for _ in range(int(seconds * cfg.control_hz)):
            tau, state, _ = control_step(reading, state, DAISY, gait, strategy, cfg.control_dt_s, payload_kg,
                                         gains, thermal=thermal)
            reading = sim.step(tau)
            heights.append(reading.body_position_m[2])
            path.append(reading.body_position_m.copy())
            if rates is not None:
                rates.append(reading.body_omega_rad_s.copy())
        return reading.body_position_m - start, np.array(heights), np.array(path)


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_each_strategy_walks_forward_without_falling(strategy):
    moved, heights, _ = walk(strategy)
    # the CPG asks for 0.104 m/s; feet slip a little: at least 0.5 m in 10 s, straight, body never low
    assert moved[0] > 0.5 and abs(moved[1]) < 0.1
    assert heights.min() > 0.10


def test_a_stiffer_attitude_damping_makes_the_body_yaw_run_away():
    """Why Gains.attitude_kd_Nm_s_rad is 5: at 50 N m s/rad and 50 Hz the attitude loop rings.  What is asserted is
    the growth over the first second, not where the chaotic walk ends (its sideways drift after 4 s is 0.60 m or
    1.35 m depending on the BLAS kernel; the first second's yaw rate is the same to six digits): measured 2.2 rad/s
    RMS against 0.005 rad/s."""
    rates = {5.0: [], 50.0: []}
    for kd, r in rates.items():
        walk("minimax", seconds=1.0, gains=replace(Gains(), attitude_kd_Nm_s_rad=kd), rates=r)
    yaw = {kd: float(np.sqrt(np.mean(np.array(r)[:, 2] ** 2))) for kd, r in rates.items()}
    assert yaw[50.0] > 100 * yaw[5.0] and yaw[50.0] > 0.5, yaw


def test_two_fresh_worlds_with_the_same_seed_give_identical_trajectories():
    _, _, one = walk("minimax", seconds=2.0, seed=3)
    _, _, two = walk("minimax", seconds=2.0, seed=3)
    np.testing.assert_array_equal(one, two)


def test_a_run_writes_a_canonical_log_that_fit_reads(tmp_path):
    from hexapod_pb.constants import JOINTS
    from hexapod_pb.experiments.load_carrying import run_scenario
    from thermolimb.logs import read_log

    result = run_scenario("stand_5kg", "minimax", 4.0)
    path = result.log.write(tmp_path / "hexapod.csv")
    log = read_log(path)
    assert log.actuators == JOINTS
    shoulder = log.series("left_middle_shoulder")
    # efforts are the torques applied after derating; readings are the plant's quantised temperatures
    assert shoulder.signals.effort.std() > 0 and np.allclose(shoulder.temperature_C * 10, np.round(shoulder.temperature_C * 10))
    assert shoulder.signals.velocity is not None and shoulder.signals.ambient_C is not None


@pytest.mark.parametrize("seed", range(3))
def test_every_solver_balances_the_wrench_it_was_given(seed):
    """Each solver's forces meet the net wrench (Nair et al.'s trust-constr its three equalities), and each reports
    a positive solve time."""
    problem = StanceProblem.from_configuration(DAISY, random_stance(np.random.default_rng(seed)), TRIPOD,
                                               payload_kg=2.0, include_leg_gravity=False)
    problem = replace(problem, wrench=problem.wrench + np.r_[4.0, -3.0, 0.0, 0.0, 0.0, 1.5])  # pushing and turning
    nair_way = nair_trust_constr(problem)
    # Nair et al.'s equalities are the horizontal forces and the yaw moment (its normals come from statics, which
    # leave the horizontal forces' roll and pitch moments unbalanced: its approximation)
    error = problem.equilibrium @ nair_way.forces_N.ravel() - problem.wrench
    assert np.max(np.abs(error[[0, 1, 5]])) < 1e-6
    for sol in (minimax(problem, solver="highs"), minimax(problem), minimax_lex(problem)):
        assert sol.residuals()["equilibrium"] < 1e-6, sol.solver
    for sol in (nair_way, minimax(problem, solver="highs"), minimax(problem), minimax_lex(problem)):
        assert 0.0 < sol.solve_time_s < 5.0, sol.solver
    assert minimax_lex(problem).label == "minimax_lex by daqp" and minimax(problem, solver="highs").solver == "highs"


def test_the_default_wrench_carries_robot_and_payload():
    q = random_stance(np.random.default_rng(0))
    light = StanceProblem.from_configuration(DAISY, q, TRIPOD, payload_kg=0.0)
    heavy = StanceProblem.from_configuration(DAISY, q, TRIPOD, payload_kg=5.0)
    assert light.wrench[2] == pytest.approx(DAISY.robot_weight_N)
    assert heavy.wrench[2] - light.wrench[2] == pytest.approx(5.0 * GRAVITY_M_S2)
    np.testing.assert_array_equal(heavy.wrench[[0, 1, 3, 4, 5]], 0.0)
    assert heavy.wrench.dtype == float and vertical_only(heavy).forces_N[:, 2].sum() == pytest.approx(heavy.wrench[2])
    with pytest.raises(ValueError, match="at least 3 feet on the ground, got 2"):
        StanceProblem.from_configuration(DAISY, q, (0, 1), payload_kg=0.0)


@pytest.mark.parametrize("push", [np.r_[-60.0, 0.0], np.r_[0.0, -60.0], np.r_[60.0, 0.0], np.r_[0.0, 60.0]])
def test_friction_pyramid_holds_in_every_direction(push):
    """A horizontal push either way along either axis: every foot's force stays inside its pyramid."""
    q = random_stance(np.random.default_rng(3))
    problem = StanceProblem.from_configuration(DAISY, q, TRIPOD, payload_kg=2.0, friction=0.3, min_normal_N=5.0)
    problem = replace(problem, wrench=problem.wrench + np.r_[push, 0.0, 0.0, 0.0, 0.0])
    for sol in (minimax(problem), minimax_lex(problem)):
        f = sol.forces_N
        assert np.all(np.abs(f[:, :2]) <= 0.3 * f[:, 2:3] + 1e-6), sol.solver
        assert sol.residuals()["equilibrium"] < 1e-6


def test_a_stalled_dual_active_set_falls_back_to_highs_with_the_same_optimum(monkeypatch):
    """The named fallback, reached by making daqp report a stall: HiGHS meets the same equalities and the same
    optimum (the LP's value; its minimiser need not be unique), the label says so, and both certify optimality."""
    import daqp

    from thermolimb.optimization.programs import SolverError, solve

    problem = StanceProblem.from_configuration(DAISY, random_stance(np.random.default_rng(1)), TRIPOD,
                                               payload_kg=2.0, include_leg_gravity=False)
    lp = problem.minimax_program
    by_daqp = solve(lp, "daqp", fallback="highs", eps_prox=1e-6)
    assert by_daqp.solver == "daqp"
    monkeypatch.setattr(daqp, "solve", lambda *args, **kwargs: (None, None, -2, {}))
    by_highs = solve(lp, "daqp", fallback="highs")
    assert by_highs.solver == "highs" and by_highs.fallback_from == "daqp stalled, exit flag -2"  # said
    assert by_highs.label == "highs (daqp stalled, exit flag -2)"
    with pytest.raises(SolverError, match="daqp could not solve the stance LP"):
        solve(lp, "daqp")  # and never taken unless named
    assert lp.cost @ by_highs.x == pytest.approx(lp.cost @ by_daqp.x, rel=1e-6)
    np.testing.assert_allclose(lp.A[:6] @ by_highs.x, lp.upper[:6], atol=1e-6)  # the wrench, balanced
    for found in (by_daqp, by_highs):
        r = found.residuals
        assert r["bounds"] < 1e-6 and r["stationarity"] < 1e-8 and r["complementarity"] < 1e-8, r
        assert abs(r["duality_gap"]) < 1e-8, r


def test_every_program_certifies_its_optimum_and_a_wrong_point_fails_the_certificate():
    """Each solved program's residuals hold at the optimum (LP by both solvers, the smoothed and second-stage
    QPs by daqp), and the certificate rejects a feasible point that is not optimal (so the check can fail)."""
    problem = StanceProblem.from_configuration(DAISY, random_stance(np.random.default_rng(4)), TRIPOD,
                                               payload_kg=5.0, friction=0.5, min_normal_N=5.0)
    solutions = [minimax(problem), minimax(problem, solver="highs"), minimax_lex(problem),
                 minimax(problem, smoothing_1_N2=1e-3, previous_N=vertical_only(problem).forces_N)]
    for sol in solutions:
        r = sol.residuals()
        assert r["equilibrium"] < 1e-6 and r["bounds"] < 1e-6, (sol.solver, r)
        assert r["stationarity"] < 1e-6 and abs(r["duality_gap"]) < 1e-6, (sol.solver, r)
    lp, exact = problem.minimax_program, solutions[0].program
    worse = exact.x.copy()
    worse[-1] += 0.1  # a larger peak bound: still feasible, not optimal
    r = lp.residuals(worse, exact.duals)
    assert r["bounds"] < 1e-9 and r["duality_gap"] > 0.09




def test_a_blend_solves_each_program_once_and_says_what_solved_each_part(monkeypatch):
    """Blending minimax, its second stage and the thermal minimax solves the closest-wrench LP once and the torque
    minimax LP once (shared as the others' first point); the blend keeps each part's solver."""
    import hexapod_pb.control.minimax as minimax_module
    import hexapod_pb.control.thermal_minimax as thermal_module
    from thermolimb.optimization.programs import solve

    solved = []

    def counted(program, *args, **kwargs):  # the real solver, each call's program named
        solved.append(program.name)
        return solve(program, *args, **kwargs)

    monkeypatch.setattr(minimax_module, "solve", counted)
    monkeypatch.setattr(thermal_module, "solve", counted)
    q = random_stance(np.random.default_rng(2))
    problem = StanceProblem.from_configuration(DAISY, q, TRIPOD, payload_kg=2.0, friction=0.6, min_normal_N=2.0)
    bank = datasheet_bank(ambient_C=25.0).subset(np.arange(18))
    blend = distribute(problem, {"minimax": 0.5, "minimax_lex": 0.3, "thermal_aware": 0.2}, bank=bank,
                       temperature_C=np.full(18, 40.0), solver="daqp", fallback="highs")
    assert solved.count("the closest achievable wrench's LP") == 1
    assert solved.count("the stance LP") == 1
    assert [part.strategy for part in blend.parts] == ["minimax", "minimax_lex", "thermal_aware"]
    assert blend.label == "minimax by daqp; minimax_lex by daqp; thermal_aware by daqp" and not blend.fell_back
    assert blend.residuals()["equilibrium"] < 1e-6  # a convex combination of balanced distributions


def test_a_stalled_solver_falls_back_only_when_named_and_the_step_says_so(monkeypatch):
    """The controller names daqp and HiGHS: a stall reaches the solution's label; without a fallback it raises."""
    import daqp

    from thermolimb.optimization.programs import SolverError

    problem = StanceProblem.from_configuration(DAISY, random_stance(np.random.default_rng(4)), TRIPOD,
                                               payload_kg=2.0, friction=0.6, min_normal_N=2.0)
    monkeypatch.setattr(daqp, "solve", lambda *args, **kwargs: (None, None, -2, {}))
    found = distribute(problem, "minimax", smoothing_1_N2=1e-3, solver="daqp", fallback="highs")
    assert found.solver == "highs" and found.fell_back
    assert found.label == "minimax by highs (daqp stalled, exit flag -2 on the smoothed QP)"
    with pytest.raises(SolverError):
        distribute(problem, "minimax", solver="daqp", fallback=None)
