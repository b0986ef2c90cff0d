"""The designed test against what a user would run instead (issue: the next experiment).

For each open question a first log leaves -- a slow mass a short log cannot size, a lagging sensor on a log
sampled too slowly, copper's tempco without hot and cool phases at one effort, motion cooling on a log without
motion -- the plant (with the effect) writes the first log; the model with the named term is fitted on it
(``thermolimb fit --save``); then three tests of the same length, peak effort and winding limit are run on the
plant and fitted:

* **designed**: ``thermolimb plan --identify PARAM`` (the Fisher information of the free run);
* **prbs**: a pseudo-random binary sequence between rest and the peak, switching at most once a hold (MATLAB
  ``idinput``'s 'prbs'), seeded;
* **random**: holds at random levels between rest and the peak ('rgs' held), seeded.

PRBS and random holds are scaled down, as the plan is, until the model's forecast band stays under the same
limit less its margin.  The table: the parameter's standard error after each test (its fit), whether the
question is answered (relative standard error at most 10 %), the hottest true winding on the plant, and the
promised standard error against the obtained one.

    python benchmarks/plan.py [--json] [--cases slow_mass,sensor_lag,tempco,motion_cooling,separate_tempco]

``separate_tempco`` asks ``plan --separate joule,winding_tempco`` instead of a standard error: the question is
answered where ``diagnose --auto`` on the test, from Joule heating alone, takes the tempco (its promised column is
the separation against the noise, ``separation_sigma``).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from thermolimb.experiment import DesignProblem, Limits, design, posed
from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile
from thermolimb.util.errors import ThermolimbError
from thermolimb.workbench.saving import saved_from_report
from thermolimb.workbench.validation import fit_and_validate

ANSWERED = 0.10  # relative standard error at which a question counts as answered
SHARES = (0.25, 0.5, 0.75)  # the designed test's first quarter, half and three quarters, fitted on their own
SENSOR = ["sensor_noise", "quantisation"]


@dataclass(frozen=True)
class Case:
    name: str
    question: str
    network: str
    effects: tuple[str, ...]
    model: str
    identify: str
    first_s: float  # the first log's length
    first_dt_s: float
    first_profile: str
    test_s: float
    max_effort: float
    max_velocity: float = 0.0


CASES = {
    c.name: c
    for c in (
        Case(
            "slow_mass",
            "a slow mass a 10-minute log cannot size",
            "second_order",
            (),
            "joule,second_node",
            "frame_tau_s",
            600.0,
            1.0,
            "random",
            1800.0,
            20.0,
        ),
        Case(
            "sensor_lag",
            "a lagging sensor on a log sampled every 30 s",
            "first_order",
            ("sensor_lag",),
            "joule,sensor_lag",
            "sensor_tau_s",
            3600.0,
            30.0,
            "random",
            1800.0,
            20.0,
        ),
        Case(
            "tempco",
            "copper's tempco on a short log that stays cool",
            "first_order",
            ("winding_tempco",),
            "joule,winding_tempco",
            "alpha_per_K",
            300.0,
            1.0,
            "squat",
            1800.0,
            25.0,
        ),
        Case(
            "motion_cooling",
            "motion cooling on a log without motion",
            "first_order",
            ("motion_cooling",),
            "joule,motion_cooling",
            "cooling_per_rad_s",
            1800.0,
            1.0,
            "pulses",
            1800.0,
            20.0,
            3.0,
        ),
    )
}


def plant_run(case: Case, profile, duration_s: float, dt_s: float, seed: int):
    spec = replace(X8_9, network=NETWORKS[case.network])
    fx = PlantEffects.from_names(SENSOR + list(case.effects))
    return simulate_profile(str(profile), duration_s, dt_s, ["knee"], [spec], fx, seed=seed)


def fitted(log, model: str):
    return fit_and_validate(log.runs("knee"), model)


def guessed(saved, model: str):
    """``saved`` with the terms of ``model`` it lacks added at their parameters' typical values (a guess, with no
    standard error): what a user plans from when the first log cannot identify a term at all."""
    from thermolimb.model import ThermalModel, model_parameters, parse_model

    parameters = model_parameters(parse_model(model))
    extended = ThermalModel(model, {p.name: saved.model.params.get(p.name, p.typical) for p in parameters})
    names = [p.name for p in extended.parameters]
    old = [p.name for p in saved.model.parameters]
    cov = np.zeros((len(names), len(names)))
    at = [names.index(n) for n in old]
    cov[np.ix_(at, at)] = saved.covariance
    return replace(
        saved,
        model=extended,
        covariance=cov,
        jackknife=None,
        stderr={n: float(saved.stderr.get(n, 0.0)) for n in names},
        units={p.name: saved.units.get(p.name, p.unit) for p in parameters},
    )


def alternative(kind: str, problem: DesignProblem, rng: np.random.Generator) -> np.ndarray:
    """A PRBS or random-hold vector of hold levels, in the plan's own parametrisation."""
    holds = problem.holds
    if kind == "prbs":
        levels = rng.integers(0, 2, holds).astype(float)
        levels[0] = 1.0  # start by heating, as a user would
    else:
        levels = rng.uniform(0.0, 1.0, holds)
    return np.concatenate([levels, rng.uniform(0.0, 1.0, holds) if problem.moves else []])


