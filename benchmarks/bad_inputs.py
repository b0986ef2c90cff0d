"""A careless user's battery: bad inputs on every command and both environments, each outcome classified.

    python benchmarks/bad_inputs.py            # the table of outcomes and the counts
    python benchmarks/bad_inputs.py --json     # one record per input

Every input runs in its own process (so that a hang is a timeout, not a stuck
benchmark) in a scratch folder holding a small valid log and its broken
variants.  An outcome is

``clear``
    refused with exit status 2 and one line on stderr, and nothing written
    (no new file, no ``.partial``), or, where the input is legal but needs a
    word (a gap in time, rows left out), exit 0 with that word on stderr;
``traceback``
    a Python traceback or another exit status;
``silent``
    exit 0 without the expected refusal or word;
``left behind``
    refused, but a file was written or a temporary left;
``hang``
    still running after the timeout (60 s; a Ray address that does not
    answer has its own 10 s limit).

Faults from the machine and the shell (a full disk behind standard output or
an output folder, a reader that closes the pipe, SIGTERM from ``timeout``)
are ``clear`` when the command ends with their own status -- 1 with one
sentence naming what could not be written, 141 and nothing said for a closed
pipe, 143 for SIGTERM -- and leaves no file behind.  The full-disk cases
mount a small tmpfs (root only; skipped, and said, elsewhere).

Environments' bad actions (NaN, out of range, stepping after the end) are
``clear`` when the step raises an error of one line and the environment still
steps after it (or after ``reset`` for stepping past the end), or when
``gymnasium.make`` refuses its arguments in one line.  Finite continuous
actions outside the box are clipped by design (documented), so they are not
in the battery.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import textwrap
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parent.parent
BAG = ROOT / "thermolimb" / "data" / "real" / "interbotix-wx200" / "waist_diagnostics.bag"
TIMEOUT_S = 60.0
HEX = "thermolimb/HexapodLoadCarry-v0"
HUM = "thermolimb/HumanoidThermalRecovery-v0"


# ------------------------------------------------------------------ fixtures
def _frame(n: int = 300) -> pd.DataFrame:
    t = np.arange(float(n))
    rows = []
    for name, gain in (("knee", 1.0), ("hip", 0.6)):
        rows.append(pd.DataFrame({"time": t, "actuator": name, "effort": gain * (5 + 3 * np.sin(t / 20)),
                                  "temperature": 30 + gain * 0.02 * t + 0.5 * np.sin(t / 30)}))
    return pd.concat(rows, ignore_index=True)


def write_fixtures(d: Path) -> None:
    good = _frame()
    good.to_csv(d / "good.csv", index=False)
    good.drop(columns="temperature").to_csv(d / "no_temperature.csv", index=False)
    good.rename(columns={"effort": "torque_Nm"}).to_csv(d / "misnamed.csv", index=False)
    bad = good.copy()
    bad.loc[10, "effort"] = np.nan
    bad.to_csv(d / "nan_effort.csv", index=False)
    bad = good.copy()
    bad.loc[5, "time"] = np.nan
    bad.to_csv(d / "nan_time.csv", index=False)
    bad = good.copy()
    bad.loc[20:30, "time"] = 3.0
    bad.to_csv(d / "time_backwards.csv", index=False)
    bad = good.copy()
    bad["time"] = pd.Timestamp("2026-01-01") + pd.to_timedelta(bad["time"], unit="s")
    bad.to_parquet(d / "datetime_time.parquet")
    bad.assign(time=bad["time"].dt.strftime("%Y-%m-%dT%H:%M:%S")).to_csv(d / "iso_time.csv", index=False)
    good.assign(time=[f"t{k}" for k in range(len(good))]).to_csv(d / "text_time.csv", index=False)
    good.assign(effort=good["effort"].astype(str).where(good.index != 7, "high")).to_csv(d / "text_effort.csv",
                                                                                          index=False)
    bad = good.copy()
    bad.loc[12, "actuator"] = None
    bad.to_csv(d / "blank_actuator.csv", index=False)
    bad = good.copy()
    bad.loc[bad.index >= 150, "time"] += 1e7
    bad.loc[(bad.index >= 450), "time"] += 1e7
    bad.to_csv(d / "gap.csv", index=False)
    good.assign(effort=4.0).to_csv(d / "constant_effort.csv", index=False)
    good.assign(temperature=good["temperature"] + 1e4).to_csv(d / "hot_10000C.csv", index=False)
    good.assign(effort=np.inf).to_csv(d / "inf_effort.csv", index=False)
    good.head(3).to_csv(d / "three_rows.csv", index=False)
    good.head(0).to_csv(d / "header_only.csv", index=False)
    (d / "empty.csv").write_text("")
    (d / "junk.csv").write_bytes(bytes(range(256)) * 40)
    (d / "junk.parquet").write_bytes(b"PAR1" + os.urandom(500))
    (d / "junk.mcap").write_bytes(b"\x89MCAP0\r\n" + os.urandom(500))
    (d / "log.txt").write_text("time effort temperature\n0 1 2\n")
    (d / "truncated.bag").write_bytes(BAG.read_bytes()[:20000])
    (d / "empty_folder").mkdir()
    (d / "afile").write_text("not a folder\n")
    (d / "dir.csv").mkdir()
    (d / "index_dir").mkdir()
    (d / "index_dir" / "index.html").mkdir()
    (d / "corrupt").mkdir()
    (d / "corrupt" / "diagnose").mkdir()
    (d / "corrupt" / "diagnose" / "summary.json").write_text("{not json")


# ------------------------------------------------------------------ the battery
UNREADABLE = ("empty.csv", "junk.csv", "junk.parquet", "junk.mcap", "truncated.bag", "missing.csv", "empty_folder",
              "nothing*.csv")
READ_ONLY = "/proc/thermolimb"  # a read-only place even for root (permission bits do not bind root)
CLEAR, WORD = "refuse", "word"  # expected: exit 2, or exit 0 with a word on stderr (a regex)


def cli_cases() -> list[tuple[str, list[str], str, str | None]]:
    """(name, argv, expected, regex of the word on stdout or stderr) for the command line."""
    cases = []

    def refuse(name, *argv):
        cases.append((name, list(argv), CLEAR, None))

    def word(name, pattern, *argv):
        cases.append((name, list(argv), WORD, pattern))

    # logs as users bring them
    for log in ("no_temperature.csv", "misnamed.csv", "nan_effort.csv", "nan_time.csv", "time_backwards.csv",
                "text_time.csv", "text_effort.csv", "blank_actuator.csv", "constant_effort.csv",
                "hot_10000C.csv", "inf_effort.csv", "three_rows.csv", "header_only.csv", "empty.csv", "junk.csv",
                "junk.parquet", "junk.mcap", "log.txt", "truncated.bag", "missing.csv", "empty_folder",
                "nothing*.csv", "afile"):
        for command in ("fit", "diagnose"):
            refuse(f"{command} {log}", command, log, "--quiet")
        if log in UNREADABLE:
            refuse(f"inspect {log}", "inspect", log)
    word("inspect a space-separated .txt (one column shown)", r"1 column", "inspect", "log.txt")
    word("fit a log with a 1e7 s gap", r"segment|gap", "fit", "gap.csv", "--quiet")
    word("fit datetime times (parquet)", r"time stamps turned into seconds", "fit", "datetime_time.parquet", "--quiet", "--json")
    word("fit ISO timestamps (csv)", r"time stamps turned into seconds", "fit", "iso_time.csv", "--quiet", "--json")
    word("fit --drop-incomplete with NaN", r"left out|dropped|missing", "fit", "nan_effort.csv", "--drop-incomplete",
         "--quiet")
    # options of the log commands
    for argv in (["--map", "effort=effort,effort=temperature"], ["--map", "effort"], ["--map", "torque=effort"],
                 ["--map", "effort=nope"], ["--cv", "0"], ["--cv", "-2"], ["--cv", "abc"], ["--cv", "1000000"],
                 ["--split", "0"], ["--split", "1"], ["--split", "nan"], ["--split", "-0.5"],
                 ["--model", "joule,warp_drive"], ["--model", ""],
                 ["--method", "magic"], ["--actuator", "elbow"], ["--velocity-unit", "furlong"],
                 ["--sep", "pipe"], ["--plot", "afile"], ["--plot", READ_ONLY], ["--html", "empty_folder"],
                 ["--html", f"{READ_ONLY}/page.html"], ["--validate-on", "missing.csv"],
                 ["--validate-on", "junk.csv"]):
        refuse("fit good.csv " + " ".join(argv), "fit", "good.csv", "--quiet", *argv)
    for argv in (["--refit", "some"], ["--auto", "--model", "nope"], ["--plot", "afile"], ["--cv", "0"]):
        refuse("diagnose good.csv " + " ".join(argv), "diagnose", "good.csv", "--quiet", *argv)
    for argv in (["--model", "joule", "--model", "joule,nope"], ["--plot", "afile"]):
        refuse("compare good.csv " + " ".join(argv), "compare", "good.csv", "--quiet", *argv)
    for argv in (["--workers", "0"], ["--workers", "-1"], ["--backend", "threads"], ["--table", "rows.xlsx"],
                 ["--table", "empty_folder"], ["--cv", "runs"], ["--backend", "ray", "--address", "127.0.0.1:1"]):
        refuse("fit --fleet " + " ".join(argv), "fit", "good.csv", "--fleet", "--quiet", *argv)
    refuse("fit --fleet bag and table mixed", "fit", "good.csv", str(BAG), "--fleet", "--quiet")
    # simulate
    for argv in (["--duration", "inf"], ["--duration", "nan"], ["--duration", "1e15"], ["--duration", "0"],
                 ["--duration", "-5"], ["--duration", "ten"], ["--dt", "0"], ["--dt", "-0.1"], ["--dt", "nan"],
                 ["--dt", "100", "--duration", "10"], ["--ambient", "-500"], ["--ambient", "nan"],
                 ["--ambient", "inf"], ["--ambient", "400"], ["--seed", "-1"], ["--seed", "1.5"],
                 ["--load-scale", "-2"], ["--load-scale", "nan"], ["--load-scale", "inf"],
                 ["--actuators", "knee"], ["--actuators", "knee:NOPE"], ["--actuators", "a:X8_9,a:X8_9"],
                 ["--actuators", ""], ["--network", "x9"], ["--effects", "warp"], ["--effects", "none,tempco"],
                 ["--profile", "moonwalk"]):
        refuse("simulate " + " ".join(argv), "simulate", "--out", "sim.csv", "--quiet", "--duration", "60", *argv)
    for out in ("dir.csv", "afile/a.csv", f"{READ_ONLY}/a.csv", "sim.xlsx", "empty_folder"):
        refuse(f"simulate --out {out}", "simulate", "--duration", "60", "--quiet", "--out", out)
    # strategies
    for argv in (["--env", "thermolimb/Nope-v0"], ["--episodes", "0"], ["--episodes", "-3"], ["--episodes", "nan"],
                 ["--seed", "-1"], ["--strategies", "teleport"], ["--strategies", ""], ["--max-time", "nan"],
                 ["--max-time", "0"], ["--max-time", "-5"], ["--max-time", "inf"], ["--workers", "0"],
                 ["--plot", "afile"], ["--backend", "ray", "--address", "127.0.0.1:1"]):
        base = ["compare-strategies", "--env", HEX, "--episodes", "1", "--strategies", "vertical_only", "--quiet",
                "--plot", "strategies"]
        refuse("compare-strategies " + " ".join(argv), *base, *argv)
    # demos and reports
    for argv in (["nope"], ["diagnose", "--out", "afile"], ["diagnose", "--out", READ_ONLY]):
        refuse("demo " + " ".join(argv), "demo", *argv, "--quick", "--quiet")
    for target in ("afile", "missing_folder", "empty_folder", "corrupt", "index_dir", READ_ONLY):
        refuse(f"report {target}", "report", target)
    refuse("unknown command", "frobnicate")
    return cases


ENV_SNIPPET = textwrap.dedent("""
    import json, sys
    import numpy as np
    import gymnasium as gym
    import hexapod_pb, humanoid_pb
    env_id, kwargs, action, after_end = sys.argv[1], json.loads(sys.argv[2]), json.loads(sys.argv[3]), sys.argv[4]
    try:
        env = gym.make(env_id, disable_env_checker=True, **kwargs).unwrapped
    except Exception as exc:
        print(json.dumps({"raised": type(exc).__name__, "lines": len(str(exc).strip().splitlines()), "at": "make"}))
        sys.exit(0)
    if after_end == "options":  # reset with options the environment does not take
        try:
            env.reset(seed=0, options=action)
            print(json.dumps({"raised": None}))
        except Exception as exc:
            env.reset(seed=0)
            env.step(env.action_space.sample())  # still usable
            print(json.dumps({"raised": type(exc).__name__, "lines": len(str(exc).strip().splitlines())}))
        sys.exit(0)
    env.reset(seed=0)
    if after_end == "yes":
        for _ in range(100000):
            _, _, term, trunc, _ = env.step(env.action_space.sample())
            if term or trunc:
                break
    act = np.array(action, dtype=float) if isinstance(action, list) else action
    try:
        env.step(act)
        print(json.dumps({"raised": None}))
    except Exception as exc:
        message = str(exc)
        if after_end == "yes":
            env.reset(seed=1)
        env.step(env.action_space.sample())  # still usable
        print(json.dumps({"raised": type(exc).__name__, "lines": len(message.strip().splitlines())}))
