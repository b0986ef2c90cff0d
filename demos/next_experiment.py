"""Demo ``next-experiment``: a log that cannot size a slow mass, the test designed to size it, run on the plant.

Ten minutes of an X8-9 knee on a heavier housing (the plant's second-order network) are fitted with a second
mass: the housing's time constant comes out twice the log's length, ± hundreds of seconds, and the workbench
says the log cannot size it.  ``thermolimb plan``'s design (:func:`thermolimb.experiment.design`) writes a
30-minute test of holds within 20 N m that keeps the winding's forecast band 5 K under a 90 °C limit and
promises a standard error; the plant runs it (with its own sensor noise, a seed the plan never saw), the model
is fitted on that run, and the demo reports the standard error before, promised and obtained.
"""

from __future__ import annotations

import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

from thermolimb.demo_registry import DemoPage, demo_main, register_demo
from thermolimb.experiment import Limits, design
from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile
from thermolimb.plotting.fits import plt, save
from thermolimb.plotting.plan import plot_plan
from thermolimb.workbench.saving import saved_from_report
from thermolimb.workbench.validation import fit_and_validate

NAME = "next-experiment"
MODEL = "joule,second_node"
QUESTION = "frame_tau_s"  # the housing's time constant
LIMIT_C, MARGIN_K, PEAK_NM, TEST_S, NOISE_K = 90.0, 5.0, 20.0, 1800.0, 0.056


def _plant(profile: str, duration_s: float, seed: int):
    spec = replace(X8_9, network=NETWORKS["second_order"])
    return simulate_profile(profile, duration_s, 1.0, ["knee"], [spec],
                            PlantEffects.from_names(("sensor_noise", "quantisation")), seed=seed)


def _sized(report) -> dict:
    value, stderr = float(report.model.params[QUESTION]), float(report.stderr[QUESTION])
    return {"value_s": value, "stderr_s": stderr, "relative": stderr / abs(value)}


def _figure(summary: dict, out: Path) -> Path:
    fig, ax = plt.subplots(figsize=(7, 3.2))
    rows = [("the 10-minute log", summary["before"]), ("the plan's promise", summary["promised"]),
            ("the planned test, run", summary["after"])]
    for k, (label, row) in enumerate(rows):
        ax.errorbar(row["value_s"], k, xerr=row["stderr_s"], fmt="o", color="black" if k != 1 else "tab:blue",
                    capsize=4, label=None)
    ax.set_yticks(range(len(rows)), [label for label, _ in rows])
    ax.invert_yaxis()
    ax.set_xlabel("the housing's time constant (s), ± one standard error")
    ax.grid(alpha=0.3, axis="x")
    ax.set_title("what the next experiment tells")
    return save(fig, out / "sized.png")


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    b, p, a = summary["before"], summary["promised"], summary["after"]
    return [
        ("housing time constant, 10-minute log", f"{b['value_s']:.0f} ± {b['stderr_s']:.3g} s", "unsized"),
        ("standard error the plan promised", f"± {p['stderr_s']:.3g} s", f"a {summary['test_s']:.0f} s test"),
        ("after the planned test on the plant", f"{a['value_s']:.0f} ± {a['stderr_s']:.3g} s",
         f"obtained / promised {summary['obtained_over_promised']:.2f}"),
        ("hottest true winding during the test", f"{summary['hottest_true_C']:.1f} °C",
         f"limit {LIMIT_C:g} °C, band kept {MARGIN_K:g} K under it"),
    ]


def _finding(summary: dict) -> str:
    b, a = summary["before"], summary["after"]
    return (f"In this run the housing's time constant went from {b['value_s']:.0f} ± {b['stderr_s']:.3g} s on the "
            f"10-minute log to {a['value_s']:.0f} ± {a['stderr_s']:.3g} s after the planned test, "
            f"{summary['obtained_over_promised']:.2f} times the standard error the plan promised, the winding "
            f"never above {summary['hottest_true_C']:.1f} °C.")


PAGE = DemoPage(
    about="A short log cannot size a slow mass; thermolimb plan designs the test that can, within the "
          "actuator's limits, and says beforehand what it will tell. Look at the plan's figure (the holds, the "
          "predicted winding, its band kept under the limit) and at how the standard error falls from the short "
          "log to the test, next to what the plan promised.",
    headline=_headline,
    captions={
        "plan_knee.png": "The planned test: the effort set-points (top) and the predicted winding with the upper end "
                         "of its 90 % forecast interval, kept 5 K under the 90 °C limit (bottom).",
        "sized.png": "The housing's time constant with ± one standard error: from the 10-minute log, as the plan "
                     "promised it (blue), and from the planned test run on the plant.",
    },
    finding=_finding)


@register_demo(NAME, "the next experiment: the test that sizes what a short log could not, run on the plant",
               page=PAGE, cost_s=15.0)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    first = _plant("random", 600.0, seed=5).log
    report = fit_and_validate(first.runs("knee"), MODEL)
    saved = replace(saved_from_report(report, []), limit_C=LIMIT_C)
    limits = Limits(limit_C=LIMIT_C, max_effort=PEAK_NM, duration_s=TEST_S, start_C=25.0, margin_K=MARGIN_K)
    plan = design(saved, [QUESTION], limits, noise_K=NOISE_K, seed=0)
    plot_plan(plan, out)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "plan.csv"
        plan.table().to_csv(path, index=False)
        test = _plant(str(path), TEST_S, seed=7)
    after = _sized(fit_and_validate(test.log.runs("knee"), MODEL))
    promised = plan.stderr_after[QUESTION]
    summary = {
        "before": _sized(report),
        "promised": {"value_s": plan.values[QUESTION], "stderr_s": promised},
        "after": after,
        "obtained_over_promised": after["stderr_s"] / promised,
        "hottest_predicted_C": plan.hottest_C,
        "hottest_true_C": float(np.max(test.true_winding_C)),
        "test_s": TEST_S,
        "peak_effort_Nm": float(np.max(np.abs(plan.effort))),
    }
    _figure(summary, out)
    return summary


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
