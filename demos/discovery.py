"""Demo ``discovery``: the diagnosis learns an effect its catalog does not have, and hands over the term it found.

The plant's motor weakens its field above a base speed (current that makes no
torque heats the winding), and a holding brake heats it while engaged; the
log has the brake's state (``brake [1]``) but no current.  The catalog alone
reaches for its nearest shape (speed losses).  With ``--discover`` the
diagnosis tries the brake channel as a heat, a conductance or a boundary, and,
when no change helps any more, a sparse regression over physical features of
the log proposes the form the catalog lacks.  The terms it took are written as
a Python file (``proposed_terms.py``), which loads back with ``--terms``.
"""

from __future__ import annotations

from pathlib import Path

from thermolimb.demo_registry import DemoPage, demo_main, kelvin, register_demo
from thermolimb.logs import from_frame
from thermolimb.model.parameter_units import spaced
from thermolimb.model.terms import TERMS
from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS
from thermolimb.plotting.diagnosis import plot_diagnosis
from thermolimb.workbench.diagnosis import auto_diagnose
from thermolimb.workbench.diagnosis.proposal import write_proposal
from thermolimb.workbench.validation import fit_and_validate

NAME = "discovery"
PROPOSAL = "proposed_terms.py"


def _walk(first) -> list[dict]:
    return [{"change": step.get("change", "start"), "model": step["model"], "rmse_K": step["rmse_K"]}
            for step in first.auto]


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for key, label in (("catalog_only", "catalogue terms only"), ("with_discovery", "with --discover")):
        steps = summary[key]
        rows.append((f"validation RMSE, {label}", kelvin(steps[-1]["rmse_K"]),
                     f"from {kelvin(steps[0]['rmse_K'])} ({', '.join(s['change'] for s in steps[1:]) or 'no change'})"))
    rows.append(("validation RMSE, the plant's law refitted", kelvin(summary["true_law_K"]),
                 "current and brake logged: current_heating + the brake's heat"))
    for name, p in summary["generated_params"].items():
        rows.append((f"fitted parameter {name}", f"{p['value']:.4g} ± {p['stderr']:.2g}{spaced(p['unit'])}", "in the written term file"))
    return rows


def _finding(summary: dict) -> str:
    cat, disc = summary["catalog_only"], summary["with_discovery"]
    return (f"In this run --discover brings the held-out error from {kelvin(disc[0]['rmse_K'])} to "
            f"{kelvin(disc[-1]['rmse_K'])}, against {kelvin(cat[-1]['rmse_K'])} with the catalogue alone and "
            f"{kelvin(summary['true_law_K'])} for the plant's own law refitted.")


PAGE = DemoPage(
    about="A motor whose field weakens above a base speed, and a holding brake that heats it while engaged; the log "
          "carries the brake's state but not the current. The stepwise search runs with the catalogue alone, then "
          "with --discover, which tries the log's extra channels and proposes a form the catalogue lacks. Look at "
          "the waterfall: which step names the brake, which step is a discovered form, and how close the end is to "
          "the plant's own law refitted. The term file below is what --propose hands the user.",
    headline=_headline,
    finding=_finding,
    captions={"waterfall_knee.png": "Validation RMSE after each step of diagnose --auto --discover (red: a fitted "
                                    "value is flagged); channel and discovered terms are named as such."})


@register_demo(NAME, "channels and discovered forms: the effect the catalog lacks, found and written as a Term",
               page=PAGE)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    effects = PlantEffects.from_names("sensor_noise,quantisation,field_weakening,holding_brake")
    log = simulate_profile("random", (1 if quick else 2) * 3600.0, 1.0, list(CASE_NAMES), list(CASE_SPECS), effects,
                           seed=4, network=NETWORKS["first_order"], quiet=quiet).log
    no_current = [from_frame(log.frame.drop(columns="current"), units=log.units).series("knee")]
    catalog, _ = auto_diagnose(no_current, quiet=quiet)
    found, steps = auto_diagnose(no_current, quiet=quiet, discover=True)
    plot_diagnosis(found, out, "knee")
    final = steps[-1].base
    write_proposal(out / PROPOSAL, [("knee", final)])
    generated = [t for t in final.model.terms if TERMS[t].generated]
    params = final.to_json()["params"]
    brake = "brake_heat" if "brake_heat" in TERMS else None  # registered by the channel search above
    truth_model = ("current_heating",) + ((brake,) if brake else ())
    truth = fit_and_validate([log.series("knee")], truth_model).validation["rmse_K"]
    return {
        "catalog_only": _walk(catalog),
        "with_discovery": _walk(found),
        "proposals": [d.proposal.formula for d in steps if d.proposal is not None],
        "generated_terms": generated,
        "generated_params": {p.name: params[p.name] for t in generated for p in TERMS[t].parameters},
        "true_law_K": truth,
        "term_file": PROPOSAL if generated else None,
    }


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
