"""Thermal IK per contact mode: Jorgensen et al.'s naive descent against the fast method, from the same start.

For each mode: the wall time of each method (one warm-up solve, then the best
of three, for both), their ratio, the final potential of each on the same
objective (the fast configuration scored with Eq. 23's single Gamma(q), as the
descent scores its own), apart from it what the fast method's free choice of
balancing torques and force split reaches, and the constraint violations of
the fast result (contacts, equilibrium, unilateral normals, centre of
pressure, joint limits).  Also Jorgensen et al.'s final form: one descent step (Eqs.
30-32, bounded by delta_max) per control step, timed alike, with the number of
control steps the descent needs.  A hot right leg (78 degC) sets the potential's weights.

The fast method's like-for-like mode (``like_for_like=True``: the descent's
own problem, Eq. 23's torques with only the contacts and joint limits held,
by Gauss-Newton on analytic derivatives) is timed and scored alike.

Then, so that the headline is not one start's luck, twenty seeded random
temperature profiles (30-85 degC) in every mode, timed alike: the spread of
each fast mode's time, of the speed-up and of the potential ratio, and the
like-for-like mode's worst ratio to the descent.

    python benchmarks/thermal_ik.py [--json] [--profiles N]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from humanoid_pb.constants import ACTUATORS, CONTACT_MODES, JOINTS, leg_actuators
from humanoid_pb.ik.descent import descent_step, naive_descent, potential_of
from humanoid_pb.ik.fast_ik import FastThermalIK
from humanoid_pb.ik.poses import crouch_angles, single_support, standing
from humanoid_pb.ik.potential import ThermalPotential
from humanoid_pb.model.statics import WholeBody
from humanoid_pb.params import VALKYRIE
from humanoid_pb.thermal import datasheet_bank


def best_of(solve, repeats: int = 3):
    """The fastest of ``repeats`` solves after one warm-up (caches, first-call costs)."""
    solve()
    return min((solve() for _ in range(repeats)), key=lambda r: r.wall_s)


def _step_time(body: WholeBody, q, mode, potential, repeats: int = 3) -> float:
    """One descent step (Eqs. 30-32), timed like the solvers: a warm-up, then the best of ``repeats``."""
    descent_step(body, q, mode, potential)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        descent_step(body, q, mode, potential)
        times.append(time.perf_counter() - start)
    return min(times)


def violations(body: WholeBody, q0, result, mode) -> dict[str, float]:
    Jc = body.contact_jacobian(result.q, mode)
    w = result.contact_wrenches
    lx, ly = np.array(VALKYRIE.sole_m) / 2
    angles = body.joint_angles(result.q)
    limits = np.array([VALKYRIE.limits(j) for j in JOINTS])
    return {
        "contact_m": result.contact_drift_m,
        "equilibrium": float(np.max(np.abs(body.S_a.T @ result.torques_Nm + Jc.T @ w.ravel() - body.gravity(result.q)))),
        "unilateral_N": float(max(0.0, -w[:, 2].min())),
        "cop_m": float(max(0.0, np.max(np.abs(w[:, 3]) / w[:, 2] - ly), np.max(np.abs(w[:, 4]) / w[:, 2] - lx))),
        "joint_limits_rad": float(max(0.0, np.max(limits[:, 0] - angles), np.max(angles - limits[:, 1]))),
    }


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    parser.add_argument("--profiles", type=int, default=20, help="random temperature profiles timed (default 20)")
    args = parser.parse_args(argv)
    body = WholeBody()
    q_double = standing(body, crouch_angles())
    T = np.full(len(ACTUATORS), 40.0)
    for a in leg_actuators("right"):
        T[ACTUATORS.index(a)] = 78.0
    potential = ThermalPotential.from_measurement(datasheet_bank(VALKYRIE), T)
    fast_solver = FastThermalIK(body, solver="daqp")
    record = {"modes": {}}
    for mode in CONTACT_MODES:
        start = q_double if mode == "double" else single_support(body, q_double, mode)
        # both methods timed alike: one warm-up solve, then the best of three
        naive = best_of(lambda: naive_descent(body, start, mode, potential, max_iter=300))
        fast = best_of(lambda: fast_solver.solve(start, mode, potential))
        same_mode = best_of(lambda: fast_solver.solve(start, mode, potential, like_for_like=True))
        step_s = _step_time(body, start, mode, potential)
        v = violations(body, start, fast, mode)
        # like for like: the fast configuration scored as the descent scores it, with Eq. 23's single Gamma(q)
        same = potential_of(body, fast.q, mode, potential)
        record["modes"][mode] = {"naive_s": naive.wall_s, "fast_s": fast.wall_s, "speedup": naive.wall_s / fast.wall_s,
                                 "naive_potential": naive.potential, "fast_potential": same,
                                 "fast_free_potential": fast.potential, "step_s": step_s,
                                 "steps_to_converge": naive.iterations,
                                 "naive_contact_drift_m": naive.contact_drift_m, "fast_violations": v,
                                 "like_for_like_s": same_mode.wall_s, "like_for_like_potential": same_mode.potential,
                                 "like_for_like_speedup": naive.wall_s / same_mode.wall_s,
                                 "fast_solver": fast.solver, "fast_qp_failures": len(fast.qp_failures)}
        print(f"{mode:7s} naive {naive.wall_s * 1e3:7.0f} ms ({naive.iterations} it) potential {naive.potential:10.0f} "
              f"| fast {fast.wall_s * 1e3:6.1f} ms ({fast.iterations} it) potential {same:10.0f} with Gamma(q), "
              f"{fast.potential:10.0f} with its own torques and forces "
              f"| speed-up {naive.wall_s / fast.wall_s:5.1f} x (target >= 40 x)")
        print(f"        like for like (Eq. 23's torques, contacts and joint limits only): {same_mode.wall_s * 1e3:.1f} ms "
              f"({same_mode.iterations} it), potential {same_mode.potential:10.0f} = "
              f"{same_mode.potential / naive.potential:.4f} of the descent's, speed-up "
              f"{naive.wall_s / same_mode.wall_s:5.1f} x")
        print(f"        Jorgensen et al.'s final form, one descent step per control step: {step_s * 1e3:.1f} ms per step "
              f"({'fits' if step_s <= 0.01 else 'does not fit'} a 100 Hz loop), {naive.iterations} steps = "
              f"{naive.iterations / 100:.2f} s of control at 100 Hz to reach the descent's end")
        print(f"        naive contact drift {naive.contact_drift_m * 1e3:.2f} mm; fast violations "
              + ", ".join(f"{k} {val:.1e}" for k, val in v.items()))
        print(f"        fast QPs solved by {fast.solver}; {len(fast.qp_failures)} not solved (steps rejected, the trust "
              f"region halved)" + (f": {fast.qp_failures[0]}" if fast.qp_failures else ""))
    record["profiles"] = _profiles(body, q_double, fast_solver, args.profiles)
    if args.json:
        print(json.dumps({"modes": {m: {k: r[k] for k in ("naive_s", "fast_s", "speedup", "naive_potential",
                                                           "fast_potential", "like_for_like_s",
                                                           "like_for_like_potential", "like_for_like_speedup")}
                                    for m, r in record["modes"].items()},
                          "profiles": record["profiles"]}))
    return record


def _profiles(body: WholeBody, q_double, fast_solver: FastThermalIK, count: int, seed: int = 0) -> dict:
    """Both methods, and the fast method's like-for-like mode, on ``count`` random temperature profiles in every
    mode, timed alike."""
    rng = np.random.default_rng(seed)
    runs = {"free": ([], [], []), "like_for_like": ([], [], [])}  # times, speed-ups, potential ratios
    for _ in range(count):
        potential = ThermalPotential.from_measurement(datasheet_bank(VALKYRIE),
                                                      rng.uniform(30.0, 85.0, len(ACTUATORS)))
        for mode in CONTACT_MODES:
            start = q_double if mode == "double" else single_support(body, q_double, mode)
            naive = best_of(lambda: naive_descent(body, start, mode, potential, max_iter=300))
            for name, (times, speedups, ratios) in runs.items():
                fast = best_of(lambda: fast_solver.solve(start, mode, potential, like_for_like=name != "free"))
                times.append(fast.wall_s)
                speedups.append(naive.wall_s / fast.wall_s)
                ratios.append(potential_of(body, fast.q, mode, potential) / naive.potential)
    summary = {}
    for name, (times, speedups, ratios) in runs.items():
        summary[name] = {"solves": len(times), "fast_s": _spread(times), "speedup": _spread(speedups),
                         "potential_ratio_same_objective": _spread(ratios)}
        t, x, r = summary[name]["fast_s"], summary[name]["speedup"], summary[name]["potential_ratio_same_objective"]
        print(f"{count} random temperature profiles x {len(CONTACT_MODES)} modes, fast method "
              f"{'(its own problem)' if name == 'free' else 'like for like'}: {t['median'] * 1e3:.1f} ms median "
              f"({t['max'] * 1e3:.1f} worst), speed-up {x['median']:.0f} x median ({x['min']:.0f}-{x['max']:.0f}), "
              f"potential / the descent's with Gamma(q) {r['min']:.4f}-{r['max']:.4f} (worst {r['max']:.4f})")
    return summary


def _spread(values: list[float]) -> dict:
    return {"min": float(np.min(values)), "median": float(np.median(values)), "max": float(np.max(values))}


if __name__ == "__main__":
    main()
