"""Every real log the repository carries, read as its lab wrote it: what a newcomer's first hour would be.

For each file (the bundled real logs and the PMSM bench, or every CSV, Parquet and bag of the folders given):

1. ``thermolimb inspect`` suggests a map, and says the words to add where it needs help (an effort no name
   says, ``--columns`` for a file without a header row);
2. the file is read with that map (plus only the words inspect named): *suggested*, *with inspect's words*, or
   the one sentence that refuses it;
3. ``fit`` (Jorgensen et al.'s model) and ``diagnose --auto`` on its actuator with the widest temperature span:
   the validation error, the walk, the sensor's floor;
4. where a source has several runs of the actuator (files of one folder read alike, or a log's own runs), the
   walk's model and the default fitted on the first run and validated on the others (``fit --validate-on``):
   *better* (at least 10 % lower), *worse* (more than 5 % higher) or *same*, and the error against the floor;
5. the log cut by five rows at either end and diagnosed again: the same walk, or not.

    python benchmarks/corpus.py [--json] [FOLDER ...]
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

from thermolimb.cli.main import main as thermolimb
from thermolimb.data import REAL_DIR
from thermolimb.logs import read_log

ROOT = Path(__file__).resolve().parents[1]
BUNDLED = [REAL_DIR, ROOT / "thermolimb" / "data" / "pmsm"]
SUFFIXES = (".csv", ".parquet", ".bag", ".mcap")
# hand-written help where inspect can only say what is missing: a file without a header row needs its columns'
# names, which only its lab knows (the GimbalBot logger's sketch names them)
HELP = {"gimbalbot-esc-motor/test01252015": ["--columns", "timeSinceStart,pwmOut,tempCelsius,tempRefCelsius"]}


def run(argv: list[str]) -> tuple[int, str, str]:
    """``thermolimb ARGV`` in this process: exit status, standard output, the last line of standard error."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = thermolimb(argv)
        except SystemExit as exc:
            code = int(exc.code or 0)
    lines = [line for line in err.getvalue().splitlines() if line.strip()]
    return code, out.getvalue(), lines[-1] if lines else ""


def options(path: Path, listing: dict) -> tuple[list[str], str]:
    """The read options inspect's listing gives (its map, its flags, the words it says to add), and how the
    file came to be read: ``suggested`` or ``with inspect's words``."""
    mapping = dict(listing.get("suggested_map") or {})
    how = "suggested"
    for note in listing.get("notes", []):
        if "add effort=" in note and "effort" not in mapping:
            mapping["effort"] = note.split("add effort=")[1].split()[0]
            how = "with inspect's words"
    args = ["--map", ",".join(f"{k}={v}" for k, v in mapping.items())] if mapping else []
    for flag in listing.get("flags", []):
        args += flag.split(" ", 1)
    return args, how


def widest(path: Path, args: list[str]) -> str | None:
    """The actuator with the widest span of readings (the one a user would look at first)."""
    mapping = args[args.index("--map") + 1] if "--map" in args else None
    columns = args[args.index("--columns") + 1].split(",") if "--columns" in args else None
    named = {} if path.suffix.lower() in (".bag", ".mcap") else {"actuator_name": path.stem}
    log = read_log(path, mapping=mapping, drop_incomplete="--drop-incomplete" in args, columns=columns, **named)
    spans = {name: float(np.ptp(log.series(name).temperature_C)) for name in log.actuators}
    return max(spans, key=spans.get) if spans else None


def trimmed(path: Path, folder: Path) -> Path:
    """The file without its first five and last five data rows (a bag is left whole)."""
    if path.suffix.lower() != ".csv":
        return path
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    head = next((k for k, line in enumerate(lines) if line.strip() and not line[0].isdigit()
                 and not line.startswith(("-", "+"))), -1)
    body = lines[head + 1:]
    out = folder / f"trim_{path.name}"
    out.write_text("\n".join(lines[:head + 1] + body[5:-5]) + "\n", encoding="utf-8")
    return out


