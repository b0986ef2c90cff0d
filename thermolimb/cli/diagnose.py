"""``thermolimb diagnose``: where does the model fail, and what should change."""

from __future__ import annotations

import sys
from pathlib import Path

from ..model.parameter_units import spaced
from ..util.atomic import file_stem
from ..util.errors import UsageError
from ..util.numbers import plus_minus
from ..workbench.diagnosis import Search, auto_diagnose, diagnose
from ..workbench.diagnosis.proposal import write_proposal
from ..workbench.diagnosis.questions import open_questions
from ..workbench.diagnosis.stability import MIN_FREQUENCY, REPLICATES, Stability
from .output import format_params
from .template import LogCommand, Run
from .types import SEED, integer, number, output_file
from .verdict import verdict_text


class Diagnose(LogCommand):
    name = "diagnose"
    help = "find where the thermal model fails and which physical effect is missing"
    description = ("Fit the model (output error, on the first --split of each run), analyse its residual "
                   "(autocorrelation; cross-correlation with effort, effort^2, |velocity|, current^2, power, "
                   "ambient, the housing and the neighbours' "
                   "temperatures; RMSE by phase), try every change worth "
                   "trying (add an effect, drop a term, swap the "
                   "heat source), validate each on held-out data and "
                   "recommend the one that helps most, if it is "
                   "plausible and identifiable. --auto takes recommended"
                   " changes while one helps. --discover also tries "
                   "every extra channel the log carries (heat, "
                   "conductance, boundary forms) and, when nothing "
                   "helps and the residual has structure, a form "
                   "found by sparse regression; --propose writes it as a Term. Errors in K.")
    model_help = "model to diagnose"
    fleet = True
    discovers = True
    json_help = "print the diagnosis as one JSON object"
    plot_help = "write the diagnosis plots into DIR"
    saves = True
    save_help = ("write each actuator's final model (with --auto: "
                 "the walk's last; else the recommended change's, or "
                 "the model as given) to a model file (JSON; docs/model-file.md)")

    def add_options(self, p):
        p.add_argument("--auto", action="store_true",
                       help="take the recommended change (add, drop or "
                            "swap) while one helps, never revisiting a "
                            "model, and draw the waterfall")
        p.add_argument("--refit", choices=("strong", "all"), default="strong",
                       help="refit only additions with a strong score test "
                            "(default) or all of them; drops and swaps "
                            "are always refitted")
        p.add_argument("--discover", action="store_true",
                       help="open the vocabulary: try the log's extra "
                            "channels as heat, conductance or boundary, and "
                            "propose a form the catalog lacks when nothing "
                            "else helps (labelled 'discovered'); with "
                            "--auto, such changes are taken under the same gates as catalog effects")
        g = p.add_argument_group("stability of a verdict")
        g.add_argument("--stability", type=integer(0, 1000), default=REPLICATES, metavar="K",
                       help="before recommending a change, repeat the "
                            "search on K perturbed replicates of the log "
                            "(rows trimmed at either end, the split "
                            "moved, other starts) and recommend it only if "
                            "enough of them take it, K more where the "
                            "first K leave it within one replicate of that "
                            f"share (default {REPLICATES}; 0 turns the check off)")
        g.add_argument("--min-frequency", type=number(0.0, 1.0, low_open=True), default=MIN_FREQUENCY,
                       metavar="F", help="the share of replicates that must take a "
                       "change for it to be recommended (default " f"{MIN_FREQUENCY})")
        g.add_argument("--stability-seed", type=SEED, default=0, metavar="N", help="seed of the replicates' "
                       "perturbations (the same seed gives the same frequencies)")
        p.add_argument("--explain", action="store_true",
                       help="print every change's evidence, the start "
                            "model's flags and what would tell confounded "
                            "changes apart (the default text leads with "
                            "the answer: what is missing, the error "
                            "before and after, how sure, what next)")
        p.add_argument("--propose", type=output_file, default=None, metavar="FILE",
                       help="with --discover: write the generated terms "
                            "of the recommended (with --auto: the final) "
                            "model as a Python file of Term classes, "
                            "to read, rename, keep and load with --terms")

    def check(self, args):
        if args.propose and not args.discover:
            raise UsageError("--propose writes what --discover finds; add --discover")
        if args.stability == 1:
            raise UsageError("--stability needs at least 2 replicates (or 0 to turn the check off)")
        if args.fleet and args.discover:
            raise UsageError("--discover works on the logs of one "
                             "command, not with --fleet; diagnose a run of "
                             "interest with --discover, then load what it proposes in the fleet with --terms")

    def analyse(self, run: Run, name, series, scheme):
        args, model = run.args, run.models[0]
        stability = (Stability(args.stability, args.min_frequency, args.stability_seed) if args.stability
                     else None)
        search = Search(scheme, args.refit, args.discover, run.datasheet, stability, quiet=args.quiet)
        if args.auto:
            d, steps = auto_diagnose(series, model, search)
            final = steps[-1].base
        else:
            d = diagnose(series, model, search)
            steps = [d]
            final = d.recommended.report if d.recommended is not None else d.base
        run.kept.append((name, final))  # each actuator's final model, for --propose
        run.final[name] = final
        if args.plot:
            from ..plotting.diagnosis import plot_diagnosis

            plot_diagnosis(d, Path(args.plot), file_stem(name), steps)
        if run.page is not None:
            from ..plotting.interactive import add_diagnosis

            add_diagnosis(run.page, d, steps)
        questions = open_questions(final, steps[-1])
        record = {**d.to_json(), "open_questions": questions.to_json()}
        text = describe_diagnosis(d) if args.explain else verdict_text(d, steps, questions, args.discover)
        return record, text

    def finish(self, run: Run):
        if run.args.propose:
            print(write_proposal(Path(run.args.propose), run.kept), file=sys.stderr)


