"""How fast the monitor is: one step for 30 actuators, and whether it keeps up with a 1 kHz log of 6.

1. One step: a :class:`thermolimb.monitor.Session` of 30 actuators, each with a saved model of the kind
   ``diagnose --auto`` ends with (a slow mass, a lagging sensor, speed losses), fed one new sample of every
   actuator at a time (the worst case: the log polled after every row).  Beside it, in the same process, the
   plant's own :class:`~thermolimb.plant.observer.WindingObserver` (three nodes, a thermistor, an unknown heat
   and two loss coefficients per actuator, the rig's observer) updated for the same 30 actuators: the ratio.
   Also the cost per sample when the monitor is fed 50 samples at a time (a 1 kHz log polled at 20 Hz), and
   each step both ways: together as arrays (the monitor's way for these families of model) and one by one; and
   the same for 30 first-order actuators (the default model).
2. Keeping up: another process appends a 6-actuator canonical CSV at 1 kHz in real time (every 10 ms, ten rows
   per actuator) for ``--seconds``; the monitor follows it (MCAP output at 20 Hz) and the benchmark reports the
   share of the wall time it was busy and how far behind the writer it was when the writer stopped.

    python benchmarks/monitor.py [--seconds 10] [--json]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from thermolimb.logs.follow import CsvFollower, Run
from thermolimb.model import ThermalModel, model_parameters
from thermolimb.model.saved import ModelFile, ResidualStats, bare
from thermolimb.monitor import Session
from thermolimb.monitor.recording import McapOutput
from thermolimb.plant import X8_9
from thermolimb.plant.observer import WindingObserver

TERMS = ("joule", "effort_bias", "speed_losses", "second_node", "sensor_lag")
FIRST_ORDER = ("joule", "effort_bias")  # Jorgensen et al.'s model, the default: stepped together as arrays
WRITER = """
import sys, time
path, actuators, seconds = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
with open(path, "w") as f:
    f.write("time,actuator,effort,temperature,velocity\\n")
    f.flush()
    start = time.monotonic()
    k = 0
    while k < seconds * 1000:
        rows = []
        for _ in range(10):
            t = k / 1000.0
            rows += [f"{t:.3f},j{a},{5 + a + 3 * ((k // 500) % 2)},{30 + 0.001 * k:.2f},{0.5 * a}\\n" for a in range(actuators)]
            k += 1
        f.write("".join(rows))
        f.flush()
        time.sleep(max(0.0, start + k / 1000.0 - time.monotonic()))
