"""A fleet of 20 actuators x 10 runs of 1 h at 10 Hz fitted serially, over the process pool, and on a local Ray.

The logs come from the plant (sensor noise and quantisation, each run its own
seed) and are written to Parquet; each backend reads them (each worker the
files it fits), fits every actuator's every run (``thermolimb fit --fleet``'s code path) and is timed
from reading to the last row, once each, in this process.  Every backend is
timed the same way: opened (pool started, Ray started) and warmed by two
untimed small fits per worker first, so that each time is the fleet's work,
not imports and first calls; starting a pool or Ray is the cost of any
parallel run, and is printed apart.  ``identical``
says every parameter, standard error and error is equal across the three.

    python benchmarks/fleet.py [--actuators 20] [--runs 10] [--hours 1] [--json]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

from thermolimb.model import DEFAULT_MODEL
from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile
from thermolimb.util.parallel import Runner
from thermolimb.workbench.fleet import analyse_file, expand_paths, fit_fleet_files
from thermolimb.workbench.validation import Scheme

MODEL = DEFAULT_MODEL
NAME0 = "j00"


def _timed(paths, backend: str, workers: int):
    """Open the backend and warm every worker (untimed), then time one fleet fit."""
    opened = time.perf_counter()
    with Runner(backend, workers) as runner:
        warm = [(str(paths[0]), {}, [NAME0], MODEL, Scheme(), "output_error", False)] * (2 * workers)
        runner.map(analyse_file, warm)
        start = time.perf_counter()
        rows, _ = fit_fleet_files(paths, {}, MODEL, runner=runner)
        end = time.perf_counter()
    print(f"  ({backend}: opening and warming took {start - opened:.1f} s, untimed)")
    return end - start, rows


def _differences(a, b, where="") -> list[str]:
    if isinstance(a, dict):
        return [d for k in a for d in _differences(a[k], b.get(k), f"{where}.{k}")]
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in _differences(x, y, f"{where}[{i}]")]
    return [] if a == b or (a != a and b != b) else [f"{where}: {a!r} != {b!r}"]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--actuators", type=int, default=20)
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--hours", type=float, default=1.0)
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    args = parser.parse_args(argv)
    workers = os.cpu_count() or 1
    names = [f"j{k:02d}" for k in range(args.actuators)]
    effects = PlantEffects.from_names("sensor_noise,quantisation")
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        for run in range(args.runs):
            log = simulate_profile("random", args.hours * 3600.0, 0.1, names, [X8_9] * len(names), effects,
                                   seed=run, network=NETWORKS["first_order"]).log
            log.write(Path(folder) / f"run{run:02d}.parquet")
        paths = expand_paths([folder])
        print(f"fleet: {args.actuators} actuators x {args.runs} runs x {log.series(names[0]).n} samples, "
              f"written in {time.perf_counter() - start:.1f} s")
        serial_s, serial = _timed(paths, "serial", 1)
        print(f"serial        {serial_s:8.1f} s")
        process_s, process = _timed(paths, "process", workers)
        print(f"process pool  {process_s:8.1f} s  ({workers} workers): {serial_s / process_s:.2f}x serial")
        try:
            import ray  # noqa: F401
        except ImportError:
            ray_s, on_ray = None, None
            print("ray           not installed (pip install 'thermolimb[ray]')")
        else:
            ray_s, on_ray = _timed(paths, "ray", workers)
            print(f"local ray     {ray_s:8.1f} s: {serial_s / ray_s:.2f}x serial")
    differences = _differences(serial, process) + (_differences(serial, on_ray) if on_ray is not None else [])
    for line in differences[:5]:
        print("differs:", line)
    identical = not differences
    errors = sum(1 for r in serial if r["error"])
    print(f"rows: {len(serial)}, failed fits: {errors}, identical on every backend: {identical}")
    record = {"serial_s": serial_s, "process_s": process_s, "ray_s": ray_s, "speedup": serial_s / process_s,
              "identical": identical}
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
