"""``diagnose --auto --discover`` on every bundled real log: what it proposes and whether it holds on other runs.

For each log (UR3 joints with every column kept, the WidowX-200 waist's two
runs and its ROS 1 bag, the BLDC bench's two runs, the PMSM bench's
profiles 24 and 46 with every column), per actuator:

* the walk from Jorgensen et al.'s model on each run alone, judged by its default scheme (the split, or
  interleaved blocks where the split's tail leaves a channel or the heat still: said in the row), without and
  with ``--discover``: the final validation RMSE and what discovery added;
* where there are several runs, leave one run out: fit on one, validate on
  the other (``--validate-on``), with ``--discover``; a channel or discovered
  term taken on one run is shown with its effect on the other.

    python benchmarks/discovery_real.py [--json]
"""

from __future__ import annotations

import argparse
import json
import time

from thermolimb.data import PMSM_MAP, PMSM_UNITS, REAL_LOGS, WX200_BAG, pmsm_profile
from thermolimb.logs import parse_mapping, read_log
from thermolimb.model.terms import TERMS
from thermolimb.util.errors import ThermolimbError
from thermolimb.workbench.diagnosis import auto_diagnose
from thermolimb.workbench.diagnosis.stability import Stability
from thermolimb.workbench.validation import Scheme

UR3_JOINTS = ("J1", "J2", "J4")  # three of the six: the shoulder and elbow carry load, J4 a wrist


def _generated(model) -> list[str]:
    return [t for t in model if TERMS[t].generated]


def _walk(series, validate_on=(), discover=False) -> dict:
    start = time.perf_counter()
    try:
        first, steps = auto_diagnose(series, discover=discover, stability=STABILITY[0],
                                     scheme=Scheme.on_runs(validate_on) if validate_on else Scheme())
    except ThermolimbError as exc:  # the log cannot carry Jorgensen et al.'s model: said, not hidden
        nan = float("nan")
        return {"base_K": nan, "final_K": nan, "model": [], "generated": [], "walk": [], "proposals": [],
                "seconds": time.perf_counter() - start, "refused": str(exc)}
    return {"base_K": first.auto[0]["rmse_K"], "final_K": first.auto[-1]["rmse_K"], "model": list(steps[-1].model),
            "generated": _generated(steps[-1].model), "walk": [s.get("change", "start") for s in first.auto],
            "proposals": [d.proposal.formula for d in steps if d.proposal is not None],
            "judged": first.base.scheme.split(";")[0].split(":")[0], "seconds": time.perf_counter() - start}


def _runs() -> dict[str, dict[str, list]]:
    """log name -> actuator -> its runs (one series per run)."""
    out = {}
    ur3 = REAL_LOGS["ur3"].read()[0]
    out["ur3"] = {j: ur3.runs(j) for j in UR3_JOINTS}
    for key in ("wx200", "bldc"):
        logs = REAL_LOGS[key].read()
        out[key] = {a: [log.series(a) for log in logs] for a in logs[0].actuators}
    bag = WX200_BAG.read()[0]
    out["wx200-bag"] = {a: [bag.series(a)] for a in bag.actuators}
    pmsm = [read_log(pmsm_profile(n), mapping=parse_mapping(PMSM_MAP), **PMSM_UNITS, actuator_name="pmsm")
            for n in (24, 46)]
    out["pmsm"] = {"pmsm": [log.series("pmsm") for log in pmsm]}
    return out


def _row(log, actuator, scheme, extras, catalog, found) -> dict:
    r = {"log": log, "actuator": actuator, "scheme": scheme, "extras": extras, "catalog_K": catalog["final_K"],
         "base_K": found["base_K"], "discover_K": found["final_K"], "generated": found["generated"],
         "proposals": found["proposals"], "model": found["model"], "seconds": found["seconds"],
         "refused": found.get("refused")}
    taken = f"refused: {r['refused'][:90]}" if r["refused"] else (", ".join(r["generated"]) or "nothing")
    print(f"{log:10s} {actuator:8s} {scheme:34s} {r['base_K']:7.3f} {r['catalog_K']:9.3f} {r['discover_K']:10.3f}  "
          f"{taken}", flush=True)
    return r


# the stability check every walk makes (--stability K replicates, as thermolimb diagnose; 0: off)
STABILITY: list = [None]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    parser.add_argument("--stability", type=int, default=10, metavar="K",
                        help="replicates of the stability check, as thermolimb diagnose's default (0: off)")
    args = parser.parse_args(argv)
    STABILITY[0] = Stability(args.stability) if args.stability else None
    rows = []
    print(f"{'log':10s} {'actuator':8s} {'scheme':34s} {'base K':>7s} {'catalog K':>9s} {'discover K':>10s}  "
          f"taken by discovery", flush=True)
    for log, actuators in _runs().items():
        for actuator, runs in actuators.items():
            extras = list(runs[0].signals.extra)
            for k, run in enumerate(runs):
                catalog, found = _walk([run]), _walk([run], discover=True)
                judged = "70/30 split" if found.get("judged", "").startswith("fit on the first") else "blocks"
                rows.append(_row(log, actuator, f"run {k + 1}, {judged}", extras, catalog, found))
            for k, run in enumerate(runs if len(runs) > 1 else []):
                other = [r for j, r in enumerate(runs) if j != k]
                catalog, found = _walk([run], other), _walk([run], other, discover=True)
                rows.append(_row(log, actuator, f"fit run {k + 1}, validate on the other", extras, catalog, found))
    record = {"rows": rows}
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