print(time.monotonic(), flush=True)
"""


def models(names, terms=TERMS) -> ModelFile:
    params = {p.name: p.typical for p in model_parameters(terms)}
    params.update(RC_s=40.0, frame_fraction=0.5, frame_tau_s=1200.0, sensor_tau_s=5.0, T_offset_C=25.0)
    model = ThermalModel(terms, {p.name: params[p.name] for p in model_parameters(terms)})
    residual = ResidualStats(1000, 1000.0, 0.0, 0.5, {"0.5": 0.3, "0.8": 0.6, "0.9": 0.8, "0.95": 1.0, "0.99": 1.3},
                             0.9, 20.0)
    from dataclasses import replace

    return ModelFile({n: replace(bare(model, n, 90.0), residual=residual) for n in names})


def piece(times, effort, temperature, velocity, new_run: bool = False) -> list[Run]:
    arrays = {"time": times, "effort": effort, "temperature": temperature, "velocity": velocity}
    return [Run({k: np.atleast_1d(np.asarray(v, float)) for k, v in arrays.items()}, new_run)]


def step_costs(actuators: int = 30, steps: int = 400, terms=TERMS, together: bool = True) -> dict:
    names = [f"j{i}" for i in range(actuators)]
    session = Session(models(names, terms), {}, [], publish_every_s=0.0, together=together)
    rng = np.random.default_rng(0)
    session.feed({n: piece([0.0], [5.0], [30.0], [0.0], new_run=True) for n in names})
    times = []
    for k in range(1, steps + 1):
        pieces = {n: piece([k * 0.001], [rng.uniform(0, 10)], [30.0 + 0.001 * k], [rng.uniform(0, 2)]) for n in names}
        start = time.perf_counter()
        session.feed(pieces)
        times.append(time.perf_counter() - start)
    one = float(np.median(times))
    # the same 30 actuators, 50 samples a piece
    block = []
    for k in range(steps // 50):
        t0 = 1.0 + k * 0.05
        pieces = {n: piece(t0 + 0.001 * np.arange(1, 51), rng.uniform(0, 10, 50), 30.0 + 0.01 * np.arange(50),
                           rng.uniform(0, 2, 50)) for n in names}
        start = time.perf_counter()
        session.feed(pieces)
        block.append((time.perf_counter() - start) / 50)
    observer = WindingObserver([X8_9] * actuators, sensor_tau_s=15.0, initial_C=30.0)
    current, measured, speed = np.full(actuators, 3.0), np.full(actuators, 30.0), np.full(actuators, 1.0)
    observer.update(current, measured, 25.0, 0.001, speed)
    obs = []
    for _ in range(steps):
        start = time.perf_counter()
        observer.update(current, measured, 25.0, 0.001, speed)
        obs.append(time.perf_counter() - start)
    return {"actuators": actuators, "monitor_step_s": one, "monitor_per_sample_in_pieces_of_50_s": float(np.median(block)),
            "plant_observer_step_s": float(np.median(obs)), "ratio_monitor_to_observer": one / float(np.median(obs))}


def keeps_up(seconds: float, actuators: int = 6) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        log, out = Path(folder) / "live.csv", Path(folder) / "out.mcap"
        names = [f"j{a}" for a in range(actuators)]
        writer = subprocess.Popen([sys.executable, "-c", WRITER, str(log), str(actuators), str(seconds)],
                                  stdout=subprocess.PIPE, text=True)
        session = Session(models(names), {}, [McapOutput(out, names)], publish_every_s=0.05)
        follower = CsvFollower(log)
        busy, start, done_at = 0.0, time.monotonic(), None
        while True:
            t0 = time.monotonic()
            pieces = follower.poll()
            if pieces:
                session.feed(pieces)
            busy += time.monotonic() - t0
            if writer.poll() is not None and done_at is None:
                done_at = float(writer.stdout.read().strip())
                continue  # one more poll for what the writer wrote last
            if done_at is not None and not pieces:
                break
            time.sleep(0.02)
        behind = time.monotonic() - done_at
        wall = time.monotonic() - start
        session.close()
        last = max(m.last.time_s for m in session.monitors.values())
        return {"actuators": actuators, "rate_hz": 1000, "seconds": seconds, "samples": session.samples,
                "busy_share": busy / wall, "behind_at_end_s": behind, "last_time_s": last,
                "mcap_bytes": out.stat().st_size}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0, help="how long the 1 kHz writer runs")
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    args = parser.parse_args(argv)
    steps = step_costs()
    alone = step_costs(together=False)
    first = {"together": step_costs(terms=FIRST_ORDER), "one_by_one": step_costs(terms=FIRST_ORDER, together=False)}
    live = keeps_up(args.seconds)
    print(f"one step, {steps['actuators']} actuators with the walk's kind of model ({', '.join(TERMS)}): "
          f"{1e3 * steps['monitor_step_s']:.3f} ms together (target 1 ms), {1e3 * alone['monitor_step_s']:.3f} ms "
          f"one by one (ratio {alone['monitor_step_s'] / steps['monitor_step_s']:.1f}); the plant's winding "
          f"observer for as many: "
          f"{1e3 * steps['plant_observer_step_s']:.3f} ms (ratio {steps['ratio_monitor_to_observer']:.1f}); per "
          f"sample in pieces of 50: {1e3 * steps['monitor_per_sample_in_pieces_of_50_s']:.3f} ms")
    print(f"one step, {steps['actuators']} first-order actuators ({', '.join(FIRST_ORDER)}): stepped together "
          f"{1e3 * first['together']['monitor_step_s']:.3f} ms, one by one "
          f"{1e3 * first['one_by_one']['monitor_step_s']:.3f} ms (ratio "
          f"{first['one_by_one']['monitor_step_s'] / first['together']['monitor_step_s']:.1f})")
    print(f"1 kHz log of {live['actuators']} actuators for {live['seconds']:g} s: {live['samples']} samples "
          f"followed, busy {100 * live['busy_share']:.0f} % of the time, {live['behind_at_end_s']:.2f} s behind the "
          f"writer at its end; MCAP {live['mcap_bytes'] / 1e6:.1f} MB")
    result = {"step": steps, "step_one_by_one": alone, "first_order_step": first, "keeps_up": live}
    if args.json:
        print(json.dumps(result))
    return result


if __name__ == "__main__":
    main()
