"""Mutation score of the default (not slow) test suite over the numerical core, with mutmut.

    pip install -e ".[mutation]"
    python benchmarks/mutation.py --sample 400 --seed 0

What is mutated is set in ``setup.cfg``'s ``[mutmut]`` section: ``thermolimb/model``,
``identification``, ``diagnosis`` (not its plots), ``logs``, ``plant`` and
``hexapod_pb/wrench.py``.  mutmut runs, for each mutant, the tests that
execute the mutated function (from its own coverage statistics), from the
default (not slow) suite less the tests that run whole robots, demos,
fleets, browsers and command lines (listed in ``setup.cfg``; they take
minutes and call everything): a mutant a subset kills, the whole suite
kills, so the score is a lower bound.

The whole population is several thousand mutants, hours on two cores; the
score is estimated on a seeded random sample, with a 95 % Wilson interval.
Survivors are listed with their diff (``mutmut show NAME``) so that
equivalent mutants -- a mutation no test could notice, such as a changed
error message or a default the callers always override -- can be judged by
hand; the report prints the score with and without the ones judged
equivalent in ``benchmarks/mutation_equivalent.txt``.

mutmut's sanity check (every test must fail when every mutant raises) fails
here with a collection error rather than test failures: module-level
constants (``X8_9 = ActuatorSpec(...)``) call mutated functions at import.
That is the failure the check asks for, so it is accepted as such; mutants
run in processes forked after the import, so a mutant of a function only
module-level code calls counts as surviving (the score is a lower bound).
"""

from __future__ import annotations

import argparse
import json
import math
import random
import subprocess
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MUTANTS = ROOT / "mutants"
EQUIVALENT = Path(__file__).with_name("mutation_equivalent.txt")

WORKER = """
import sys
import mutmut.__main__ as mm
from mutmut.runners.harness import BadTestExecutionCommandsException

checked = mm.run_forced_fail_test

def forced_fail(runner):
    try:
        checked(runner)
    except BadTestExecutionCommandsException:  # collection failed at import: the forced failure happened
        mm.set_mutant_under_test("")

mm.run_forced_fail_test = forced_fail
mm.cli(["run", "--max-children", sys.argv[1], *sys.argv[2:]])
"""


def run_mutmut(names: list[str], children: int) -> None:
    subprocess.run([sys.executable, "-c", WORKER, str(children), *names], cwd=ROOT, check=False)


def exit_codes() -> dict[str, int | None]:
    codes = {}
    for meta in sorted(MUTANTS.rglob("*.meta")):
        codes.update(json.loads(meta.read_text())["exit_code_by_key"])
    return codes


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    if n == 0:
        return 0.0, 1.0
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half


def equivalent_names() -> set[str]:
    if not EQUIVALENT.exists():
        return set()
    return {line.split()[0] for line in EQUIVALENT.read_text().splitlines() if line.strip() and not line.startswith("#")}


STATUS = {1: "killed", 3: "killed", -24: "timeout", 36: "timeout", 0: "survived", 33: "no tests", 5: "no tests"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sample", type=int, default=400, help="mutants drawn at random (default 400)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--children", type=int, default=2, help="mutants tested at once")
    parser.add_argument("--report-only", action="store_true", help="summarise the last run without running")
    args = parser.parse_args()
    if not args.report_only:
        if not MUTANTS.exists():
            run_mutmut(["__generate_only__"], args.children)  # generates mutants and coverage, then matches nothing
        population = sorted(exit_codes())
        sample = sorted(random.Random(args.seed).sample(population, min(args.sample, len(population))))
        (MUTANTS / "sample.json").write_text(json.dumps({"seed": args.seed, "population": len(population),
                                                         "sample": sample}))
        run_mutmut(sample, args.children)
    drawn = json.loads((MUTANTS / "sample.json").read_text())
    codes = exit_codes()
    status = {name: STATUS.get(codes.get(name), "suspicious" if codes.get(name) is not None else "not checked")
              for name in drawn["sample"]}
    counts = Counter(status.values())
    equivalent = equivalent_names() & {n for n, s in status.items() if s in ("survived", "no tests")}
    killed = counts["killed"] + counts["timeout"]
    tested = killed + counts["survived"] + counts["no tests"]  # a mutant no selected test runs is not killed
    print(f"population {drawn['population']} mutants, sample {len(drawn['sample'])} (seed {drawn['seed']}): "
          + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    lo, hi = wilson(killed, tested)
    print(f"killed {killed} of {tested} decided: {killed / max(tested, 1):.1%} (95 % {lo:.1%}-{hi:.1%})"
          + (f"; {counts['not checked']} not reached (mutmut runs the quickly tested first: a partial run is "
             "biased towards them)" if counts["not checked"] else ""))
    non_eq = tested - len(equivalent)
    lo, hi = wilson(killed, non_eq)
    print(f"judged equivalent {len(equivalent)}; killed {killed} of {non_eq} non-equivalent: "
          f"{killed / max(non_eq, 1):.1%} (95 % {lo:.1%}-{hi:.1%})")
    by_module = Counter()
    for name, s in status.items():
        by_module[(name.rsplit(".x", 1)[0], s)] += 1
    for module in sorted({m for m, _ in by_module}):
        print(f"  {module}: " + ", ".join(f"{s} {c}" for (m, s), c in sorted(by_module.items()) if m == module))
    survivors = sorted(n for n, s in status.items() if s in ("survived", "no tests") and n not in equivalent)
    print(f"survivors not judged equivalent ({len(survivors)}):")
    for name in survivors:
        print("  " + name)


if __name__ == "__main__":
    main()