add_parser = Diagnose().add_parser


def describe_diagnosis(d) -> str:
    b = d.base.validation
    lines = [f"{d.actuator}: model {','.join(d.model)}: validation RMSE {b['rmse_K']:.3f} K, "
             f"largest error {b['max_abs_K']:.3f} K ({d.base.scheme})"]
    lines += format_params(d.base)
    if d.heat_source is not None:
        lines.append(f"  {d.heat_source['sentence']}")
    if d.floor is not None:
        lines.append(f"  {d.floor.sentence(b['rmse_K'])}")
    k = d.stability["replicates"] if d.stability else None
    w = max([32] + [len(c.label) for c in d.candidates])  # the widest label sets the column
    lines.append(f"  {'change':{w}s} {'RMSE K':>8s} {'gain %':>7s} {'dBIC':>9s} {'taken':>6s}  status")
    for c in d.candidates:
        if not c.refitted:
            lines.append(f"  {c.label:{w}s} {'':>8s} {'':>7s} {'':>9s} "
                         f"{'':>6s}  {c.status}: {c.not_refitted_because}")
            continue
        taken = f"{round(c.selection_frequency * k)}/{k}" if c.selection_frequency is not None else ""
        lines.append(f"  {c.label:{w}s} {c.rmse_K:8.3f} "
                     f"{100 * c.improvement:7.1f} {c.delta_bic:9.1f} {taken:>6s}  "
                     f"{c.status}")
        for pname, v in c.params.items():
            lines.append(f"      {pname} = {plus_minus(v['value'], v['stderr'], 4)}{spaced(v['unit'])}")
        lines.append(f"      {c.evidence}")
    evidence = d.base.evidence
    if not evidence.rankable:
        lines.append("  recommended: none (the evidence above is too thin to carry a recommendation)")
    elif d.at_floor:
        lines.append("  recommended: none (the model is already at the sensor's floor)")
    elif d.unstable is not None and d.recommended is None:
        lines.append(f"  recommended: none ({d.unstable.label} helps but is {d.unstable.held_back_because})")
    else:
        warn = f" (on {evidence.verdict} evidence: a hint)" if d.recommended and evidence.thin else ""
        if d.unstable is not None:
            u, r = d.unstable, d.recommended
            warn += (f" ({r.label} taken in {round(r.selection_frequency * k)} "
                     f"of {k} replicates; {u.label} helps "
                     f"more on the whole log, {u.rmse_K:.3f} against {r.rmse_K:.3f} K, but is taken in "
                     f"{round(u.selection_frequency * k)} of {k})")
        lines.append(f"  recommended: {d.recommended.label if d.recommended else 'none'}{warn}")
    if d.auto:
        lines.append("  steps:")
        for step in d.auto:
            head = (
                f"    {step.get('change', 'start'):28s} -> {','.join(step['model'])}: {step['rmse_K']:.3f} K"
            )
            lines.append(head + (f"  ({step['why']})" if "why" in step else ""))
            lines += [f"      ! {flag}" for flag in step["flags"]]
    return "\n".join(lines)