def run_case(case: Case, folder: Path, seed: int = 0) -> dict:
    first = plant_run(case, case.first_profile, case.first_s, case.first_dt_s, seed).log
    try:
        report = fitted(first, case.model)
        saved = replace(saved_from_report(report, []), limit_C=90.0)
        before = float(report.stderr[case.identify]) / abs(float(report.model.params[case.identify]))
    except ThermolimbError:  # the first log cannot identify the term at all: planned from a guess at its size
        base = ",".join(t for t in case.model.split(",") if t != case.model.split(",")[-1])
        saved, before = (
            guessed(replace(saved_from_report(fitted(first, base), []), limit_C=90.0), case.model),
            np.inf,
        )
    limits = Limits(
        limit_C=90.0,
        max_effort=case.max_effort,
        duration_s=case.test_s,
        start_C=25.0,
        max_velocity=case.max_velocity,
    )
    noise = 0.06  # the plant's sensor: about 0.06 K (noise and 0.1 degC steps), the floor diagnose reports
    started = time.perf_counter()
    plan = design(saved, [case.identify], limits, noise_K=noise, seed=seed)
    planning_s = time.perf_counter() - started
    t = plan.time_s
    holds = int(round(case.test_s / plan.hold_s))  # the alternatives switch on the plan's own grid of holds
    problem = DesignProblem(
        saved,
        t,
        np.minimum((np.arange(t.size) * holds) // t.size, holds - 1),
        holds,
        limits,
        plan.noise_K,
        (case.identify,),
        False,
        plan.velocity is not None,
    )
    rng = np.random.default_rng(seed + 100)
    runs = {}
    out = {
        "case": case.name,
        "question": case.question,
        "parameter": case.identify,
        "first_relative_stderr": before,
        "plan_s": planning_s,
        "tests": {},
    }
    for kind in ("designed", "prbs", "random"):
        if kind == "designed":
            effort, velocity, promised = plan.effort, plan.velocity, plan.stderr_after[case.identify]
        else:
            x, _ = problem.checked(alternative(kind, problem, rng))
            effort, velocity = problem.inputs(x)
            velocity = velocity if problem.moves else None
            k = problem.names.index(case.identify)
            promised = float(np.sqrt(problem.covariance(x)[k, k]))
        path = folder / f"{case.name}_{kind}.csv"
        table = {"time": t, "actuator": "knee", "effort": effort}
        if velocity is not None:
            table["velocity"] = velocity
        import pandas as pd

        pd.DataFrame(table).to_csv(path, index=False)
        run = plant_run(case, path, case.test_s, 1.0, seed + 7)
        runs[kind] = run.log.runs("knee")[0]
        try:
            fit = fitted(run.log, case.model)
        except ThermolimbError as exc:  # the test's log cannot identify the model: the question stays open
            out["tests"][kind] = {
                "value": None,
                "stderr": None,
                "relative_stderr": float("inf"),
                "answered": False,
                "promised": promised,
                "obtained_over_promised": None,
                "error": str(exc),
                "hottest_true_winding_C": float(np.max(run.true_winding_C)),
                "peak_effort": float(np.max(np.abs(effort))),
            }
            continue
        value, stderr = float(fit.model.params[case.identify]), float(fit.stderr[case.identify])
        out["tests"][kind] = {
            "value": value,
            "stderr": stderr,
            "relative_stderr": stderr / max(abs(value), 1e-300),
            "answered": stderr / max(abs(value), 1e-300) <= ANSWERED,
            "promised": promised,
            "obtained_over_promised": stderr / promised if promised > 0 else None,
            "hottest_true_winding_C": float(np.max(run.true_winding_C)),
            "peak_effort": float(np.max(np.abs(effort))),
        }
    out["designed_time_to_best_alternative_s"] = time_to(runs["designed"], case, out["tests"])
    return out


def time_to(designed, case: Case, tests: dict) -> float | None:
    """How much of the designed test reaches the best alternative's relative standard error, each share of it
    (:data:`SHARES`, then the whole) fitted on its own as a shorter test would be: the seconds, or ``None``
    where even the whole does not.  A share of a test designed for the whole length is not the test a plan for
    that length would design, so this is an upper bound on the time a design needs."""
    target = min(tests[k]["relative_stderr"] for k in ("prbs", "random"))
    for share in SHARES:
        part = designed.slice(0, int(round(share * designed.n)))
        try:
            fit = fit_and_validate([part], case.model)
        except ThermolimbError:
            continue
        value = abs(float(fit.model.params[case.identify]))
        if float(fit.stderr[case.identify]) / max(value, 1e-300) <= target:
            return float(part.time_s[-1] - part.time_s[0])
    return case.test_s if tests["designed"]["relative_stderr"] <= target else None


SEPARATE = Case("separate_tempco", "copper's tempco told from Joule heating on a cool log (--separate)",
                "first_order", ("winding_tempco",), "joule", "alpha_per_K", 600.0, 1.0, "squat", 1800.0, 25.0)
PAIR = ("joule", "winding_tempco")


def run_separation(case: Case, folder: Path, seed: int = 0) -> dict:
    """``plan --separate joule,winding_tempco`` against a PRBS and random holds scaled to the same limits: each
    run on the plant (copper's tempco on) and walked from Joule heating alone by ``diagnose --auto``; answered
    where the walk takes the tempco.  Promised: the separation against the noise (``separation_sigma``)."""
    import pandas as pd

    from thermolimb.separation import SeparationProblem, rival, separate
    from thermolimb.workbench.diagnosis import auto_diagnose

    first = plant_run(case, case.first_profile, case.first_s, case.first_dt_s, seed).log
    saved = replace(saved_from_report(fitted(first, case.model), []), limit_C=90.0)
    _, steps = auto_diagnose(first.runs("knee"), case.model, quiet=True)
    limits = Limits(limit_C=90.0, max_effort=case.max_effort, duration_s=case.test_s, start_C=25.0)
    started = time.perf_counter()
    plan = separate(saved, PAIR, limits, noise_K=0.06, seed=seed)
    planning_s = time.perf_counter() - started
    base, _ = posed(saved, (), limits, 0.06)
    problem = SeparationProblem(base, rival(saved, PAIR)[0].model)
    rng = np.random.default_rng(seed + 100)
    out = {"case": case.name, "question": case.question, "parameter": case.identify,
           "first_relative_stderr": float("inf") if case.identify not in steps[-1].model else 0.0,
           "first_takes": [s.get("change", "start") for s in steps[0].auto], "plan_s": planning_s, "tests": {}}
    for kind in ("designed", "prbs", "random"):
        if kind == "designed":
            effort, promised = plan.effort, plan.separation_sigma
        else:
            x, _ = problem.checked(alternative(kind, problem, rng))
            effort = problem.inputs(x)[0]
            promised = float(np.sqrt(np.sum(problem.part(x)[0] ** 2)) / problem.noise)
        path = folder / f"{case.name}_{kind}.csv"
        pd.DataFrame({"time": plan.time_s, "actuator": "knee", "effort": effort}).to_csv(path, index=False)
        run = plant_run(case, path, case.test_s, 1.0, seed + 7)
        _, walk = auto_diagnose(run.log.runs("knee"), case.model, quiet=True)
        final = walk[-1].base
        taken = case.identify in final.model.params
        value = float(final.model.params[case.identify]) if taken else None
        stderr = float(final.stderr[case.identify]) if taken else None
        out["tests"][kind] = {
            "value": value, "stderr": stderr,
            "relative_stderr": stderr / abs(value) if taken else float("inf"),
            "answered": taken, "promised": promised, "obtained_over_promised": None,
            "hottest_true_winding_C": float(np.max(run.true_winding_C)),
            "peak_effort": float(np.max(np.abs(effort))), "walk": [s.get("change", "start") for s in walk[0].auto],
        }
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--cases", default=",".join([*CASES, SEPARATE.name]))
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.cases.split(","):
            run = run_separation if name == SEPARATE.name else run_case
            rows.append(run(CASES.get(name, SEPARATE), Path(tmp), args.seed))
    if args.json:
        json.dump(rows, sys.stdout, indent=2)
        print()
        return 0
    print(
        f"{'case':16s} {'first':>7s} {'test':9s} {'value':>10s} {'rel. SE':>8s} {'answered':>8s} "
        f"{'promised':>9s} {'obt/prom':>8s} {'hottest':>8s}"
    )
    for r in rows:
        for kind, x in r["tests"].items():
            value = float("nan") if x["value"] is None else x["value"]
            print(
                f"{r['case']:16s} {100 * r['first_relative_stderr']:6.1f}% {kind:9s} {value:10.4g} "
                f"{100 * x['relative_stderr']:7.2f}% {str(x['answered']):>8s} {x['promised']:9.3g} "
                f"{x['obtained_over_promised'] or float('nan'):8.2f} {x['hottest_true_winding_C']:8.1f}"
            )
        reach = r.get("designed_time_to_best_alternative_s", "n/a")
        reach = "never" if reach is None else reach if isinstance(reach, str) else f"{reach:.0f} s"
        print(f"{'':16s} plan took {r['plan_s']:.1f} s; the designed test reaches the best alternative's error "
              f"in {reach}")
    designed = [r["tests"]["designed"] for r in rows]
    print(
        f"designed answers {sum(d['answered'] for d in designed)} of {len(rows)}; prbs "
        f"{sum(r['tests']['prbs']['answered'] for r in rows)}; random {sum(r['tests']['random']['answered'] for r in rows)}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
