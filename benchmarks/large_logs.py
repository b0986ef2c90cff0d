"""Memory and time of one actuator read from a large log: ``fit``, ``diagnose`` and ``inspect`` on big files.

A synthetic canonical log of three actuators (``knee``, ``hip``, ``ankle``) at 10 Hz, each a first-order
thermal response to a random effort with sensor noise, is written as Parquet and as CSV; each command runs
in its own process, and its peak resident memory (``ru_maxrss`` of that process, from ``wait4``) and wall
time are printed with the size of the selected actuator's data (its rows times the file's columns, 8 bytes
each) and their ratio.

    python benchmarks/large_logs.py                      # 2 M rows per actuator (6 M rows per file)
    python benchmarks/large_logs.py --rows 13.4e6 --csv-only --no-diagnose  # the 40 M-row, 2 GB CSV

"above base / selected" is the peak less the memory of the same command on a 3000-row file (the
interpreter and its libraries), over the selected actuator's data: the cost of the file's size.
    python benchmarks/large_logs.py --json
    PYTHONPATH=/path/to/other/checkout python benchmarks/large_logs.py   # the same on another version
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.signal import lfilter

NAMES = ("knee", "hip", "ankle")


def synthetic_log(rows_per_actuator: int, seed: int = 0, dt_s: float = 0.1) -> pd.DataFrame:
    """Three actuators, each a first-order response (RC 600 s) to a random, held effort, with 0.05 K noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(rows_per_actuator) * dt_s
    parts = []
    for k, name in enumerate(NAMES):
        levels = rng.uniform(0.0, 8.0, rows_per_actuator // 600 + 1)
        effort = np.repeat(levels, 600)[:rows_per_actuator]
        a = np.exp(-dt_s / 600.0)
        rise = lfilter([1 - a], [1, -a], 0.2 * effort ** 2)
        temperature = 25.0 + rise + rng.normal(0.0, 0.05, rows_per_actuator)
        parts.append(pd.DataFrame({"time": t, "actuator": name, "effort": effort,
                                   "velocity": rng.normal(0.0, 1.0, rows_per_actuator),
                                   "temperature": np.round(temperature, 2)}))
    return pd.concat(parts, ignore_index=True)


def measure(argv: list[str], cwd: Path) -> dict:
    """Wall time and peak resident memory of one command in its own process."""
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "thermolimb.cli.main", *argv], cwd=cwd,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    err = proc.stderr.read().decode().strip().splitlines()
    return {"command": "thermolimb " + " ".join(argv), "seconds": round(seconds, 1),
            "peak_MB": round(usage.ru_maxrss / 1024.0, 0), "exit": os.waitstatus_to_exitcode(status),
            "last_line": err[-1] if err else ""}


def write_files(folder: Path, rows: int, kinds: tuple[str, ...]) -> None:
    """The test files, written by a process of their own: a child forked from a parent holding the frame
    would count the parent's pages in its peak memory."""
    code = ("import sys; sys.path.insert(0, sys.argv[1]); from large_logs import synthetic_log; "
            "from pathlib import Path; d = Path(sys.argv[2]); f = synthetic_log(int(sys.argv[3])); "
            "[f.to_parquet(d / 'large.parquet', index=False) if k == 'parquet' else f.to_csv(d / 'large.csv', "
            "index=False) for k in sys.argv[4:]]; synthetic_log(3000).to_csv(d / 'small.csv', index=False)")
    subprocess.run([sys.executable, "-c", code, str(Path(__file__).parent), str(folder), str(rows), *kinds],
                   check=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rows", type=float, default=2e6, help="rows per actuator (default 2e6)")
    parser.add_argument("--csv-only", action="store_true", help="only the CSV (the 40 M-row case)")
    parser.add_argument("--no-diagnose", action="store_true", help="only fit and inspect")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    rows = int(args.rows)
    kinds = ("csv",) if args.csv_only else ("parquet", "csv")
    columns = synthetic_log(10).shape[1]
    selected_MB = rows * columns * 8 / 1e6
    records = []
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        start = time.perf_counter()
        write_files(d, rows, kinds)
        written = time.perf_counter() - start
        base = measure(["fit", "small.csv", "--actuator", "knee", "--quiet"], d)["peak_MB"]
        for kind in kinds:
            path = d / f"large.{kind}"
            commands = [["fit", path.name, "--actuator", "knee", "--quiet"],
                        ["diagnose", path.name, "--actuator", "hip", "--quiet"], ["inspect", path.name]]
            for argv in commands[::2] if args.no_diagnose else commands:
                record = measure(argv, d)
                record.update(file=kind, file_MB=round(path.stat().st_size / 1e6), rows=rows * len(NAMES),
                              selected_MB=round(selected_MB), baseline_MB=base,
                              above_baseline_over_selected=round((record["peak_MB"] - base) / selected_MB, 2),
                              files_written_in_s=round(written, 1))
                records.append(record)
    if args.json:
        print(json.dumps(records, indent=1))
        return
    print(f"{'command':52s} {'file MB':>8s} {'s':>7s} {'peak MB':>8s} {'above base / selected':>22s}  exit")
    for r in records:
        print(f"{r['command'][:52]:52s} {r['file_MB']:8d} {r['seconds']:7.1f} {r['peak_MB']:8.0f} "
              f"{r['above_baseline_over_selected']:22.2f}  {r['exit']}")
    print(f"{records[0]['rows']} rows, {len(NAMES)} actuators; the selected actuator's data: "
          f"{records[0]['selected_MB']} MB ({rows} rows x {columns} columns x 8 bytes); the base (fit on a "
          f"3000-row file: the interpreter and its libraries): {records[0]['baseline_MB']:.0f} MB")


if __name__ == "__main__":
    main()