def study(path: Path, folder: Path) -> dict:
    row = {"file": str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)}
    code, out, err = run(["inspect", str(path), "--json"])
    if code:
        return {**row, "read": f"inspect refused: {err}"}
    listing = json.loads(out)
    helped = next((words for key, words in HELP.items() if key in str(path)), [])
    if helped and any("no header row" in n for n in listing.get("notes", [])):
        listing = json.loads(run(["inspect", str(path), "--json", *helped])[1])
        listing["flags"] = [f for f in listing.get("flags", []) if not f.startswith("--columns")]
    args, how = options(path, listing)
    if helped and "--columns" not in args and any(n for n in listing.get("notes", [])):
        args, how = args + helped, "hand-written --columns"
    if not args:
        return {**row, "read": "no map suggested: " + "; ".join(listing.get("notes", []))[:200]}
    try:
        name = widest(path, args)
    except Exception as exc:  # noqa: BLE001 -- said in the table: the file is refused with this map
        return {**row, "read": f"refused with the suggested map: {str(exc)[:200]}", "options": args}
    if name == path.stem:  # a file of one actuator, named after the file: named alike in every file of its folder
        name = "joint"
    row.update(read=how, options=args, actuator=name)
    code, out, err = run(["fit", str(path), *args, "--actuator", name, "--json", "--quiet"])
    if code:
        return {**row, "fit": f"refused: {err[:240]}"}
    fit = json.loads(out)
    row["fit_rmse_K"] = fit["validation"]["rmse_K"]
    code, out, err = run(["diagnose", str(path), *args, "--actuator", name, "--auto", "--json", "--quiet"])
    if code:
        return {**row, "diagnose": f"refused: {err[:240]}"}
    d = json.loads(out)
    walk = [s["change"] for s in d.get("auto", [])[1:]]
    row.update(walk=walk, final_model=d["auto"][-1]["model"], walk_rmse_K=d["auto"][-1]["rmse_K"],
               floor_K=(d.get("floor") or {}).get("floor_K"))
    cut = trimmed(path, folder)
    if cut != path and not any("@" in a for a in args):  # (a file of several time bases is not cut by rows)
        code, out, _ = run(["diagnose", str(cut), *args, "--actuator", name, "--auto", "--json", "--quiet"])
        row["trim_same_walk"] = bool(code == 0 and [s["change"] for s in json.loads(out).get("auto", [])[1:]] == walk)
    return row


def transfer(rows: list[dict]) -> list[dict]:
    """For the files of one folder read with one map and one actuator name: fitted on the first, validated on
    the others, the walk's model against the default."""
    moved = []
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        if "walk_rmse_K" in r:
            groups.setdefault((str(Path(r["file"]).parent), json.dumps(r["options"]), r["actuator"]), []).append(r)
    for (_, opts, name), members in groups.items():
        if len(members) < 2:
            continue
        first, others = members[0], [m["file"] for m in members[1:]]
        args = json.loads(opts)
        errors = {}
        for label, model in (("default", None), ("walk", ",".join(first["final_model"]))):
            argv = ["fit", str(ROOT / first["file"]), *args, "--actuator", name, "--validate-on",
                    *[str(ROOT / o) for o in others], "--json", "--quiet"] + (["--model", model] if model else [])
            code, out, err = run(argv)
            errors[label] = json.loads(out)["validation"]["rmse_K"] if code == 0 else None
        d, w = errors["default"], errors["walk"]
        verdict = ("not run" if d is None or w is None else "better" if w <= 0.9 * d else
                   "worse" if w > 1.05 * d else "same")
        moved.append({"fitted_on": first["file"], "validated_on": others, "actuator": name, "default_rmse_K": d,
                    "walk_rmse_K": w, "verdict": verdict, "floor_K": first.get("floor_K")})
    return moved


def files(folders: list[Path]) -> list[Path]:
    return sorted(p for f in folders for p in Path(f).rglob("*") if p.suffix.lower() in SUFFIXES
                  and "raw" not in p.parts and not p.name.startswith("trim_"))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folders", nargs="*", type=Path, default=BUNDLED)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        rows = [study(p, Path(tmp)) for p in files(args.folders)]
        moved = transfer(rows)
    if args.json:
        json.dump({"files": rows, "transfer": moved}, sys.stdout, indent=2)
        print()
        return 0
    print(f"{'file':58s} {'read':22s} {'actuator':10s} {'fit K':>7s} {'walk K':>7s} {'floor K':>7s} trim  walk")
    for r in rows:
        if "walk_rmse_K" not in r:
            print(f"{r['file'][-58:]:58s} {r.get('read', '')[:22]:22s} {r.get('actuator') or '':10s}  "
                  f"{(r.get('fit') or r.get('diagnose') or r.get('read'))[:110]}")
            continue
        floor = f"{r['floor_K']:.3f}" if r.get("floor_K") else "-"
        same = {True: "same", False: "moved", None: "-"}[r.get("trim_same_walk")]
        print(f"{r['file'][-58:]:58s} {r['read'][:22]:22s} {r['actuator']:10s} {r['fit_rmse_K']:7.3f} "
              f"{r['walk_rmse_K']:7.3f} {floor:>7s} {same:5s} {', '.join(r['walk']) or 'nothing'}")
    print()
    for t in moved:
        d, w = (f"{v:.3f}" if v is not None else "not run" for v in (t["default_rmse_K"], t["walk_rmse_K"]))
        print(f"transfer {Path(t['fitted_on']).name} -> {', '.join(Path(v).name for v in t['validated_on'])}: "
              f"default {d} K, the walk's model {w} K: {t['verdict']} (floor {t['floor_K']:.3f} K)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