""")


def env_cases() -> list[tuple[str, list[str]]]:
    nan, inf = float("nan"), float("inf")
    cases = [
        ("hexapod NaN action", [HEX, "{}", json.dumps([nan, 0.5, 0.5, 0.5]), "no"]),
        ("hexapod inf action", [HEX, "{}", json.dumps([0.5, inf, 0.5, 0.5]), "no"]),
        ("hexapod action of the wrong shape", [HEX, "{}", json.dumps([0.5, 0.5]), "no"]),
        ("hexapod step after the end", [HEX, json.dumps({"max_time_s": 2.0}), json.dumps([0.5] * 4), "yes"]),
        ("humanoid mode -1", [HUM, "{}", "-1", "no"]),
        ("humanoid mode 3", [HUM, "{}", "3", "no"]),
        ("humanoid mode 1.5", [HUM, "{}", "1.5", "no"]),
        ("humanoid configuration NaN", [HUM, json.dumps({"action_type": "configuration"}),
                                        json.dumps([nan, 0.0, 0.0, 0.0]), "no"]),
        ("humanoid configuration inf", [HUM, json.dumps({"action_type": "configuration"}),
                                        json.dumps([0.0, -inf, 0.0, 0.0]), "no"]),
        ("humanoid step after the end", [HUM, json.dumps({"max_time_s": 1.0}), "0", "yes"]),
    ]
    for env_id in (HEX, HUM):
        short = env_id.split("/")[1]
        for value in ("nan", "-1", "0"):
            cases.append((f"{short} max_time_s={value}", [env_id, json.dumps({"max_time_s": float(value)}),
                                                          "null", "no"]))
    cases.append(("humanoid action_type='torque'", [HUM, json.dumps({"action_type": "torque"}), "0", "no"]))
    for env_id in (HEX, HUM):
        short = env_id.split("/")[1]
        for options in ({"payload_kg": 3.0}, "fast", [1, 2]):
            cases.append((f"{short} reset(options={json.dumps(options)})", [env_id, "{}", json.dumps(options),
                                                                            "options"]))
        cases.append((f"{short} a reset range the wrong way round", [env_id, json.dumps(
            {"ambient_range_C": [30.0, 20.0]}), "null", "no"]))
    return cases


# ------------------------------------------------------------------ faults from the machine and the shell
FULL = "full"  # a tmpfs of 64 KiB mounted in the scratch folder for the full-disk cases


def fault_cases() -> list[tuple[str, list[str], str, int]]:
    """(name, argv, how, expected exit status): ``how`` is full_stdout, closed_pipe, sigterm or full_disk."""
    cases = []
    for extra in ([], ["--json"]):
        cases.append((f"fit {' '.join(extra)} > /dev/full".replace("  ", " "), ["fit", "good.csv", "--quiet", *extra],
                      "full_stdout", 1))
        cases.append((f"fit {' '.join(extra)} | a reader that closes at once".replace("  ", " "),
                      ["fit", "good.csv", "--quiet", *extra], "closed_pipe", 141))
    cases.append(("inspect good.csv > /dev/full", ["inspect", "good.csv"], "full_stdout", 1))
    cases.append(("fit --fleet > /dev/full", ["fit", "good.csv", "--fleet", "--quiet"], "full_stdout", 1))
    cases.append(("fit --fleet | a reader that closes at once", ["fit", "good.csv", "--fleet", "--quiet"],
                  "closed_pipe", 141))
    for out in ("run.csv", "run.parquet", "run.mcap"):
        cases.append((f"simulate --out {FULL}/{out} on a full disk", ["simulate", "--duration", "3600", "--quiet",
                                                                       "--out", f"{FULL}/{out}"], "full_disk", 1))
    cases.append((f"fit --plot {FULL}/plots on a full disk", ["fit", "good.csv", "--quiet", "--plot", f"{FULL}/plots"],
                  "full_disk", 1))
    cases.append((f"fit --html {FULL}/page.html on a full disk", ["fit", "good.csv", "--quiet", "--html",
                                                                   f"{FULL}/page.html"], "full_disk", 1))
    cases.append((f"fit --fleet --table {FULL}/rows.csv on a full disk", ["fit", "good.csv", "--fleet", "--quiet",
                                                                           "--table", f"{FULL}/rows.csv"], "full_disk", 1))
    for seconds in ("1", "3"):
        cases.append((f"simulate --out big.csv, SIGTERM after {seconds} s", ["simulate", "--duration", "100000",
                                                                              "--dt", "0.5", "--quiet", "--out",
                                                                              "big.csv", f"@{seconds}"], "sigterm", 143))
    return cases


def _mount_full(d: Path) -> bool:
    (d / FULL).mkdir(exist_ok=True)
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(d / FULL)], capture_output=True)
    return done.returncode == 0


def run_fault(d: Path, name: str, argv: list[str], how: str, expected: int, can_fill: bool) -> dict:
    if how == "full_disk" and not can_fill:
        return {"input": name, "outcome": "skipped", "message": "no tmpfs here (needs root)"}
    filler = d / FULL / ".filler"
    if how == "full_disk":  # every block taken, so the command's first write meets a full disk
        with open(filler, "wb", buffering=0) as f:
            try:
                while True:
                    f.write(b"\0" * 4096)
            except OSError:
                pass
    before = _listing(d)
    command = [sys.executable, "-m", "thermolimb.cli.main", *[a for a in argv if not a.startswith("@")]]
    try:
        if how == "closed_pipe":
            proc = subprocess.Popen(command, cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            proc.stdout.close()
            err = proc.stderr.read()
            code = proc.wait(timeout=TIMEOUT_S)
        elif how == "sigterm":
            proc = subprocess.Popen(command, cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            time.sleep(float(argv[-1][1:]))
            proc.terminate()
            _, err = proc.communicate(timeout=TIMEOUT_S)
            code = proc.returncode
        else:
            with open("/dev/full" if how == "full_stdout" else os.devnull, "w") as out:
                done = subprocess.run(command, cwd=d, stdout=out, stderr=subprocess.PIPE, text=True, timeout=TIMEOUT_S)
            err, code = done.stderr, done.returncode
    except subprocess.TimeoutExpired:
        return {"input": name, "outcome": "hang"}
    new = sorted(p for p in _listing(d) - before if not p.startswith(FULL + "/") or not (d / p).is_dir())
    lines = err.strip().splitlines()
    record = {"input": name, "exit": code, "message": lines[-1] if lines else ""}
    # SIGTERM before the command has started (Python still importing) ends it by the signal itself, as any tool
    if how == "sigterm" and code == -15:
        code = expected
    if "Traceback" in err or code != expected or len(lines) > 1 or (how == "closed_pipe" and lines):
        outcome = "traceback"
    elif new:
        outcome = "left behind"
        record["written"] = new
    else:
        outcome = "clear"
    filler.unlink(missing_ok=True)
    _remove(d, sorted(_listing(d) - before, reverse=True))
    return {**record, "outcome": outcome}


# ------------------------------------------------------------------ running
def _listing(d: Path) -> set[str]:
    return {str(p.relative_to(d)) for p in d.rglob("*")}


def _remove(d: Path, paths) -> None:
    """What an input wrote, so that the next input starts clean."""
    for path in paths:
        target = d / path
        if target.is_dir():
            shutil.rmtree(target, ignore_errors=True)
        elif target.exists():
            target.unlink()


def run_cli(d: Path, name: str, argv: list[str], expected: str, pattern: str | None) -> dict:
    before = _listing(d)
    started = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "thermolimb.cli.main", *argv], cwd=d, capture_output=True,
                              text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return {"input": name, "outcome": "hang", "seconds": TIMEOUT_S}
    seconds = time.perf_counter() - started
    new = sorted(_listing(d) - before)
    err = done.stderr.strip()
    lines = err.splitlines()
    record = {"input": name, "exit": done.returncode, "seconds": round(seconds, 2),
              "message": lines[-1] if lines else ""}
    if "Traceback" in err or done.returncode not in (0, 2):
        outcome = "traceback"
    elif done.returncode == 2:
        outcome = "clear" if len(lines) == 1 and not new else "left behind"
        if new:
            record["written"] = new
    elif expected == WORD and re.search(pattern, done.stdout + done.stderr):
        outcome = "clear"
    else:
        outcome = "silent"
    _remove(d, new)
    return {**record, "outcome": outcome}


def run_env(name: str, args: list[str]) -> dict:
    try:
        done = subprocess.run([sys.executable, "-c", ENV_SNIPPET, *args], capture_output=True, text=True,
                              timeout=TIMEOUT_S * 3, cwd=ROOT)
    except subprocess.TimeoutExpired:
        return {"input": name, "outcome": "hang"}
    if done.returncode != 0:  # the environment broke after the error (or before it)
        last = done.stderr.strip().splitlines()[-1] if done.stderr.strip() else ""
        return {"input": name, "outcome": "traceback", "message": last}
    result = json.loads(done.stdout.strip().splitlines()[-1])
    if result["raised"] is None:
        return {"input": name, "outcome": "silent"}
    outcome = "clear" if result["lines"] == 1 else "traceback"
    return {"input": name, "outcome": outcome, "message": result["raised"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", action="store_true", help="print one record per input")
    parser.add_argument("--only", default="", help="run only inputs whose name contains this")
    args = parser.parse_args()
    records = []
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        write_fixtures(d)
        for name, argv, expected, pattern in cli_cases():
            if args.only in name:
                records.append(run_cli(d, name, argv, expected, pattern))
        for name, argv in env_cases():
            if args.only in name:
                records.append(run_env(name, argv))
        faults = [case for case in fault_cases() if args.only in case[0]]
        can_fill = bool(faults) and _mount_full(d)
        try:
            for name, argv, how, expected in faults:
                records.append(run_fault(d, name, argv, how, expected, can_fill))
        finally:
            if can_fill:
                subprocess.run(["umount", str(d / FULL)], capture_output=True)
    counts = Counter(r["outcome"] for r in records)
    if args.json:
        print(json.dumps({"counts": counts, "inputs": records}, indent=1))
        return
    for r in records:
        print(f"{r['outcome']:12s} {r['input'][:70]:70s} {r.get('message', '')[:110]}")
    print(f"{len(records)} bad inputs: " + ", ".join(f"{k} {counts[k]}" for k in
                                                      ("clear", "traceback", "silent", "left behind", "hang",
                                                       "skipped")))


if __name__ == "__main__":
    main()
