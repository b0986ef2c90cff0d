"""``diagnose``'s answer, read in ten seconds: what is missing, the error before and after, how sure, what to
do next, the walk's steps and the model it ends with, then one compact table of the changes tried.  Every fact
is said once; each change's evidence, the start model's flags and the confounded pairs' explanations are
``--explain``'s (and always in ``--json`` and ``--plot``)."""

from __future__ import annotations

from ..workbench.diagnosis.candidates import MIN_IMPROVEMENT
from .output import format_params

WIDEST = 28  # a change's label column, at most (longer labels are cut with an ellipsis)


def verdict_text(d, steps, questions, discover: bool = False) -> str:
    """The default text of one actuator's diagnosis ``d`` (with ``--auto``, ``steps`` are the walk's
    diagnoses, the first being ``d``; without, ``[d]``), with the ``questions`` it leaves open
    (:func:`~thermolimb.workbench.diagnosis.questions.open_questions`)."""
    last = steps[-1]
    lines = [_answer(d, last)]
    lines.append(f"  how sure: {'; '.join(_sureness(d, last))}")
    lines.append(f"  next: {_next(d, last, discover)}")
    unsized, pair = questions.identify, questions.separate
    if unsized:
        lines.append(f"  to size {', '.join(unsized)}, which this log leaves uncertain: save the model "
                     f"(--save " f"MODEL.json) and design the test that sizes it: thermolimb plan "
                     f"MODEL.json --identify " f"{','.join(unsized)} --max-effort E --duration S --out "
                     f"plan.csv")
    if pair:
        lines.append(f"  to tell {pair[1]} from {pair[0]}, which this log cannot: save the model (--save "
                     f"MODEL.json) " f"and design the test that can: thermolimb plan MODEL.json --separate "
                     f"{','.join(pair)} " f"--max-effort E --duration S --out plan.csv")
    if d.auto and len(d.auto) > 1:
        lines.append("  steps:")
        for step in d.auto:
            taken = step.get("selection_frequency")
            k = (d.stability or {}).get("replicates")
            share = f"  taken {round(taken * k)}/{k}" if taken is not None and k else ""
            lines.append(f"    {_cut(step.get('change', 'start')):{WIDEST}s} {step['rmse_K']:8.3f} K  "
                         f"{','.join(step['model'])}{share}")
    lines.append(f"  model {','.join(last.model)}:")
    lines += format_params(last.base, indent="    ", evidence=False)
    lines += _table(d)
    lines.append("  (each change's evidence: --explain; everything: --json, --plot)")
    return "\n".join(lines)


def _answer(d, last) -> str:
    # the walk's start: the effort model where the first step is the heat source's swap to current
    before = d.auto[0]["rmse_K"] if d.auto else d.base.validation["rmse_K"]
    taken = [s["change"] for s in (d.auto or [])[1:]]
    if taken:
        return (
            f"{d.actuator}: missing {', '.join(taken)}: validation RMSE {before:.3f} K -> "
            f"{last.base.validation['rmse_K']:.3f} K"
        )
    r = d.recommended
    if r is not None and not d.auto:
        return (
            f"{d.actuator}: missing {r.label}: validation RMSE {before:.3f} K -> {r.rmse_K:.3f} K "
            f"(recommended; --auto takes it)"
        )
    return f"{d.actuator}: nothing to add to {','.join(d.model)}: validation RMSE {before:.3f} K"


def _sureness(d, last) -> list[str]:
    from ..workbench.diagnosis.stability import share_interval

    k = (d.stability or {}).get("replicates")
    shares = []
    for s in (d.auto or [])[1:]:
        if s.get("selection_frequency") is None or not k:
            continue
        n = round(s["selection_frequency"] * k)
        lo, hi = share_interval(n, k)
        shares.append(f"{s['change']} taken in {n} of {k} perturbed replicates (95 % interval "
                      f"{100 * lo:.0f}-{100 * hi:.0f} %)")
    return shares + [last.base.evidence.sentence().removeprefix("evidence: ")]


def _next(d, last, discover: bool) -> str:
    rmse = last.base.validation["rmse_K"]
    if last.at_floor:
        floor = last.floor.sentence(rmse).partition(" against ")[2].partition(": nothing more")[0]
        return f"none: {rmse:.3f} K is at the sensor's floor, {floor}: nothing more can be told apart"
    if not last.base.evidence.rankable:
        return ("the evidence is too thin to rank changes: a longer log, with more heating and cooling, "
                "would tell")
    if last.unstable is not None and last.recommended is None:
        u = last.unstable
        return f"{u.label} helps ({u.rmse_K:.3f} K) but is {u.held_back_because}; the walk stops before it"
    if last.recommended is not None and not d.auto:
        return "take it with --auto (or --model " + ",".join(last.recommended.model) + ")"
    floor = (
        f", {rmse / last.floor.floor_K:.0f} times the sensor's floor"
        if last.floor and last.floor.floor_K
        else ""
    )
    more = "" if discover else "; --discover tries the log's other channels and proposes a form"
    barred = next((c for c in last.candidates if c.helps and not c.eligible), None)
    if barred is not None:  # the best held-out gain, barred by a gate: said, with the gate
        why = f": {barred.implausible_because}" if barred.status == "implausible" else ""
        return (f"{barred.label} helps ({barred.rmse_K:.3f} K held out) but is {barred.status}{why}; "
                f"no change is taken: {rmse:.3f} K remains{floor}{more}")
    return (
        f"no change helps by {100 * MIN_IMPROVEMENT:.0f} % on held-out data; {rmse:.3f} K remains{floor}"
        f"{more}"
    )


def _table(d) -> list[str]:
    """The changes tried at the start: a row for each refitted one, then one line per reason the others were
    not (not refitted, confounded, ...: named, their explanations --explain's)."""
    k = d.stability["replicates"] if d.stability else None
    rows = [
        f"  changes tried on {','.join(d.model)}:",
        f"  {'change':{WIDEST + 2}s} {'RMSE K':>8s} {'gain %':>7s} {'dBIC':>9s} {'taken':>6s}  status",
    ]
    others: dict[str, list[str]] = {}
    for c in d.candidates:
        if c.refitted:
            taken = (
                f"{round(c.selection_frequency * k)}/{k}" if c.selection_frequency is not None and k else ""
            )
            rows.append(f"  {_cut(c.label):{WIDEST + 2}s} {c.rmse_K:8.3f} {100 * c.improvement:7.1f} "
                        f"{c.delta_bic:9.1f} {taken:>6s}  {c.status}")
        else:
            others.setdefault(c.status, []).append(c.label)
    rows += [f"  {status}: {', '.join(labels)}" for status, labels in others.items()]
    return rows


def _cut(label: str) -> str:
    return label if len(label) <= WIDEST else label[: WIDEST - 1] + "…"
