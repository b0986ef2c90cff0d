"""Why a stability replicate of a long log is slower beside another: the two cores share the memory's bandwidth.

Part one streams a NumPy loop (``y = 0.5 x + 0.1; x = |y|``) over arrays of 200 k, 2 M and 20 M samples, alone and
in two processes at once: arrays that outgrow a core's caches (a 2 M-sample float64 array is 16 MB) run slower when
both cores stream, arrays that fit do not.

Part two times each replicate of the stability check on one actuator of a long log (the 6 M-row Parquet of
``benchmarks/diagnose.py --large``, written here unless ``--log`` names one): run serially in one process, on the
check's two workers, and serially in two unrelated processes at once.  If the two unrelated processes slow each
other's replicates as much as the pool's workers do, the pool is not the cause.

    python benchmarks/contention.py [--json] [--log LOG --actuator NAME] [--no-replicates]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

SIZES = (200_000, 2_000_000, 20_000_000)
SWEEP = 80_000_000  # samples streamed per loop, whatever the array's size


def stream(n: int) -> float:
    """Seconds to stream :data:`SWEEP` samples through an array of ``n``."""
    x = np.random.default_rng(0).normal(size=n)
    start = time.perf_counter()
    for _ in range(max(1, SWEEP // n)):
        y = x * 0.5 + 0.1
        x = np.abs(y)
    return time.perf_counter() - start


def streaming() -> list[dict]:
    rows = []
    for n in SIZES:
        alone = min(stream(n) for _ in range(2))
        with ProcessPoolExecutor(2) as pool:
            both = list(pool.map(stream, [n, n]))
        rows.append({"samples": n, "alone_s": round(alone, 3), "two_at_once_s": [round(t, 3) for t in both],
                     "slower": round(float(np.mean(both)) / alone, 2)})
        print(f"{n:>10d} samples: alone {alone:.2f} s, two at once {both[0]:.2f} and {both[1]:.2f} s "
              f"({rows[-1]['slower']:.2f}x)")
    return rows


_REAL = None  # stability.perturbed, before _timed stands in for it
_TIMES = None  # the file each replicate's seconds are appended to (from the workers too)


def _timed(*args):
    """One replicate, its seconds appended to :data:`_TIMES` where it runs (a worker inherits both by fork)."""
    start = time.perf_counter()
    label = _REAL(*args)
    with open(_TIMES, "a") as out:
        out.write(f"{time.perf_counter() - start}\n")
    return label


def replicates(log: str, actuator: str, workers: int) -> dict:
    """The seconds of each replicate of ``diagnose`` on ``actuator`` (timed where it runs), and the whole call's."""
    global _REAL, _TIMES
    from thermolimb.logs import read_log
    from thermolimb.workbench.diagnosis import diagnose, stability
    from thermolimb.workbench.diagnosis.stability import Stability

    series = read_log(log).series(actuator)
    with tempfile.NamedTemporaryFile("r", suffix=".txt") as times:
        _REAL, _TIMES = _REAL or stability.perturbed, times.name
        stability.perturbed = _timed
        start = time.perf_counter()
        diagnose([series], stability=Stability(workers=workers))
        total = time.perf_counter() - start
        seconds = [float(line) for line in open(times.name)]
    return {"replicates_s": [round(t, 2) for t in seconds], "total_s": round(total, 2)}


def replicate_rows(log: str, actuator: str) -> dict:
    me = [sys.executable, __file__, "--child", "--log", log, "--actuator", actuator]
    out = {"serial": replicates(log, actuator, 1), "two_workers": replicates(log, actuator, 2)}
    children = [subprocess.Popen(me, stdout=subprocess.PIPE, text=True) for _ in range(2)]
    out["two_processes_serial"] = [json.loads(c.communicate()[0].strip().splitlines()[-1]) for c in children]
    for name, runs in out.items():
        for run in runs if isinstance(runs, list) else [runs]:
            t = run["replicates_s"]
            print(f"{name:22s} replicates {min(t):.2f}-{max(t):.2f} s each (median {np.median(t):.2f}), "
                  f"the diagnosis {run['total_s']:.1f} s")
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--log", help="a long log (default: the 6 M-row Parquet of diagnose.py --large, written)")
    parser.add_argument("--actuator", default="knee")
    parser.add_argument("--no-replicates", action="store_true", help="part one only")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--json", action="store_true", help="print the record last, on one line")
    args = parser.parse_args(argv)
    if args.log is not None and not Path(args.log).is_file():
        parser.error(f"--log {args.log!r}: no such file; expected a log the suite reads (CSV, Parquet, a bag)")
    if args.child:
        print(json.dumps(replicates(args.log, args.actuator, 1)))
        return None
    record = {"streaming": streaming()}
    if not args.no_replicates:
        with tempfile.TemporaryDirectory() as tmp:
            log = args.log
            if log is None:
                log = str(Path(tmp) / "large.parquet")
                subprocess.run([sys.executable, "-m", "thermolimb.cli.main", "simulate", "--profile", "random",
                                "--network", "first_order", "--effects", "sensor_noise,quantisation,speed_losses",
                                "--duration", "200000", "--dt", "0.1", "--out", log, "--quiet"], check=True)
            record["replicates"] = replicate_rows(log, args.actuator)
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
