"""Demo ``real-logs``: the model-versus-measurement loop on real robot and bench logs, from the default start.

Three openly licensed logs the suite did not generate (``thermolimb/data/real``):
a UR3 cobot's six joints (signed motor currents, 1 Hz, two parts hours apart),
a Dynamixel servo's two 600 s runs (whole degrees), and a BLDC bench's two
heating runs (electrical power, no torque).  Each is read with the suite's own
options, then ``diagnose --auto`` walks from Jorgensen et al.'s model: per actuator the
validation error before and after, every change and why, and the fitted
values the suite flags.  Where there are several runs, leave-one-run-out
(``--cv runs``) checks that what was found carries over to a run it was not
fitted on.
"""

from __future__ import annotations

from pathlib import Path

from thermolimb.data import REAL_LOGS
from thermolimb.demo_registry import DemoPage, demo_main, kelvin, register_demo
from thermolimb.identification import IdentifiabilityError
from thermolimb.plotting.diagnosis import plot_diagnosis
from thermolimb.workbench.diagnosis import auto_diagnose
from thermolimb.workbench.diagnosis.stability import Stability
from thermolimb.workbench.validation import Scheme

NAME = "real-logs"
QUICK_JOINTS = {"ur3": ("J3",)}


def _walk(first) -> dict:
    steps = first.auto
    return {"before_K": steps[0]["rmse_K"], "after_K": steps[-1]["rmse_K"], "final_model": steps[-1]["model"],
            "steps": [{"change": s.get("change", "start"), "rmse_K": s["rmse_K"], "why": s.get("why"),
                       "flags": s["flags"]} for s in steps]}


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for dataset, record in summary.items():
        for actuator, result in record["actuators"].items():
            split = result["split"]
            rows.append((f"{dataset} {actuator}: validation RMSE", kelvin(split["after_K"]),
                         f"from {kelvin(split['before_K'])} with Jorgensen et al.'s model; final model "
                         + ",".join(split["final_model"])))
    return rows


def _finding(summary: dict) -> str:
    splits = [(f"{d} {a}", r["split"]) for d, rec in summary.items() for a, r in rec["actuators"].items()]
    better = [(name, s) for name, s in splits if s["after_K"] < s["before_K"]]
    text = f"In this run the search lowers the held-out error on {len(better)} of {len(splits)} real actuators"
    if better:
        name, s = max(better, key=lambda b: 1 - b[1]["after_K"] / b[1]["before_K"])
        text += f" (most on {name}: {kelvin(s['before_K'])} to {kelvin(s['after_K'])})"
    same = [name for name, s in splits if s["after_K"] >= s["before_K"]]
    return text + (f"; on {', '.join(same)} it takes nothing: the log cannot tell more (its flags say why)."
                   if same else ".")


PAGE = DemoPage(
    about="Logs from robots and benches the suite did not generate: a UR3 cobot's joints, a Dynamixel servo "
          "(whole-degree readings) and a BLDC motor on a bench. Each is read as a user would, diagnosed from "
          "Jorgensen et al.'s model, and the search adds what helps. Look at where physics is found (heat from a neighbour "
          "in the UR3's wrist) and where the data cannot tell (the servo's 1 °C steps), which the suite says "
          "rather than guesses.",
    headline=_headline,
    finding=_finding)


@register_demo(NAME, "real UR3, Dynamixel and BLDC-bench logs: what Jorgensen et al.'s model misses and what the search adds",
               page=PAGE, cost_s=9)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    summary = {}
    for key, real in REAL_LOGS.items():
        logs = real.read()
        names = QUICK_JOINTS.get(key, logs[0].actuators) if quick else logs[0].actuators
        entry = {"description": real.description, "files": list(real.files), "map": real.mapping,
                 "notes": [n for log in logs for n in log.notes], "actuators": {}}
        for name in names:
            runs = [r for log in logs for r in log.runs(name)]
            # each run's 70 % split (what `--split 0.7` gives), then, on a full run, the default where a log has
            # several runs: each run held out in turn.  Quick: 5 stability replicates instead of 10
            first, _ = auto_diagnose(runs, quiet=quiet, scheme=Scheme.at_split(0.7),
                                     stability=Stability(replicates=5) if quick else Stability())
            plot_diagnosis(first, out, f"{key}_{name}")
            record = {"runs": len(runs), "split": _walk(first)}
            if len(runs) > 1 and not quick:
                try:
                    cross, _ = auto_diagnose(runs, quiet=quiet, scheme=Scheme.leave_one_run_out(), stability=Stability())
                    record["leave_one_run_out"] = _walk(cross)
                except IdentifiabilityError as exc:
                    record["leave_one_run_out"] = {"refused": str(exc)}
            entry["actuators"][name] = record
        summary[key] = entry
    return summary


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
