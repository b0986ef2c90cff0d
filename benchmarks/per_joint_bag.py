"""A ROS 2 bag in the common per-joint layout, diagnosed for every joint in one command, against its CSV.

The plant drives three actuators (knee, hip, ankle: X8 winding/housing/body
networks, sensor noise and 0.1 degC quantisation) through an hour of random
holds and motions.  The run is written twice: as the suite's CSV, and as an
MCAP bag the way many robots publish, ``/joint_states`` (JointState, 10 Hz)
and one ``sensor_msgs/Temperature`` topic per joint (``/knee/temperature``…,
1 Hz).  Then, as a user would:

* ``thermolimb inspect BAG``: the suggested ``--map`` (``{j}`` in the topic);
* ``thermolimb diagnose BAG --fleet`` with that map: every joint in one command;
* ``thermolimb diagnose CSV --fleet``: the same joints read from the CSV.

Printed per joint: validation RMSE of Jorgensen et al.'s model and the recommended
change, from the bag and from the CSV (the bag's temperatures are at 1 Hz
and its efforts are averaged into each temperature interval, so the two
agree closely, not exactly), and the time of each command, measured the same way.

    python benchmarks/per_joint_bag.py [--json]
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import tempfile
import time
from pathlib import Path

from thermolimb.cli.main import main
from thermolimb.logs import read_log
from thermolimb.logs.bag_writer import write_mcap
from thermolimb.plant import X8_9, X8_16, PlantEffects, simulate_profile

JOINTS = ("knee", "hip", "ankle")


def _run(argv: list[str]) -> tuple[str, float]:
    out = io.StringIO()
    start = time.perf_counter()
    with contextlib.redirect_stdout(out):
        code = main(argv)
    if code != 0:
        raise SystemExit(f"thermolimb {' '.join(argv)} exited {code}")
    return out.getvalue(), time.perf_counter() - start


def _rows(table: Path) -> dict[str, dict]:
    return {r["actuator"]: r for r in json.loads(table.read_text())["rows"]}


def measure(folder: Path, seed: int = 0) -> dict:
    run = simulate_profile("random", 3600.0, 0.1, JOINTS, [X8_9, X8_16, X8_9], PlantEffects.realistic_sensor(), seed)
    csv = run.log.write(folder / "run.csv")
    bag = write_mcap(run.log, folder / "run.mcap", layout="per_joint", temperature_every=10)
    inspected, _ = _run(["inspect", str(bag)])
    suggested = next(line.split("--map ", 1)[1].split()[0] for line in inspected.splitlines() if "--map " in line)
    _, bag_s = _run(["diagnose", str(bag), "--map", suggested, "--fleet", "--workers", "2", "--quiet",
                     "--table", str(folder / "bag.json")])
    _, csv_s = _run(["diagnose", str(csv), "--fleet", "--workers", "2", "--quiet", "--table", str(folder / "csv.json")])
    from_bag, from_csv = _rows(folder / "bag.json"), _rows(folder / "csv.json")
    joints = {j: {"bag_samples": from_bag[j]["samples"], "csv_samples": from_csv[j]["samples"],
                  "bag_validation_K": from_bag[j]["validation_rmse_K"],
                  "csv_validation_K": from_csv[j]["validation_rmse_K"],
                  "bag_recommended": from_bag[j]["recommended"], "csv_recommended": from_csv[j]["recommended"]}
              for j in JOINTS}
    return {"suggested_map": suggested, "actuators_read": list(read_log(bag, mapping=None).actuators),
            "bag_seconds": bag_s, "csv_seconds": csv_s, "joints": joints}


def main_(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        result = measure(Path(tmp))
    if args.json:
        print(json.dumps(result, indent=1))
    else:
        print(f"suggested map: {result['suggested_map']}  (actuators read: {', '.join(result['actuators_read'])})")
        print(f"{'joint':6s} {'samples bag/csv':>16s} {'validation K bag/csv':>22s}  recommended bag / csv")
        for j, r in result["joints"].items():
            print(f"{j:6s} {r['bag_samples']:>7d}/{r['csv_samples']:<8d} {r['bag_validation_K']:>10.3f}/"
                  f"{r['csv_validation_K']:<11.3f} {r['bag_recommended']} / {r['csv_recommended']}")
        print(f"one command per file: bag {result['bag_seconds']:.1f} s, csv {result['csv_seconds']:.1f} s "
              f"(ratio {result['bag_seconds'] / result['csv_seconds']:.2f})")
    return result


if __name__ == "__main__":
    main_()
