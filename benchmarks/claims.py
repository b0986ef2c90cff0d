"""Re-run a declared sample of the numbers README.md and docs/ state, and compare.

Each claim names the page, the words the page says (which must still be there:
a page edited without its claim here is caught too), the command the page names,
and the numbers to read from the command's output.  A claim holds when the page
still says it and every number comes back within its tolerance.

    python benchmarks/claims.py            # every claim (about 8 minutes on two cores)
    python benchmarks/claims.py --list     # the claims, without running them
    python benchmarks/claims.py --only tour-walk,bag-diagnose

Exit status 1 when a claim does not hold.  The commands run in a scratch folder,
with the suite's own command line (``python -m thermolimb.cli.main``).
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
THERMOLIMB = [sys.executable, "-m", "thermolimb.cli.main"]
UR3 = ROOT / "thermolimb/data/real/ur3-cobotops/dataset_02052023.csv"
UR3_MAP = "time=Timestamp,effort=Current_J{j},temperature=Temperature_*{j},velocity=Speed_J{j}"
BAG = ROOT / "thermolimb/data/real/interbotix-wx200/waist_diagnostics.bag"
WX200 = [ROOT / f"thermolimb/data/real/interbotix-wx200/wx200_{run}_bearing.csv" for run in ("ext", "home")]
WX200_MAP = "time=States Time [s],effort=Effort [mA],temperature=Temp [C],velocity=Velocity [rad/s]"
BLDC = [ROOT / f"thermolimb/data/real/tass-bldc-bench/{run}_unified.csv"
        for run in ("Run2-Throttle100", "Run13-Throttle8")]
BLDC_MAP = "time=Time (s),effort=Power (W),power=Power (W),temperature=Winding Temp (°C)"


@dataclass(frozen=True)
class Claim:
    name: str
    page: str  # path from the repository's root
    says: str  # words the page says, whitespace-insensitive
    # run in order in one scratch folder, the last one's output read: the suite's command line, or
    # ("BENCHMARK", "name.py", args...) for a script of benchmarks/
    commands: tuple[tuple[str, ...], ...]
    pattern: str  # a regular expression on the last command's output (stdout and stderr)
    expected: tuple  # a float per group (compared within ``tolerance``), or a string (compared as written)
    tolerance: float = 0.02  # relative


TOUR_LOG = ("simulate", "--profile", "random", "--duration", "3600", "--dt", "1", "--network", "first_order",
            "--effects", "sensor_noise,quantisation,speed_losses", "--out", "run.csv", "--quiet")

CLAIMS = (
    Claim("tour-walk", "README.md",
          "validation RMSE 7.056 K → 0.059 K",
          (TOUR_LOG, ("diagnose", "run.csv", "--actuator", "knee", "--auto", "--quiet")),
          r"start\s+-> joule,effort_bias: ([\d.]+) K.*?\+ speed_losses\s+-> joule,effort_bias,speed_losses: ([\d.]+) K"
          r".*?taken in (\d+) of 10",
          (7.056, 0.059, 10.0)),
    Claim("tour-three-mass", "README.md",
          "6.778 K → `+ speed_losses` 2.603 K → `+ neighbor_coupling` 2.196 K",
          (tuple(a for a in TOUR_LOG if a not in ("--network", "first_order")),
           ("diagnose", "run.csv", "--actuator", "knee", "--auto", "--quiet")),
          r"start\s+-> joule,effort_bias: ([\d.]+) K.*?\+ speed_losses\s+->[^:]*: ([\d.]+) K"
          r".*?\+ neighbor_coupling\s+->[^:]*: ([\d.]+) K.*?taken in (\d+) of 10",
          (6.778, 2.603, 2.196, 10.0)),
    Claim("tour-predict", "README.md",
          "reaches 90.0 degC from 30.0 degC in 91 s (90 % interval 77 s to 112 s)",
          (TOUR_LOG, ("diagnose", "run.csv", "--actuator", "knee", "--auto", "--save", "knee.json", "--limit-C", "90",
                      "--quiet"),
           ("predict", "knee.json", "--hold", "20,1", "--duration", "3600", "--start-C", "30")),
          r"reaches 90\.0 degC from 30\.0 degC in (\d+) s \(90 % interval (\d+) s to (\d+) s\)",
          (91.0, 77.0, 112.0), tolerance=0.03),
    Claim("tour-forecast", "README.md",
          "held the true time in 93 % and 81 % of cases at 1 and 15 min, 0.27 and 0.37 times as wide",
          (("BENCHMARK", "forecast.py", "--no-real"),),
          r"diagnose --auto model\s+horizon\s+60s:.*?coverage (\d+) %, median width ([\d.]+)x.*?"
          r"diagnose --auto model\s+horizon\s+900s:.*?coverage (\d+) %, median width ([\d.]+)x",
          (93.0, 0.27, 81.0, 0.37)),
    Claim("travel-refit", "docs/travel.md",
          "| UR3 J1 | 33.00 | 0.00018 | 0.0006 % | effort_bias: 0.040 → 16.705 | 0.041 |",
          (("BENCHMARK", "travel.py", "--blocks", "1", "--steps", "20"),),
          r"UR3 J1 .*?rise\s+([\d.]+) K.*?dropped effort_bias: ([\d.]+) -> ([\d.]+) K RMSE on the log, refitted ([\d.]+) K",
          (33.00, 0.040, 16.705, 0.041)),
    Claim("pmsm-sensors-transfer", "docs/workbench.md",
          "| stator tooth | profile 24 | 75.244 K | 10.661 K | heat from current, `+ second_node` |",
          (("BENCHMARK", "transfer.py", "--sources", "pmsm-sensors"),),
          r"fit on pmsm_stator_tooth_profile24\s+default ([\d.]+) K, walk ([\d.]+) K.*?"
          r"fit on pmsm_pm_profile46\s+default ([\d.]+) K, walk ([\d.]+) K.*?better in (\d+) of (\d+) cases, more "
          r"than 5 % worse in (\d+)",
          (75.244, 10.661, 74.230, 56.249, 6.0, 6.0, 0.0)),
    Claim("bag-diagnose", "docs/logs.md",
          "takes nothing: dropping the effort bias helps on the held-out part (0.598 → 0.510 K",
          (("diagnose", str(BAG), "--actuator", "waist", "--quiet"),),
          r"validation RMSE ([\d.]+) K against.*?- effort_bias\s+([\d.]+).*?recommended: (\w+)",
          (0.598, 0.510, "none")),
    Claim("ur3-j5-walk", "docs/workbench.md",
          "| J5 (wrist 3) | 0.306 → 0.194 (re-measured",
          (("diagnose", str(UR3), "--drop-incomplete", "--map", UR3_MAP, "--actuator", "J5", "--auto", "--quiet",
            "--split", "0.7"),),
          r"start\s+-> joule,effort_bias: ([\d.]+) K.*?- effort_bias\s+->[^:]*: ([\d.]+) K",
          (0.306, 0.194)),
    Claim("wx200-runs", "docs/workbench.md",
          "| waist | 0.524 | nothing | 0.605 → 0.560 (− effort bias, 10/10;",
          (("diagnose", str(WX200[0]), str(WX200[1]), "--map", WX200_MAP, "--actuator", "waist", "--auto",
            "--quiet"),),
          r"start\s+-> joule,effort_bias: ([\d.]+) K.*?- effort_bias\s+->[^:]*: ([\d.]+) K.*?taken in (\d+) of 10",
          (0.605, 0.560, 10.0)),
    Claim("bldc-runs", "docs/workbench.md",
          "| bldc | 10.210 → 4.735 | − effort bias (10/10) | 39.531 → 37.333 (− effort bias, 10/10;",
          (("diagnose", str(BLDC[0]), str(BLDC[1]), "--map", BLDC_MAP, "--actuator", "bldc", "--auto", "--quiet"),),
          r"start\s+-> joule,effort_bias: ([\d.]+) K.*?- effort_bias\s+->[^:]*: ([\d.]+) K.*?taken in (\d+) of 10",
          (39.531, 37.333, 10.0)),
    Claim("humanoid-strategies", "docs/environments.md",
          "thermal-aware recovers in 9.75 ± 1.15 s against 18.75 ± 9.59 s",
          (("compare-strategies", "--env", "thermolimb/HumanoidThermalRecovery-v0", "--episodes", "6", "--seed", "0",
            "--strategies", "thermal_aware,minimum_effort"),),
          r"thermal_aware\s+([\d.]+) ± [\d.]+ \(6\)\s+([\d.]+) ± ([\d.]+) \(6\).*?"
          r"minimum_effort\s+([\d.]+) ± [\d.]+ \(6\)\s+([\d.]+) ± ([\d.]+) \(6\)",
          (7.06, 9.75, 1.15, 6.06, 18.75, 9.59)),
    Claim("soak-protection", "docs/reliability.md",
          "| 219, 181, 276 °C | 225, 184, 228 °C |",
          (("BENCHMARK", "protection.py"),),
          r"seed 0, protection on the measured: hottest true winding \[([\d.]+), ([\d.]+), ([\d.]+)\].*?"
          r"seed 0, protection on the observer: hottest true winding \[([\d.]+), ([\d.]+), ([\d.]+)\].*?"
          r"seed 1, protection on the measured: hottest true winding \[([\d.]+), ([\d.]+), ([\d.]+)\]",
          (218.7, 180.7, 276.1, 153.0, 152.6, 152.9, 224.8, 184.0, 228.4), tolerance=0.005),
    Claim("brake-propose", "docs/workbench.md",
          "validation RMSE 6.039 K → 0.060 K",
          (("simulate", "--profile", "random", "--duration", "3600", "--dt", "1", "--network", "first_order",
            "--effects", "sensor_noise,quantisation,holding_brake", "--out", "brake.csv", "--quiet"),
           ("diagnose", "brake.csv", "--actuator", "knee", "--auto", "--discover", "--quiet")),
          r"start\s+-> joule,effort_bias: ([\d.]+) K.*\+ brake_heat[^:]*: ([\d.]+) K",
          (6.039, 0.060)),
    Claim("filtering-bias", "docs/measurements.md",
          "it returns RC = 60 s for a true 80 s",
          (("BENCHMARK", "identification.py"),),
          r"RC_s\s+true\s+80\s+paper\s+([\d.]+)\s+consistent LS\s+([\d.]+)\s+output error\s+([\d.]+)",
          (60.0, 80.1, 80.0)),
    Claim("minimax-walking", "docs/hexapod.md",
          "the per-stride peak falls only **8.8 %** (1.056 → 0.964)",
          (("BENCHMARK", "wrench.py"),),
          r"per-step peak normalised torque: vertical-only ([\d.]+), minimax ([\d.]+) \(-([\d.]+) %",
          (1.056, 0.964, 8.8), tolerance=0.01),
    Claim("thermal-ik-left", "docs/humanoid.md",
          "the fast method ends lower (left 1.9811 M vs 1.9823 M",
          (("BENCHMARK", "thermal_ik.py"),),
          r"left\s+naive.*?potential\s+(\d+) \| fast.*?potential\s+(\d+) with Gamma",
          (1982300.0, 1981100.0), tolerance=0.0001),
)


def normalise(text: str) -> str:
    return re.sub(r"\s+", " ", text)


def check(claim: Claim, folder: Path) -> dict:
    page = normalise((ROOT / claim.page).read_text(encoding="utf-8"))
    on_page = normalise(claim.says) in page
    start = time.perf_counter()
    output = ""
    for command in claim.commands:
        # a benchmark of this folder, or the suite's command line
        argv = ([sys.executable, str(ROOT / "benchmarks" / command[1]), *command[2:]] if command[0] == "BENCHMARK"
                else [*THERMOLIMB, *command])
        done = subprocess.run(argv, cwd=folder, capture_output=True, text=True)
        output = done.stdout + done.stderr
        if done.returncode not in (0, 1):
            break
    seconds = time.perf_counter() - start
    match = re.search(claim.pattern, output, re.S)
    got = match.groups() if match else ()
    agree = bool(match) and all(
        (abs(float(g) - e) <= claim.tolerance * abs(e) + 1e-12) if isinstance(e, float) else g == e
        for g, e in zip(got, claim.expected))
    return {"claim": claim.name, "page": claim.page, "on_page": on_page, "expected": claim.expected,
            "measured": got or (("(not in the output: " + output.strip().splitlines()[-1][:120] + ")",)
                                if output.strip() else ("(no output)",)),
            "holds": on_page and agree, "seconds": seconds}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--list", action="store_true", help="list the claims and exit")
    parser.add_argument("--only", default=None, help="comma-separated claim names")
    args = parser.parse_args(argv)
    claims = CLAIMS
    if args.only:
        wanted = set(args.only.split(","))
        unknown = wanted - {c.name for c in CLAIMS}
        if unknown:
            parser.error(f"unknown claims {sorted(unknown)}; known: {', '.join(c.name for c in CLAIMS)}")
        claims = tuple(c for c in CLAIMS if c.name in wanted)
    if args.list:
        for c in claims:
            print(f"{c.name:20s} {c.page:20s} {c.says}")
        return 0
    failed = 0
    print(f"{'claim':20s} {'page':20s} {'on page':8s} {'holds':6s} {'time':>6s}  expected -> measured")
    for claim in claims:
        with tempfile.TemporaryDirectory() as scratch:
            r = check(claim, Path(scratch))
        failed += not r["holds"]
        expected = ", ".join(str(e) for e in r["expected"])
        print(f"{r['claim']:20s} {r['page']:20s} {str(r['on_page']):8s} {str(r['holds']):6s} {r['seconds']:5.0f}s  "
              f"{expected} -> {', '.join(r['measured'])}", flush=True)
    print(f"{len(claims) - failed} of {len(claims)} claims hold")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
