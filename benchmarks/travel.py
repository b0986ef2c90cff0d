"""The model that travels: MuJoCo's integration of an exported actuator against this suite's, and what
ThermalWrapper costs a Gymnasium environment's step.

1. **Export check.**  For models fitted here -- on a plant log and on the UR3's first run, each of its six joints
   (their logged effort is the motor current, A) -- the saved model is exported to a ``<dcmotor>`` (``thermolimb.mujoco_export``), driven in
   MuJoCo by its calibration log's torque, and compared with this suite's free run of the same exported model: the
   largest difference as a share of the temperature rise (target: under 0.5 %), what dropping the terms MuJoCo
   cannot hold costs on that log, and what the one node fitted again on the log gives (``export --refit``).
2. **Wrapper overhead.**  ``Ant-v5`` and ``Humanoid-v5`` stepped bare and wrapped (a saved first-order model at
   every joint; and the suite's plant with datasheet actuators), the same seeded random actions, in alternating
   blocks so that both see the same machine: the median over blocks of the time per step, and the ratio
   (target: at most 1.10 with a saved model on Ant-v5).

    python benchmarks/travel.py [--steps 2000] [--blocks 7] [--json]
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import gymnasium as gym
import numpy as np

from thermolimb.data import REAL_LOGS
from thermolimb.envs.thermal_wrapper import ThermalWrapper
from thermolimb.logs import read_log
from thermolimb.model.saved import ModelFile
from thermolimb.mujoco_export import Motor, cost_of_dropping, refitted, run_in_mujoco, to_dcmotor
from thermolimb.plant import X8_9, PlantEffects, simulate_profile
from thermolimb.workbench.saving import saved_from_report
from thermolimb.workbench.validation import Scheme, validate_model

MOTOR = Motor(motor_const=0.1, resistance_ohm=1.0, gear=10.0)


def export_rows() -> list[dict]:
    rows = []
    plant = simulate_profile("random", 3600.0, 1.0, ["knee"], [X8_9], PlantEffects.from_names("sensor_noise"),
                             seed=0).log
    ur3 = REAL_LOGS["ur3"].read()[0]
    cases = [("plant X8-9 (random duty)", plant, "knee")]
    cases += [(f"UR3 {a} (real, first run)", ur3, a) for a in ur3.actuators]
    for label, log, actuator in cases:
        runs = log.runs(actuator)[:1]
        report = validate_model(runs, "joule,effort_bias", Scheme.at_split(0.7))
        saved = saved_from_report(report, [])
        if label.startswith("UR3"):  # the UR3 logs each joint's motor current (Current_J*), in A: heat from current
            saved = replace(saved, channel_units={**saved.channel_units, "effort": "A"})
        export = to_dcmotor(saved, MOTOR)
        s = runs[0]
        mujoco_C = run_in_mujoco(export, s.signals, float(s.temperature_C[0]))
        ours = export.exported.simulate(s.signals, float(s.temperature_C[0]))
        rise = float(ours.max() - ours.min())
        worst = float(np.max(np.abs(mujoco_C - ours)))
        cost = cost_of_dropping(saved, export, runs)
        if export.dropped:  # the one node fitted again on the log (export --refit)
            cost["refit_rmse_K"] = cost_of_dropping(saved, refitted(saved, export, runs), runs)["exported_rmse_K"]
        rows.append({"case": label, "samples": int(s.n), "rise_K": rise, "max_difference_K": worst,
                     "share_of_rise": worst / rise if rise > 0 else None, "dropped": list(export.dropped), **cost})
    return rows


def seconds_per_step(env, actions) -> float:
    env.reset(seed=0)
    start = time.perf_counter()
    for a in actions:
        _, _, terminated, truncated, _ = env.step(a)
        if terminated or truncated:
            env.reset()
    return (time.perf_counter() - start) / len(actions)


def overhead_rows(model_file: Path, steps: int, blocks: int) -> list[dict]:
    saved = ModelFile.load(model_file)["knee"]
    rows = []
    for env_id in ("Ant-v5", "Humanoid-v5"):
        bare = gym.make(env_id)
        wrapped = {"saved model": ThermalWrapper(gym.make(env_id), models=saved),
                   "datasheet plant": ThermalWrapper(gym.make(env_id), plant=X8_9)}
        space = bare.action_space
        space.seed(0)
        actions = [space.sample() for _ in range(steps)]
        times = {"bare": [], **{k: [] for k in wrapped}}
        for _ in range(blocks):
            times["bare"].append(seconds_per_step(bare, actions))
            for name, env in wrapped.items():
                times[name].append(seconds_per_step(env, actions))
        base = float(np.median(times["bare"]))
        for name in wrapped:
            t = float(np.median(times[name]))
            rows.append({"env": env_id, "heat": name, "bare_us": 1e6 * base, "wrapped_us": 1e6 * t,
                         "ratio": t / base})
    return rows


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--blocks", type=int, default=7)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    exports = export_rows()
    for r in exports:
        print(f"export  {r['case']:28s} rise {r['rise_K']:7.2f} K  MuJoCo vs suite {r['max_difference_K']:.5f} K "
              f"({100 * r['share_of_rise']:.4f} % of the rise); dropped {','.join(r['dropped']) or '-'}: "
              f"{r['saved_rmse_K']:.3f} -> {r['exported_rmse_K']:.3f} K RMSE on the log"
              + (f", refitted {r['refit_rmse_K']:.3f} K" if "refit_rmse_K" in r else ""))
    with tempfile.TemporaryDirectory() as tmp:
        log, model = Path(tmp) / "cal.csv", Path(tmp) / "model.json"
        simulate_profile("random", 1800.0, 1.0, ["knee"], [X8_9], PlantEffects(), seed=0).log.write(log)
        report = validate_model(read_log(log).runs("knee"), "joule,effort_bias", Scheme.at_split(0.7))
        ModelFile({"knee": saved_from_report(report, [log], limit_C=90.0)}).save(model)
        overhead = overhead_rows(model, args.steps, args.blocks)
    for r in overhead:
        print(f"wrapper {r['env']:12s} {r['heat']:16s} bare {r['bare_us']:7.1f} us/step, wrapped "
              f"{r['wrapped_us']:7.1f} us/step: {r['ratio']:.3f}x")
    record = {"exports": exports, "overhead": overhead}
    if args.json:
        print(json.dumps(record, indent=1))
    return record


if __name__ == "__main__":
    main()
