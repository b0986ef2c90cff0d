"""A careless user's battery: bad inputs on every command and both environments, each outcome classified.

    python benchmarks/bad_inputs.py            # every input's outcome, then the counts by class
    python benchmarks/bad_inputs.py --json     # one record per input, and the counts by class
    python benchmarks/bad_inputs.py --round 4  # only the classes of one round (1 to 6)
    python benchmarks/bad_inputs.py --class "model file"   # only the classes whose name holds this
    python benchmarks/bad_inputs.py --round 4 --code ../base   # the same inputs against an earlier checkout

Every input belongs to a class (what kind of mistake or fault it is: "model file", "raw lab logs",
"interrupts"...) and to the round that added the class; the table counts each class's outcomes.  The command
line's cases are laid out by the kind of input they give, one function each: :func:`log_cases` (logs as users
bring them, as other tools and labs write them, misread, cut off, not logs at all), :func:`option_cases`,
:func:`model_file_cases`, :func:`output_cases` (onto inputs, over a user's files), :func:`user_code_cases`
(broken terms, a policy) and :func:`whole_cases` (one bad part of a fleet, a followed log that never appears,
export's, audit's and plan's limits); then the environments (:func:`env_cases`), the machine's and the shell's
faults (:func:`fault_cases`), special files, interrupts, the monitor's recording and the Python API.

Every input runs in its own process (so that a hang is a timeout, not a stuck
benchmark) in a scratch folder holding a small valid log and its broken
variants.  An outcome is

``clear``
    refused with exit status 2 and one line on stderr (after any ``note:`` lines: what the command waited for or
    converted before it had to refuse), and nothing written
    (no new file, no ``.partial``), or, where the input is legal but needs a
    word (a gap in time, rows left out), exit 0 with that word on stderr;
``traceback``
    a Python traceback or another exit status;
``silent``
    exit 0 without the expected refusal or word;
``left behind``
    refused, but a file was written or a temporary left;
``lost``
    a recording said written that is missing or holds fewer messages than said, or an earlier one emptied;
``hang``
    still running after the timeout (60 s; a Ray address that does not
    answer has its own 10 s limit).

Faults from the machine and the shell (a full disk behind standard output or
an output folder, a reader that closes the pipe, SIGTERM from ``timeout``)
are ``clear`` when the command ends with their own status -- 1 with one
sentence naming what could not be written, 141 and nothing said for a closed
pipe, 143 for SIGTERM -- and leaves no file behind.  The full-disk cases
mount a small tmpfs (root only; skipped, and said, elsewhere).

The second round adds logs whose numbers give their unit away (epoch
milliseconds, kelvin, a jump between the two), columns named twice, NaN in
bags, names of any length, files reached twice, ``--workers`` beyond the
machine, misuse of the Python API, outputs onto special files (``clear`` when
the command succeeds and the target keeps its type), and interrupts: Ctrl-C
twice at random moments to the whole process group, SIGTERM and SIGKILL to a
fleet's main process (``clear`` when every repetition ends within 20 s with its
status and leaves no worker running).

The third round: outputs aimed at the command's own inputs (through links too), users' broken terms (eight
kinds of bug, a built-in's name, bounds the wrong way round, a CSV given as a terms file), flags that would do
nothing, one bad file in a fleet and one unidentifiable actuator of a bag (``clear`` when the command finishes
the rest, says how many failed and exits 1), and the plant's and robots' APIs given impossible values or poisoned
commands (``clear`` when refused in one line, or, for a NaN or 1e6 N m effort, when the drive faults or saturates
and the state stays finite).

Environments' bad actions (NaN, out of range, stepping after the end) are
``clear`` when the step raises an error of one line and the environment still
steps after it (or after ``reset`` for stepping past the end), or when
``gymnasium.make`` refuses its arguments in one line.  Finite continuous
actions outside the box are clipped by design (documented), so they are not
in the battery.

The fifth round holds what a sweep of the commands the README's tour does not reach found (model files whose
records are of the wrong kind, ``export --out`` onto its model file, a device or a folder given as a log, joint
patterns whose shared column the file lacks, a row of units under the header, an audit's policy and limits).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import shutil
import signal
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
    write_misreadings(d, good)
    write_victims_and_terms(d, good)
    write_hand_edits_and_lab_logs(d, good)
    write_other_tools_files(d, good)
    write_lab_files_and_edges(d, good)


BROKEN_TERMS = textwrap.dedent('''
    import sys
    import numpy as np
    from thermolimb.model import Parameter, Term, register_term

    def make(name, body, lower=-10.0, upper=10.0):
        register_term(type(name, (Term,), {"name": name, "description": "broken " + name, "columns": ("effort",),
                                           "parameters": (Parameter(name + "_K", "K", lower, upper, 1.0, "a gain"),),
                                           "contribution": body}))

    make("b_raises", lambda self, p, s: 1 / 0)
    make("b_nan", lambda self, p, s: (np.full(s.n, np.nan), 0.0))
    make("b_inf", lambda self, p, s: (np.full(s.n, np.inf), 0.0))
    make("b_shape", lambda self, p, s: (np.zeros(3), 0.0))
    make("b_none", lambda self, p, s: None)
    make("b_missing", lambda self, p, s: (p["b_missing_K"] * s.channel("torque_sensor"), 0.0))
    make("b_nan_gain", lambda self, p, s: (0.0, float("nan")))
    make("b_exits", lambda self, p, s: sys.exit(3))
    make("b_prints", lambda self, p, s: (print("hello") or p["b_prints_K"] * np.abs(s.effort), 0.0))
''')


def write_victims_and_terms(d: Path, good: pd.DataFrame) -> None:
    """The third round's inputs: recordings an output could land on, users' broken terms, term-file mix-ups."""
    for name in ("victim_html.csv", "victim_save.csv", "victim_table.csv", "victim_link_target.csv",
                 "victim_follow.csv", "victim_hard.csv"):
        good.to_csv(d / name, index=False)
    (d / "victim_link.csv").symlink_to("victim_link_target.csv")
    os.link(d / "victim_hard.csv", d / "victim_hard_link.csv")
    (d / "victim_terms.py").write_text("from thermolimb.model import Term\n")
    (d / "broken_terms.py").write_text(BROKEN_TERMS)
    (d / "clash_terms.py").write_text(textwrap.dedent('''
        from thermolimb.model import Term, register_term
        @register_term
        class Mine(Term):
            name = "joule"
            description = "my own joule"
    '''))
    (d / "bounds_terms.py").write_text(textwrap.dedent('''
        from thermolimb.model import Parameter, Term, register_term
        @register_term
        class Upside(Term):
            name = "upside"
            description = "bounds the wrong way round"
            parameters = (Parameter("upside_K", "K", 5.0, -5.0, 1.0, "a gain"),)
    '''))
    folder = d / "fleet_with_bad"
    folder.mkdir()
    good.to_csv(folder / "a.csv", index=False)
    good.to_csv(folder / "b.csv", index=False)
    (folder / "c.csv").write_bytes(bytes(range(256)) * 40)
    bad = good.copy()
    bad.loc[20:30, "time"] = 3.0
    bad.to_csv(folder / "d.csv", index=False)
    for names, file in ((("NA", "None"), "names_na.csv"), (("1", "01"), "names_1_01.csv"), (("nan", "null"), "names_nan.csv")):
        pd.concat([good[good.actuator == "knee"].assign(actuator=n) for n in names]).to_csv(d / file, index=False)
    good[good.actuator == "knee"].drop(columns="actuator").to_csv(d / "one_joint.csv", index=False)
    long = pd.DataFrame({"time": np.arange(3000.0), "actuator": "knee",
                         "effort": 5 + 4 * np.sign(np.sin(np.arange(3000.0) / 150))})
    rise = np.zeros(3000)
    for k in range(1, 3000):
        rise[k] = rise[k - 1] + (0.3 * long["effort"].iloc[k - 1] ** 2 - rise[k - 1]) / 200.0
    long["temperature"] = np.round(25 + rise, 2)
    long.assign(temperature=np.minimum(long["temperature"], np.percentile(long["temperature"], 80).round(2))).to_csv(
        d / "pinned.csv", index=False)
    stuck = long["temperature"].to_numpy().copy()
    stuck[1000:2200] = stuck[1000]
    long.assign(temperature=stuck).to_csv(d / "stuck.csv", index=False)
    dropped = long["temperature"].to_numpy().copy()
    dropped[[500, 1500, 1501, 2500]] = [0.0, -40.0, -40.0, 255.0]
    long.assign(temperature=dropped).to_csv(d / "dropouts.csv", index=False)
    rest = long.assign(effort=long["effort"] * (np.arange(3000) >= 400))  # at rest for its first 400 s
    rest.assign(temperature=np.where(np.arange(3000) < 400, 25.0, rest["temperature"]) * 1.8 + 32,
                ambient=25.0).to_csv(d / "fahrenheit.csv", index=False)
    _cut_recording(d / "crash.mcap")
    _cut_ros1(d / "crash.bag")
    knee = good[good.actuator == "knee"]
    grouped = knee.assign(effort=[f"{1000 * e:,.1f}".replace(",", "X").replace(".", ",").replace("X", ".")
                                  for e in knee["effort"]], temperature=knee["temperature"].map(lambda v: f"{v:.2f}".replace(".", ",")))
    grouped.to_csv(d / "thousands.csv", index=False, sep=";")
    stamps = pd.Timestamp("2026-01-01") + pd.to_timedelta(knee["time"], unit="s")
    mixed = [s.strftime("%Y-%m-%dT%H:%M:%S") if k < 150 else s.strftime("%d/%m/%Y %H:%M:%S")
             for k, s in enumerate(stamps)]
    knee.assign(time=mixed).to_csv(d / "mixed_dates.csv", index=False)
    model = d / "model.json"
    subprocess.run([sys.executable, "-m", "thermolimb.cli.main", "fit", str(d / "good.csv"), "--save", str(model),
                    "--quiet"], capture_output=True)


def _cut_recording(path: Path) -> None:
    """A recorder's MCAP (small chunks) cut off at 60 % of its bytes, as a crash or power loss leaves it."""
    from mcap.writer import CompressionType, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    joint, reading = store.types["sensor_msgs/msg/JointState"], store.types["sensor_msgs/msg/Temperature"]
    header, stamp = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    whole = path.with_suffix(".whole")
    with open(whole, "wb") as f:
        w = Writer(f, chunk_size=4096, compression=CompressionType.NONE)
        w.start("ros2", "battery")
        ids = {}
        for topic, cls in (("/joint_states", joint), ("/knee/temperature", reading)):
            schema = w.register_schema(cls.__msgtype__, "ros2msg", store.generate_msgdef(cls.__msgtype__)[0].encode())
            ids[topic] = w.register_channel(topic, "cdr", schema)
        temperature = 30.0
        for k in range(2000):
            ns = int(1.7e18) + k * 10**9
            h = header(stamp=stamp(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
            effort = 5.0 + 4.0 * np.sign(np.sin(k / 120))
            temperature += (25 + 0.3 * effort**2 - temperature) / 150
            w.add_message(ids["/joint_states"], ns, store.serialize_cdr(joint(
                header=h, name=["knee"], position=np.zeros(1), velocity=np.zeros(1), effort=np.array([effort])),
                joint.__msgtype__), ns)
            w.add_message(ids["/knee/temperature"], ns, store.serialize_cdr(reading(
                header=h, temperature=round(temperature, 2), variance=0.0), reading.__msgtype__), ns)
        w.finish()
    data = whole.read_bytes()
    path.write_bytes(data[: int(0.6 * len(data))])
    whole.unlink()


def _cut_ros1(path: Path) -> None:
    """A ROS 1 recorder's bag (small chunks) cut off at 60 % of its bytes."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    joint, reading = store.types["sensor_msgs/msg/JointState"], store.types["sensor_msgs/msg/Temperature"]
    header, stamp = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    whole = path.with_suffix(".whole.bag")
    writer = Writer(whole)
    writer.chunk_threshold = 4096
    writer.open()
    cj = writer.add_connection("/joint_states", joint.__msgtype__, typestore=store)
    ct = writer.add_connection("/knee/temperature", reading.__msgtype__, typestore=store)
    temperature = 30.0
    for k in range(2000):
        ns = int(1.7e18) + k * 10**9
        h = header(seq=k, stamp=stamp(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
        effort = 5.0 + 4.0 * np.sign(np.sin(k / 120))
        temperature += (25 + 0.3 * effort**2 - temperature) / 150
        writer.write(cj, ns, store.serialize_ros1(joint(header=h, name=["knee"], position=np.zeros(1),
                                                        velocity=np.zeros(1), effort=np.array([effort])),
                                                  joint.__msgtype__))
        writer.write(ct, ns, store.serialize_ros1(reading(header=h, temperature=round(temperature, 2), variance=0.0),
                                                  reading.__msgtype__))
    writer.close()
    data = whole.read_bytes()
    path.write_bytes(data[: int(0.6 * len(data))])
    whole.unlink()


def write_misreadings(d: Path, good: pd.DataFrame) -> None:
    """The second round's inputs: unit mistakes, repeated columns, names too long, bags with NaN, special files."""
    good.assign(time=1.7e12 + 1e3 * good["time"]).to_csv(d / "epoch_ms.csv", index=False)
    good.assign(time=1.75e15 + 1e6 * good["time"]).to_csv(d / "epoch_us.csv", index=False)
    good.assign(time=1.8e18 + 1e9 * good["time"]).to_csv(d / "epoch_ns.csv", index=False)
    good.assign(time=12e3 * good["time"]).to_csv(d / "relative_ms.csv", index=False)
    good.assign(temperature=good["temperature"] + 273.15).to_csv(d / "kelvin.csv", index=False)
    good.assign(temperature=good["temperature"] + 273.15, ambient=295.2).to_csv(d / "kelvin_ambient.csv", index=False)
    good.assign(temperature=good["temperature"] + 273.15).rename(columns={"temperature": "temperature [degC]"}).to_csv(
        d / "stated_degC.csv", index=False)
    for name, rows in (("jump_up", good.index % 300 >= 150), ("jump_down", good.index % 300 < 40)):
        good.assign(temperature=good["temperature"].where(~rows, good["temperature"] + 273.15)).to_csv(
            d / f"{name}.csv", index=False)
    rows = list(good.itertuples())
    for name, header, line in (
            ("two_temperatures", "time,actuator,effort,temperature,temperature",
             lambda r: f"{r.time},{r.actuator},{r.effort},{r.temperature},{r.temperature + 1}"),
            ("two_efforts", "time,actuator,effort,effort,temperature",
             lambda r: f"{r.time},{r.actuator},{r.effort},{2 * r.effort},{r.temperature}"),
            ("two_notes", "time,actuator,effort,temperature,note,note",
             lambda r: f"{r.time},{r.actuator},{r.effort},{r.temperature},1,2")):
        (d / f"{name}.csv").write_text(header + "\n" + "".join(line(r) + "\n" for r in rows))
    (d / "link_to_good.csv").symlink_to(d / "good.csv")
    for folder in ("looped", "tabled"):
        (d / folder).mkdir()
        shutil.copy(d / "good.csv", d / folder / "a.csv")
    (d / "looped" / "loop").symlink_to(d / "looped")  # a folder that holds itself
    (d / "tabled" / "rows.csv").write_text("source,actuator,run,samples,duration_s,validation_rmse_K\n"
                                           "tabled/a.csv,knee,a#1,300,299.0,1.08\n")
    good.assign(actuator=good["actuator"].where(good["actuator"] != "knee", "k" * 300)).to_csv(d / "long_name.csv",
                                                                                               index=False)
    good.assign(actuator=good["actuator"].where(good["actuator"] != "knee", "k" * 50_000)).to_csv(
        d / "huge_name.csv", index=False)
    _plant_bags(d)


def _plant_bags(d: Path) -> None:
    """MCAP bags of a short plant run: NaN readings in the temperature topic, all NaN, and kelvin."""
    from dataclasses import replace

    from thermolimb.logs.bag_writer import write_mcap
    from thermolimb.plant import PlantEffects, simulate_profile
    from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS

    log = simulate_profile("random", 600.0, 1.0, list(CASE_NAMES), list(CASE_SPECS), PlantEffects.from_names(""),
                           seed=0).log
    simulate_profile("random", 7200.0, 1.0, list(CASE_NAMES), list(CASE_SPECS), PlantEffects.from_names(""),
                     seed=1).log.write(d / "plant.csv")  # copied into a fleet for the interrupt cases
    frame = log.frame
    for name, change in (("nan_temperature", lambda f: f["temperature"].where(f.index % 50 != 7)),
                         ("all_nan_temperature", lambda f: f["temperature"] * np.nan),
                         ("kelvin_temperature", lambda f: f["temperature"] + 273.15)):
        write_mcap(replace(log, frame=frame.assign(temperature=change(frame))), d / f"{name}.mcap")


# ------------------------------------------------------------------ the battery
UNREADABLE = ("empty.csv", "junk.csv", "junk.parquet", "junk.mcap", "truncated.bag", "missing.csv", "empty_folder",
              "nothing*.csv")
READ_ONLY = "/proc/thermolimb"  # a read-only place even for root (permission bits do not bind root)
CLEAR, WORD = "refuse", "word"  # expected: exit 2, or exit 0 with a word on stderr (a regex)
PARTIAL = "partial"  # expected: exit 1 (some parts failed, the rest done) with a word on stderr
KIND: dict[str, tuple[int, str]] = {}  # each input's (round, class), filled as the case lists are built


def _kind(names, round_: int, cls: str) -> None:
    KIND.update({name: (round_, cls) for name in names})


def cli_cases() -> list[tuple[str, list[str], str, str | None]]:
    """(name, argv, expected, regex of the word on stdout or stderr) for the command line."""
    cases, where = [], [1, ""]

    def section(round_: int, cls: str):
        where[:] = [round_, cls]

    def add(name, argv, expected, pattern):
        cases.append((name, list(argv), expected, pattern))
        KIND[name] = tuple(where)

    def refuse(name, *argv, reason=None):
        add(name, argv, CLEAR, reason)

    def word(name, pattern, *argv):
        add(name, argv, WORD, pattern)

    def partial(name, pattern, *argv):
        add(name, argv, PARTIAL, pattern)

    for cases_of_a_class in (log_cases, option_cases, model_file_cases, output_cases, user_code_cases, whole_cases):
        cases_of_a_class(section, refuse, word, partial)
    return cases


def log_cases(section, refuse, word, partial) -> None:
    """Logs: as users bring them, as other tools and labs write them, misread, cut off, not logs at all."""
    section(1, "logs as users bring them")
    for log in ("no_temperature.csv", "misnamed.csv", "nan_effort.csv", "nan_time.csv", "time_backwards.csv",
                "text_time.csv", "text_effort.csv", "blank_actuator.csv", "constant_effort.csv",
                "hot_10000C.csv", "inf_effort.csv", "three_rows.csv", "header_only.csv", "empty.csv", "junk.csv",
                "junk.parquet", "junk.mcap", "log.txt", "truncated.bag", "missing.csv", "empty_folder",
                "nothing*.csv", "afile"):
        for command in ("fit", "diagnose"):
            refuse(f"{command} {log}", command, log, "--quiet")
        if log in UNREADABLE:
            refuse(f"inspect {log}", "inspect", log)
    word("inspect a space-separated .txt (its three columns)", r"3 column", "inspect", "log.txt")
    word("fit a log with a 1e7 s gap", r"segment|gap", "fit", "gap.csv", "--quiet")
    word("fit datetime times (parquet)", r"time stamps turned into seconds", "fit", "datetime_time.parquet", "--quiet", "--json")
    word("fit ISO timestamps (csv)", r"time stamps turned into seconds", "fit", "iso_time.csv", "--quiet", "--json")
    word("fit --drop-incomplete with NaN", r"left out|dropped|missing", "fit", "nan_effort.csv", "--drop-incomplete",
         "--quiet")
    section(2, "units the numbers give away")
    for log, unit in (("epoch_ms.csv", "milliseconds"), ("epoch_us.csv", "microseconds"),
                      ("epoch_ns.csv", "nanoseconds")):
        word(f"fit time in epoch {unit}", f"counted in {unit} since 1970: converted to s", "fit", log, "--quiet")
    word("fit time steps too long for seconds", r"if the time column counts milliseconds", "fit", "relative_ms.csv",
         "--quiet")
    word("fit temperatures in kelvin", r"taken as kelvin and converted", "fit", "kelvin.csv", "--quiet")
    word("fit temperatures and ambient in kelvin", r"ambient reads .* taken as kelvin", "fit", "kelvin_ambient.csv",
         "--quiet")
    word("fit kelvin under a degC header: taken as stated", r"T_offset_C", "fit", "stated_degC.csv", "--quiet")
    word("fit a bag in kelvin", r"taken as kelvin and converted", "fit", "kelvin_temperature.mcap", "--quiet",
         "--actuator", "knee")
    section(2, "columns named twice, NaN in bags")
    for log in ("jump_up.csv", "jump_down.csv", "two_temperatures.csv", "two_efforts.csv", "nan_temperature.mcap",
                "all_nan_temperature.mcap"):
        refuse(f"fit {log}", "fit", log, "--quiet")
    word("fit a bag with NaN readings, --drop-incomplete", r"left out \(--drop-incomplete\)", "fit",
         "nan_temperature.mcap", "--quiet", "--drop-incomplete", "--actuator", "knee")
    word("fit a repeated column the log does not use", r"names column 'note' 2 times", "fit", "two_notes.csv",
         "--quiet")
    section(2, "names of any length")
    word("fit --plot, an actuator name of 300 characters", r"wrote .*fit_k+-[0-9a-f]{10}\.png", "fit",
         "long_name.csv", "--quiet", "--plot", "plots")
    word("diagnose --plot, an actuator name of 50,000 characters", r"wrote .*residuals_k+-[0-9a-f]{10}\.png",
         "diagnose", "huge_name.csv", "--quiet", "--plot", "plots")
    refuse("fit --actuator nope on a name of 50,000 characters", "fit", "huge_name.csv", "--quiet", "--actuator",
           "nope")
    refuse("simulate --actuators knee:X8-9,knee:X8-16", "simulate", "--duration", "60", "--quiet", "--out", "sim.csv",
           "--actuators", "knee:X8-9,knee:X8-16")
    section(3, "logs cut off, misformatted or misread")
    word("a ROS 1 bag cut off by a crash: read to its last complete chunk, said", r"read up to its last complete chunk",
         "fit", "crash.bag", "--quiet", "--map", "effort=/joint_states.effort,temperature=/{j}/temperature.temperature")
    refuse("numbers with thousands separators (1.000,0)", "fit", "thousands.csv", "--quiet",
           reason="thousands separators")
    refuse("time stamps that change format halfway", "fit", "mixed_dates.csv", "--quiet",
           reason="changes format at row 150")
    word("an MCAP cut off by a crash: read to its last complete chunk, said", r"read up to its last complete chunk",
         "fit", "crash.mcap", "--quiet", "--map", "effort=/joint_states.effort,temperature=/{j}/temperature.temperature")
    word("a thermistor pinned at its ceiling: said with its span, left out", r"pinned at its highest reading", "fit",
         "pinned.csv", "--quiet")
    word("a sensor that drops out for a sample or two: said, left out", r"dropout", "fit", "dropouts.csv", "--quiet")
    word("a sensor stuck at one value: said with its span, left out", r"stuck at .* left out", "fit", "stuck.csv",
         "--quiet")
    word("a temperature column in degF beside an ambient in degC", r"looks like degF", "fit", "fahrenheit.csv",
         "--quiet")
    for file, first, second in (("names_na.csv", "NA", "None"), ("names_1_01.csv", "1", "01"),
                                ("names_nan.csv", "nan", "null")):
        word(f"fit actuators named {first} and {second}: two actuators, by their names",
             rf"(?m)^{first}: model.*\n(.*\n)*{second}: model", "fit", file, "--quiet")
    refuse("--map with a unit it does not know (effort:furlong)", "fit", "one_joint.csv", "--quiet", "--actuator", "a",
           "--map", "time=time,effort=effort:furlong,temperature=temperature", reason="not a unit")
    refuse("--map one column as both effort and temperature", "fit", "one_joint.csv", "--quiet", "--actuator", "a",
           "--map", "time=time,effort=effort,temperature=effort", reason="to both")
    refuse("--map a pattern with {j} twice", "fit", "good.csv", "--quiet", "--map", "effort=e{j}{j},temperature=temperature", reason="uses \\{j\\} 2 times")
    section(4, "raw lab logs")
    for file, header in (("ordinal_F.csv", "ºF (an ordinal sign)"), ("degree_F.csv", "°F"), ("deg_F.csv", "(degF)"),
                         ("bracket_F.csv", "[F]")):
        word(f"a header in {header}", r"Fahrenheit", "fit", file, "--actuator", "knee")
    word("a slow joint read in whole degrees at 2 Hz: fitted, nothing cut as stuck", r"^(?![\s\S]*left out)[\s\S]*RC_s",
         "fit", "slow_whole_degrees.csv")
    word("--validate-on a log where a joint nobody asked about reads garbage", r"validation", "fit", "good.csv",
         "--actuator", "knee", "--validate-on", "garbage_neighbour.csv")
    section(5, "what is not a log")
    refuse("fit /dev/null", "fit", "/dev/null", reason="not a regular file")
    refuse("fit a folder that is not a bag", "fit", "empty_folder", reason="not a ROS 2 bag")
    refuse("fit a header-only log for one actuator", "fit", "header_only.csv", "--actuator", "knee",
           reason="no rows with measurements")
    refuse("report a summary that is a list", "report", "list_summary", reason="not a demo's summary")
    section(5, "joint patterns")
    refuse("a joint pattern with a shared column written with *", "fit", "wide_joints.csv", "--map",
           "time=t,effort=cur{j},temperature=temp*", reason=r"temp\*.*needs \{j\}")
    refuse("a joint pattern with a time column the file lacks", "fit", "wide_joints.csv", "--map",
           "time=stamp,effort=cur{j},temperature=temp{j}", reason="names column 'stamp'")
    section(5, "logs as other tools write them")
    word("a row of units under the header", r"(?=[\s\S]*Fahrenheit)[\s\S]*K/mA\^2", "fit", "units_row.csv",
         "--actuator", "knee")
    word("data lines that end with a separator the header lacks", r"knee: model", "fit", "trailing_sep.csv")
    word("seconds written as text: read as given, not called time stamps", r"^(?![\s\S]*time stamps)[\s\S]*RC_s",
         "fit", "text_seconds.parquet", "--actuator", "knee")
    section(6, "lab files as written")
    refuse("a CSV without a header row", "fit", "headerless.csv", reason="--columns")
    refuse("a cell of junk in a temperature column", "fit", "junk_cell.csv", reason="--drop-incomplete")
    word("a cell of junk dropped and counted", r"abc", "fit", "junk_cell.csv", "--drop-incomplete", "--actuator",
         "knee")
    refuse("a blank actuator name", "fit", "blank_actuator.csv", reason="--drop-incomplete")


def option_cases(section, refuse, word, partial) -> None:
    """Options: values out of range, flags that would do nothing, files reached twice, workers beyond the machine."""
    section(1, "options of the log commands")
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
    section(1, "options of simulate")
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
    section(1, "options of compare-strategies")
    for argv in (["--env", "thermolimb/Nope-v0"], ["--episodes", "0"], ["--episodes", "-3"], ["--episodes", "nan"],
                 ["--seed", "-1"], ["--strategies", "teleport"], ["--strategies", ""], ["--max-time", "nan"],
                 ["--max-time", "0"], ["--max-time", "-5"], ["--max-time", "inf"], ["--workers", "0"],
                 ["--plot", "afile"], ["--backend", "ray", "--address", "127.0.0.1:1"]):
        base = ["compare-strategies", "--env", HEX, "--episodes", "1", "--strategies", "vertical_only", "--quiet",
                "--plot", "strategies"]
        refuse("compare-strategies " + " ".join(argv), *base, *argv)
    section(2, "files reached twice, workers beyond the machine")
    word("fit --fleet the same file twice", r"each log read once", "fit", "good.csv", "good.csv", "--fleet",
         "--quiet")
    word("fit --fleet through a link to the file", r"each log read once", "fit", "good.csv", "link_to_good.csv",
         "--fleet", "--quiet")
    word("fit --fleet over a glob through a link loop", r"each log read once", "fit", "looped/**/*.csv", "--fleet",
         "--quiet")
    word("fit --fleet over a folder holding its own earlier --table", r"a fleet table .* skipped", "fit", "tabled",
         "--fleet", "--quiet")
    for workers in ("64", "1024"):
        word(f"fit --fleet --workers {workers}", r"--workers \d+ lowered to", "fit", "good.csv", "--fleet", "--quiet",
             "--workers", workers)
    section(3, "flags that would do nothing")
    refuse("--table without --fleet", "fit", "good.csv", "--quiet", "--table", "rows.csv", reason="works with --fleet")
    refuse("--workers without --fleet", "fit", "good.csv", "--quiet", "--workers", "2", reason="works with --fleet")
    refuse("--cv with --split", "fit", "good.csv", "--quiet", "--cv", "3", "--split", "0.6", reason="--split and --cv")
    refuse("--actuator given twice", "fit", "good.csv", "--quiet", "--actuator", "knee", "--actuator", "hip", reason="given twice")


def model_file_cases(section, refuse, word, partial) -> None:
    """Model files: edited by hand, at their edges, in another unit, asked outside their experience."""
    section(4, "model file")
    for name, reason in (("m_tiny_rc.json", "RC_s"), ("m_minutes.json", "fortnights"),
                         ("m_negative_gain.json", "betaR"), ("m_negative_variance.json", "covariance"),
                         ("m_extra_param.json", "warp_K"), ("m_source.json", "term_sources|code|source"),
                         ("m_twice.json", "twice|more than once|duplicate"), ("m_low_limit.json", "limit")):
        refuse(f"predict {name}", "predict", name, "--hold", "5,0", "--duration", "60", "--start-C",
               "30", "--threshold", "90", reason=reason)
    section(5, "model file fields of the wrong kind")
    for name, reason in (("m_validation_null.json", '"validation" must map'),
                         ("m_units_list.json", '"channel_units" must map')):
        refuse(f"predict {name}", "predict", name, "--hold", "5,0", "--duration", "60", "--start-C", "30",
               "--threshold", "90", reason=reason)
    section(6, "model-file edges")
    refuse("a limit of 1e9 degC", "predict", "m_limit_huge.json", "--hold", "5,0", "--duration", "60",
           "--start-C", "30", reason="limit")
    refuse("a negative validation RMSE", "predict", "m_rmse_negative.json", "--hold", "5,0", "--duration", "60",
           "--start-C", "30", "--threshold", "90", reason="rmse_K")
    refuse("JSON nested 100,000 deep", "predict", "m_deep.json", "--hold", "5,0", "--duration", "60",
           "--start-C", "30", "--threshold", "90", reason="nested")
    section(6, "units across the model file's edge")
    refuse("a model in mA over a log in N m", "predict", "m_milliamps.json", "good.csv", "--actuator", "knee",
           "--threshold", "90", reason="effort")
    section(4, "outside the model's experience")
    word("predict a hold ten times the log's effort", r"extrapolated", "predict", "model.json",
         "--hold", "100,0", "--duration", "600", "--start-C", "30", "--threshold", "90")
    word("--ambient-C for a model without ambient", r"does not read the ambient", "predict",
         "model.json", "--hold", "5,0", "--duration", "600", "--start-C", "30", "--ambient-C", "40", "--threshold",
         "90")
    for level in ("1", "0", "nan"):
        refuse(f"predict --level {level}", "predict", "model.json", "--hold", "5,0",
               "--duration", "60", "--start-C", "30", "--threshold", "90", "--level", level, reason="--level")


def output_cases(section, refuse, word, partial) -> None:
    """Outputs: onto the command's own inputs, over a user's files, into folders that cannot hold them."""
    section(1, "demos and reports")
    for argv in (["nope"], ["diagnose", "--out", "afile"], ["diagnose", "--out", READ_ONLY]):
        refuse("demo " + " ".join(argv), "demo", *argv, "--quick", "--quiet")
    for target in ("afile", "missing_folder", "empty_folder", "corrupt", "index_dir", READ_ONLY):
        refuse(f"report {target}", "report", target)
    refuse("unknown command", "frobnicate")
    section(3, "outputs onto inputs")
    refuse("fit --html onto the log it reads", "fit", "victim_html.csv", "--quiet", "--html", "victim_html.csv",
           reason="never replaces an input")
    refuse("fit --save onto the log it reads", "fit", "victim_save.csv", "--quiet", "--save", "victim_save.csv",
           reason="never replaces an input")
    refuse("fit --fleet --table onto a log it reads", "fit", "victim_table.csv", "--fleet", "--quiet", "--table",
           "victim_table.csv", reason="never replaces an input")
    refuse("fit --html onto a symbolic link to the log", "fit", "victim_link_target.csv", "--quiet", "--html",
           "victim_link.csv", reason="never replaces an input")
    refuse("fit --html onto a hard link to the log", "fit", "victim_hard.csv", "--quiet", "--html",
           "victim_hard_link.csv", reason="never replaces an input")
    refuse("diagnose --propose onto its --terms file", "diagnose", "good.csv", "--quiet", "--discover", "--terms",
           "victim_terms.py", "--propose", "victim_terms.py", reason="never replaces an input")
    refuse("monitor --mcap onto the followed log", "monitor", "model.json", "--follow", "victim_follow.csv", "--mcap",
           "victim_follow.csv", "--idle-exit", "0.5", reason="never replaces an input")
    section(5, "outputs onto inputs")
    refuse("export --out onto its own model file", "export", "m_export_onto.json", "--to", "mujoco", "--motor-const",
           "0.1", "--resistance", "1", "--out", "m_export_onto.json", reason="never replaces an input")
    section(6, "a user's own files where a command writes")
    refuse("export over a user's MJCF", "export", "model.json", "--to", "mujoco", "--motor-const", "0.1",
           "--resistance", "1", "--out", "user.xml", reason="did not write")


def user_code_cases(section, refuse, word, partial) -> None:
    """A user's code: broken terms, a policy that cannot be called, limits a robot starts above."""
    section(3, "users' broken terms")
    for term in ("b_raises", "b_nan", "b_inf", "b_shape", "b_none", "b_missing", "b_nan_gain", "b_exits"):
        refuse(f"fit a broken term ({term})", "fit", "good.csv", "--quiet", "--actuator", "knee", "--terms",
               "broken_terms.py", "--model", f"joule,{term}", reason=f"term '{term}'")
    word("diagnose sets broken terms aside and goes on", r"set aside", "diagnose", "good.csv", "--quiet",
         "--actuator", "knee", "--terms", "broken_terms.py", "--stability", "0")
    word("fit --json with a term that prints: the JSON stays JSON", r'^\[?\s*\{', "fit", "good.csv", "--quiet",
         "--json", "--actuator", "knee", "--terms", "broken_terms.py", "--model", "joule,b_prints")
    refuse("a term registered under a built-in's name", "fit", "good.csv", "--quiet", "--terms", "clash_terms.py", reason="built-in")
    refuse("a term with bounds low > high", "fit", "good.csv", "--quiet", "--terms", "bounds_terms.py", reason="lower < upper")
    refuse("--terms given a CSV", "fit", "good.csv", "--quiet", "--terms", "good.csv", reason="not a Python file")
    section(5, "audit's policy and limits")
    refuse("audit a policy that cannot be called as (env, observation)", "audit", "--env", "Ant-v5", "--duration",
           "1", "--policy", "json:loads", reason="cannot be called as")
    refuse("audit limits below where the joints start", "audit", "--env", "Ant-v5", "--duration", "1",
           "--limit-C", "20", reason="start at or above their limit")


def whole_cases(section, refuse, word, partial) -> None:
    """Whole jobs: one bad part of a fleet, a followed log that never appears, export's, audit's and plan's limits."""
    section(3, "one bad part of a whole")
    partial("a fleet over a folder with an unreadable file and one whose time goes back",
            r"2 of 4 files could not be read", "fit", "fleet_with_bad", "--fleet", "--quiet")
    partial("fit every actuator of the bag: one not identifiable, the others fitted", r"could not be analysed", "fit",
            str(BAG), "--quiet")
    section(4, "following what does not exist")
    for target in ("never_there.csv", "/dev/null", "empty_folder"):
        refuse(f"monitor --follow {target}", "monitor", "model.json", "--follow", target, "--idle-exit",
               "1", "--mcap", "out4.mcap")
    section(4, "the model carried into other simulators")
    for argv, reason in ((["--motor-const", "0"], "motor-const"), (["--motor-const", "nan"], "motor-const"),
                         (["--resistance", "-1"], "resistance"), (["--gear", "inf"], "gear")):
        refuse("export " + " ".join(argv), "export", "model.json", "--to", "mujoco", "--motor-const", "0.1",
               "--resistance", "1", *argv, reason=reason)
    for argv, reason in ((["--env", "NoSuch-v0"], "NoSuch"), (["--policy", "nowhere:x"], "nowhere"),
                         (["--env-arg", "bogus=1"], "does not take"), (["--duration", "0"], "duration"),
                         (["--models", "m_twice.json"], "twice|more than once|duplicate")):
        refuse("audit " + " ".join(argv), "audit", "--env", "Ant-v5", "--duration", "1", *argv,
               reason=reason)
    section(6, "plans that cannot be run")
    refuse("plan from a start above the limit", "plan", "model.json", "--actuator", "knee", "--identify", "RC_s", "--max-effort", "5",
           "--duration", "600", "--start-C", "95", "--limit-C", "90", "--out", "p.csv", reason="no test can keep")
    refuse("plan for a parameter the model lacks", "plan", "model.json", "--actuator", "knee", "--identify", "frame_tau_s",
           "--max-effort", "5", "--duration", "600", "--limit-C", "90", "--out", "p.csv", reason="no parameter")
    refuse("plan a question it cannot pose", "plan", "model.json", "--actuator", "knee", "--separate", "joule,current_heating",
           "--max-effort", "5", "--duration", "600", "--limit-C", "90", "--out", "p.csv", reason="cannot pose")


def write_hand_edits_and_lab_logs(d: Path, good: pd.DataFrame) -> None:
    """The fourth round's inputs: model files edited by hand, raw lab logs (degF headers, a slow joint in whole
    degrees), a log for the monitor that never appears."""
    model = json.loads((d / "model.json").read_text())
    entry = model["actuators"][0]

    def edited(name, change):
        document = json.loads(json.dumps(model))
        change(document["actuators"][0])
        (d / name).write_text(json.dumps(document))

    edited("m_tiny_rc.json", lambda e: e["params"]["RC_s"].update(value=1e-9))
    edited("m_minutes.json", lambda e: e["params"]["RC_s"].update(unit="fortnights"))
    edited("m_negative_gain.json", lambda e: e["params"]["betaR_K_per_effort2"].update(
        value=-abs(e["params"]["betaR_K_per_effort2"]["value"])))
    edited("m_negative_variance.json", lambda e: e["covariance"]["matrix"][0].__setitem__(0, -1.0))
    edited("m_extra_param.json", lambda e: e["params"].update(warp_K={"value": 1.0, "stderr": 0.1, "unit": "K"}))
    edited("m_source.json", lambda e: e.update(term_sources={"evil": "open('ran.txt', 'w').write('x')"}))
    (d / "m_twice.json").write_text(json.dumps({**model, "actuators": [entry, entry]}))
    edited("m_low_limit.json", lambda e: e.update(limit_C=0.0))
    knee = good[good.actuator == "knee"]
    for file, header in (("ordinal_F.csv", "temperature (ºF)"), ("degree_F.csv", "temperature (°F)"),
                         ("deg_F.csv", "temperature (degF)"), ("bracket_F.csv", "temperature [F]")):
        knee.assign(temperature=knee["temperature"] * 1.8 + 32).rename(
            columns={"temperature": header}).to_csv(d / file, index=False, encoding="utf-8")
    # a 2 Hz log of a joint heating a degree every ten minutes, read in whole degrees: slow, not stuck
    t = np.arange(0.0, 7200.0, 0.5)
    effort = 3.0 + 2.0 * (np.floor(t / 600) % 2)
    pd.DataFrame({"time": t, "actuator": "slow", "effort": effort,
                  "temperature": np.round(30 + t / 600.0)}).to_csv(d / "slow_whole_degrees.csv", index=False)
    # a second run, in which a joint nobody asks about reads garbage (the knee's readings its own: the same readings
    # as good.csv's are refused as a run held out beside itself)
    other = good.assign(temperature=good["temperature"] + 0.3)
    other.assign(temperature=other["temperature"].where(other.actuator == "knee", "err")).to_csv(
        d / "garbage_neighbour.csv", index=False)


def write_other_tools_files(d: Path, good: pd.DataFrame) -> None:
    """The fifth round's inputs (a sweep of the commands a walk through the README does not reach): model files
    whose records are of the wrong kind, a wide file with joint patterns, a row of units, a report's summary that
    is a list, a model file to export onto itself."""
    model = json.loads((d / "model.json").read_text())
    for name, change in (("m_validation_null.json", {"validation": None}),
                         ("m_units_list.json", {"channel_units": ["N m"]})):
        document = json.loads(json.dumps(model))
        document["actuators"][0].update(change)
        (d / name).write_text(json.dumps(document))
    (d / "m_export_onto.json").write_text(json.dumps(model))
    knee, hip = (good[good.actuator == a].reset_index(drop=True) for a in ("knee", "hip"))
    pd.DataFrame({"t": knee["time"], "cur1": knee["effort"], "cur2": hip["effort"], "temp1": knee["temperature"],
                  "temp2": hip["temperature"]}).to_csv(d / "wide_joints.csv", index=False)
    lines = good.to_csv(index=False).splitlines()
    (d / "units_row.csv").write_text("\n".join([lines[0], "s,-,mA,°F"] + lines[1:]) + "\n")
    (d / "trailing_sep.csv").write_text("\n".join([lines[0]] + [line + "," for line in lines[1:]]) + "\n")
    good.assign(time=good["time"].astype(str)).to_parquet(d / "text_seconds.parquet")
    (d / "list_summary" / "fit").mkdir(parents=True)
    (d / "list_summary" / "fit" / "summary.json").write_text("[1, 2]")


def write_lab_files_and_edges(d: Path, good: pd.DataFrame) -> None:
    """The sixth round's inputs: lab files as their labs write them, model files at their edges and in another
    unit, a user's own files where a command writes, plans that cannot be run."""
    model = json.loads((d / "model.json").read_text())
    for name, change in (("m_milliamps.json", {"channel_units": {"effort": "mA"}}),
                         ("m_limit_huge.json", {"limit_C": 1e9}),
                         ("m_rmse_negative.json", {"validation": {"rmse_K": -1.0}})):
        document = json.loads(json.dumps(model))
        document["actuators"][0].update(change)
        (d / name).write_text(json.dumps(document))
    (d / "m_deep.json").write_text("[" * 100_000 + "]" * 100_000)
    lines = good.to_csv(index=False).splitlines()
    (d / "headerless.csv").write_text("\n".join(lines[1:]) + "\n")
    junk = good.astype({"temperature": object})
    junk.loc[35, "temperature"] = "abc"
    junk.to_csv(d / "junk_cell.csv", index=False)
    blank = good.astype({"actuator": object})
    blank.loc[40, "actuator"] = ""
    blank.to_csv(d / "blank_actuator.csv", index=False)
    (d / "user.xml").write_text("<mujoco model='mine'><worldbody/></mujoco>\n")


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
    first = len(cases)
    for env_id, weights in ((HEX, ("fall_penalty", "overheat_weight_per_K", "distance_weight_per_m")),
                            (HUM, ("effort_weight", "cooling_weight_per_K", "warning_weight"))):
        short = env_id.split("/")[1]
        for weight, value in zip(weights, (float("nan"), float("inf"), float("-inf"))):
            cases.append((f"{short} {weight}={value}", [env_id, json.dumps({weight: value}), "null", "no"]))
    _kind([c[0] for c in cases[:first]], 1, "environments")
    _kind([c[0] for c in cases[first:]], 3, "environments")
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
    first = len(cases)
    cases.append((f"demo diagnose --out {FULL}/demo on a full disk", ["demo", "diagnose", "--quick", "--quiet", "--out",
                                                                      f"{FULL}/demo"], "full_disk", 1))
    cases.append(("diagnose --json | a reader that closes at once", ["diagnose", "good.csv", "--quiet", "--json"],
                  "closed_pipe", 141))
    cases.append(("simulate --out /dev/full", ["simulate", "--duration", "600", "--quiet", "--out", "/dev/full"],
                  "plain", 1))
    # the demo's quick run takes about 3 s on an idle machine: the signal comes while it writes
    for argv, seconds in ((["simulate", "--duration", "100000", "--dt", "0.5", "--quiet", "--out", "big.mcap"], "4"),
                          (["demo", "diagnose", "--quick", "--quiet", "--out", "demo_out"], "2")):
        cases.append((f"{' '.join(argv[:2])} ... --out {argv[-1]}, SIGTERM after {seconds} s", [*argv, f"@{seconds}"],
                      "sigterm", 143))
    _kind([c[0] for c in cases[first:]], 2, "machine and shell faults")
    for seconds in ("1", "3"):
        cases.append((f"simulate --out big.csv, SIGTERM after {seconds} s", ["simulate", "--duration", "100000",
                                                                              "--dt", "0.5", "--quiet", "--out",
                                                                              "big.csv", f"@{seconds}"], "sigterm", 143))
    _kind([c[0] for c in cases if c[0] not in KIND], 1, "machine and shell faults")
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
        else:  # full_stdout, full_disk, plain
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
    if "Traceback" in err or done.returncode not in ((0, 1, 2) if expected == PARTIAL else (0, 2)):
        outcome = "traceback"
    elif done.returncode == 2 and (expected != CLEAR or (pattern and not re.search(pattern, err))):
        outcome = "wrong reason"  # refused what is legal, or refused for another reason than the input's fault
    elif done.returncode == 2:
        said = [line for line in lines if not line.startswith("note: ")]  # notes before the refusal are words
        outcome = "clear" if len(said) == 1 and not new else "left behind"
        if new:
            record["written"] = new
    elif expected in (WORD, PARTIAL) and re.search(pattern, done.stdout + done.stderr):
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


# ------------------------------------------------------------------ special files, interrupts, the Python API
def special_cases() -> list[tuple[str, list[str], str]]:
    """(name, argv, target kind): outputs onto a device node, a FIFO, /dev/stdout and a link to a file."""
    return _kind_all(2, "special files", [
        ("fit --html onto a device node", ["fit", "good.csv", "--quiet", "--html", "device"], "device"),
        ("simulate --out onto a device node", ["simulate", "--duration", "60", "--quiet", "--out", "device"],
         "device"),
        ("fit --fleet --table onto a FIFO", ["fit", "good.csv", "--fleet", "--quiet", "--table", "fifo"], "fifo"),
        ("fit --fleet --table /dev/stdout", ["fit", "good.csv", "--fleet", "--quiet", "--table", "/dev/stdout"],
         "stdout"),
        ("simulate --out through a link to a file", ["simulate", "--duration", "60", "--quiet", "--out",
                                                     "link_out.csv"], "link"),
    ])


def _kind_all(round_: int, cls: str, cases: list[tuple]) -> list[tuple]:
    _kind([c[0] for c in cases], round_, cls)
    return cases


def run_special(d: Path, name: str, argv: list[str], kind: str) -> dict:
    """``clear`` when the command succeeds and the target keeps its type (a device stays a device, a link a
    link) and the output reaches the reader of a FIFO or standard output."""
    import stat
    import threading

    before = _listing(d)
    received = []
    if kind == "device":
        if subprocess.run(["mknod", str(d / "device"), "c", "1", "3"], capture_output=True).returncode:
            return {"input": name, "outcome": "skipped", "message": "mknod needs root"}
    elif kind == "fifo":
        os.mkfifo(d / "fifo")
        threading.Thread(target=lambda: received.append((d / "fifo").read_bytes()), daemon=True).start()
    elif kind == "link":
        (d / "link_target.csv").write_text("")
        (d / "link_out.csv").symlink_to(d / "link_target.csv")
    created = _listing(d) - before
    try:
        done = subprocess.run([sys.executable, "-m", "thermolimb.cli.main", *argv], cwd=d, capture_output=True,
                              text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return {"input": name, "outcome": "hang"}
    time.sleep(0.2)
    target = d / argv[-1]
    lines = done.stderr.strip().splitlines()
    record = {"input": name, "exit": done.returncode, "message": lines[-1] if lines else ""}
    kept = {"device": lambda: stat.S_ISCHR(os.lstat(target).st_mode),
            "fifo": lambda: stat.S_ISFIFO(os.lstat(target).st_mode) and received and received[0].startswith(b"source"),
            "stdout": lambda: done.stdout.startswith("source,actuator"),
            "link": lambda: target.is_symlink() and (d / "link_target.csv").stat().st_size > 0}[kind]
    if "Traceback" in done.stderr or done.returncode != 0:
        outcome = "traceback"
    else:
        outcome = "clear" if kept() else "silent"
    new = sorted(_listing(d) - before - created - {"link_target.csv"})
    if outcome == "clear" and [p for p in new if ".partial" in p or p.startswith(".")]:
        outcome, record["written"] = "left behind", new
    _remove(d, sorted(_listing(d) - before, reverse=True))
    return {**record, "outcome": outcome}


def interrupt_cases() -> list[tuple[str, list[str], str, int]]:
    """(name, argv, how, repetitions): Ctrl-C twice at random moments to the whole process group (what a
    terminal sends), SIGTERM to the main process alone (timeout, systemd, a container's stop)."""
    strategies = ["compare-strategies", "--env", HEX, "--episodes", "4", "--quiet", "--plot", "strategies"]
    fleet = ["diagnose", "fleet", "--fleet", "--quiet"]
    return _kind_all(2, "interrupts", [("compare-strategies, Ctrl-C twice", strategies, "double_sigint", 5),
                    ("diagnose --fleet, Ctrl-C twice", fleet, "double_sigint", 5),
                    ("diagnose --fleet, SIGTERM to the main process", fleet, "sigterm_main", 3),
                    ("diagnose --fleet, SIGKILL to the main process", fleet, "sigkill_main", 2)])


def run_interrupt(d: Path, name: str, argv: list[str], how: str, repetitions: int, seed: int = 0) -> dict:
    """``clear`` when every repetition ends within 20 s with 130 (Ctrl-C) or 143 (SIGTERM) and one line, and
    no worker of it is left (zombies waiting for a PID 1 that does not reap are dead)."""
    import random

    rng = random.Random(seed)
    folder = d / "fleet"
    if not folder.exists():
        folder.mkdir()
        for k in range(24):
            shutil.copy(d / "plant.csv", folder / f"run{k:02d}.csv")
    outcomes = []
    for _ in range(repetitions):
        proc = subprocess.Popen([sys.executable, "-m", "thermolimb.cli.main", *argv], cwd=d, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, start_new_session=True,
                                preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        time.sleep(rng.uniform(2.5, 5.0))
        if how == "double_sigint":
            os.killpg(proc.pid, signal.SIGINT)
            time.sleep(rng.uniform(0.2, 1.0))
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGINT)
        else:
            os.kill(proc.pid, signal.SIGTERM if how == "sigterm_main" else signal.SIGKILL)
        try:
            code = proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            outcomes.append("hang")
            continue
        time.sleep(1.0)
        alive = [p for p in subprocess.run(["ps", "-o", "stat=", "-g", str(proc.pid)], capture_output=True,
                                           text=True).stdout.split() if not p.startswith("Z")]
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        lines = proc.stderr.read().decode().strip().splitlines()
        expected = {"double_sigint": 130, "sigterm_main": 143, "sigkill_main": -9}[how]
        if alive:
            outcomes.append("left behind")
        elif code == 0:
            outcomes.append("clear")  # finished before the signal
        elif code != expected or len(lines) > 1:
            outcomes.append("traceback")
        else:
            outcomes.append("clear")
    worst = next((o for o in ("hang", "left behind", "traceback") if o in outcomes), "clear")
    return {"input": name, "repetitions": repetitions, "outcome": worst, "message": ", ".join(outcomes)}


# ------------------------------------------------------------------ the monitor's recording under signals
LIVE_WRITER = textwrap.dedent("""
    import sys, time
    lines = open(sys.argv[1]).read().splitlines(True)
    with open(sys.argv[2], "w") as f:
        for line in lines:
            f.write(line)
            f.flush()
            time.sleep(0.01)
""")


def recording_cases() -> list[tuple[str, str]]:
    """(name, how): a monitor following a log that grows (a row every 10 ms) into an MCAP beside an earlier
    recording of the same name, ended by signals once or twice, killed, joined by a second monitor, or given a log
    that never appears."""
    return _kind_all(4, "the monitor's recording", [
        ("monitor --mcap, SIGTERM", "TERM"), ("monitor --mcap, SIGTERM twice back to back", "TERM TERM"),
        ("monitor --mcap, SIGHUP", "HUP"), ("monitor --mcap, Ctrl-C then SIGTERM", "INT TERM"),
        ("monitor --mcap, SIGKILL, then the next monitor on the same --mcap", "KILL"),
        ("monitor --mcap, a second monitor on the same --mcap", "second"),
        ("monitor --mcap over an earlier recording, --follow a log that never appears", "never")])


def _messages(path: Path) -> int | None:
    """The messages of a complete MCAP (its summary), None when it has none or cannot be read."""
    from mcap.reader import make_reader

    try:
        with open(path, "rb") as f:
            summary = make_reader(f).get_summary()
        return None if summary is None or summary.statistics is None else summary.statistics.message_count
    except Exception:  # noqa: BLE001 -- any failure to read it is the finding
        return None


def run_recording(d: Path, name: str, how: str) -> dict:
    """``clear`` when the run ends within 30 s of its signal, with exit 0 and a complete file holding the messages
    it says it wrote (an earlier recording replaced only by a complete one, never emptied; a partial left by a kill
    recovered by the next run and said); ``lost`` when a recording said written is missing or short, or an earlier
    one is gone; ``left behind`` when a partial or a temporary stays after a complete end."""
    folder = Path(tempfile.mkdtemp(prefix="rec_", dir=d))
    shutil.copy(d / "good.csv", folder / "source.csv")
    out = folder / "out.mcap"
    out.write_bytes(b"an earlier recording")  # what a run that fails or follows nothing must leave as it was
    monitor = [sys.executable, "-m", "thermolimb.cli.main", "monitor", str(d / "model.json"), "--mcap", str(out),
               "--publish-hz", "2", "--limit-C", "80"]
    record = {"input": name}
    if how == "never":
        done = subprocess.run([*monitor, "--follow", str(folder / "nowhere.csv"), "--idle-exit", "1"],
                              capture_output=True, text=True, timeout=TIMEOUT_S)
        kept = out.read_bytes() == b"an earlier recording"
        outcome = ("traceback" if "Traceback" in done.stderr else "clear" if kept and done.returncode == 2
                   else "lost" if not kept else "silent")
        return {**record, "exit": done.returncode, "outcome": outcome, "message": done.stderr.strip()[-110:]}
    writer = subprocess.Popen([sys.executable, "-c", LIVE_WRITER, str(folder / "source.csv"),
                               str(folder / "live.csv")])
    proc = subprocess.Popen([*monitor, "--follow", str(folder / "live.csv")], stderr=subprocess.PIPE, text=True)
    try:
        # publishing for a while: a chunk on the disk (or, for a monitor that writes only at its end, 20 s)
        deadline = time.monotonic() + 20.0
        partial = folder / "out.mcap.partial"
        while time.monotonic() < deadline and not (partial.exists() and partial.stat().st_size > 4096):
            time.sleep(0.1)
        second = None
        if how == "second":
            second = subprocess.run([*monitor, "--follow", str(folder / "source.csv"), "--idle-exit", "0.5"],
                                    capture_output=True, text=True, timeout=TIMEOUT_S)
            how = "TERM"
        for k, sig in enumerate(how.split()):
            proc.send_signal(getattr(signal, f"SIG{sig}"))
            time.sleep(0.01 if k == 0 else 0)
        try:
            err = proc.communicate(timeout=30)[1]
        except subprocess.TimeoutExpired:
            proc.kill()
            return {**record, "outcome": "hang"}
    finally:
        writer.kill()
        writer.wait()
    if how == "KILL":
        after = subprocess.run([*monitor, "--follow", str(folder / "source.csv"), "--idle-exit", "0.5"],
                               capture_output=True, text=True, timeout=TIMEOUT_S)
        recovered = list(folder.glob("*.recovered*.mcap"))
        good = (after.returncode == 0 and _messages(out) and recovered and _messages(recovered[0])
                and "killed" in after.stderr)
        outcome = "clear" if good else ("traceback" if "Traceback" in after.stderr else "lost")
        return {**record, "exit": after.returncode, "outcome": outcome,
                "message": after.stderr.strip().splitlines()[0][:110] if after.stderr.strip() else ""}
    said = re.search(r"(?:wrote|replaced) \S+(?: \((\d+) messages\))?", err)  # an older monitor gave no count
    record.update(exit=proc.returncode, message=(said.group(0) if said else err.strip()[-110:]))
    leftover = [p.name for p in folder.iterdir() if p.name not in ("source.csv", "live.csv", "out.mcap")]
    kept = _messages(out)
    if "Traceback" in err or proc.returncode != 0 or (second is not None and "Traceback" in second.stderr):
        outcome = "traceback"
    elif not kept or (said is not None and said.group(1) is not None and kept != int(said.group(1))):
        outcome = "lost"  # nothing complete, or said what is not there
    elif said is None or (second is not None and second.returncode != 2):
        outcome = "silent"  # complete but not said, or a second monitor let write the same file
    elif leftover:
        outcome, record["written"] = "left behind", leftover
    else:
        outcome = "clear"
    return {**record, "outcome": outcome}


API_SNIPPET = textwrap.dedent("""
    import json, pickle, sys, copy
    case = sys.argv[1]
    def poison(case):
        import numpy as np
        from dataclasses import replace
        from thermolimb.plant import ThermalPlant, X8_9
        from thermolimb.rig import RigConfig
        what = case.split(" ", 1)[1]
        nan, inf = float("nan"), float("inf")
        makers = {"ambient_C=nan": lambda: ThermalPlant(["a"], [X8_9], ambient_C=nan),
                  "ambient_C=-273": lambda: ThermalPlant(["a"], [X8_9], ambient_C=-273.0),
                  "ambient_C=5000": lambda: ThermalPlant(["a"], [X8_9], ambient_C=5000.0),
                  "initial_C=-inf": lambda: ThermalPlant(["a"], [X8_9], initial_C=-inf),
                  "set_temperatures one of three": lambda: ThermalPlant(["a", "b", "c"], [X8_9] * 3).set_temperatures([40.0]),
                  "set_temperatures -400": lambda: ThermalPlant(["a"], [X8_9]).set_temperatures(-400.0),
                  "winding_limit_C=0": lambda: replace(X8_9, winding_limit_C=0.0),
                  "continuous above peak": lambda: replace(X8_9, continuous_effort=2 * X8_9.effort_limit),
                  "step dt=nan": lambda: ThermalPlant(["a"], [X8_9]).step(np.ones(1), None, nan),
                  "foot_friction=-1": lambda: RigConfig(foot_friction=-1.0),
                  "physics_hz=nan": lambda: RigConfig(physics_hz=nan),
                  "torque_noise_Nm=-1": lambda: RigConfig(torque_noise_Nm=-1.0),
                  "ambient_C=inf": lambda: RigConfig(ambient_C=inf)}
        if what == "payload_kg=nan":
            from hexapod_pb.sim import SimConfig
            return SimConfig(payload_kg=nan)
        if what in makers:
            return makers[what]()
        plant = ThermalPlant(["a", "b"], [X8_9, X8_9])
        if what == "step with a NaN and an inf effort: faulted, the state finite":
            for _ in range(30):
                plant.step(np.array([nan, inf]), None, 1.0)
            assert plant.faulted.all() and np.all(np.isfinite(plant.state)), "poisoned"
            return "ok"
        if what == "step 1e6 N m: saturated at the peak":
            for _ in range(600):
                plant.step(np.array([1e6, 0.0]), None, 1.0)
            assert plant.winding_C[0] < 400.0 and plant.saturations[0] == 600, plant.winding_C
            return "ok"
        if what == "complex action":
            import gymnasium as gym, hexapod_pb
            env = gym.make("thermolimb/HexapodLoadCarry-v0").unwrapped
            env.reset(seed=0)
            return env.step(np.array([0.5, 0.5, 0.5, 0.5j]))
        raise AssertionError("unknown case " + what)
    def run():
        from thermolimb.logs import read_log
        if case == "read_log(mapping='effort=effort')":
            return read_log("good.csv", mapping="effort=effort")
        if case == "read_log(mapping=42)":
            return read_log("good.csv", mapping=42)
        series = read_log("good.csv").series("knee")
        from thermolimb.identification import FreeRunLeastSquares, LeastSquares
        if case.startswith("fit "):
            n = int(case.split()[1])
            return (FreeRunLeastSquares if "output" in case else LeastSquares)().fit(series.slice(0, n))
        from thermolimb.model import ThermalModel
        if case.startswith("ThermalModel "):
            value = float(case.split()[-1])
            return ThermalModel(("joule",), {"RC_s": 40.0, "betaR_K_per_effort2": value, "T_offset_C": 25.0})
        if case == "pickle a fitted FreeRunLeastSquares, FitReport and ThermalModel":
            from thermolimb.model import DEFAULT_MODEL
            from thermolimb.workbench.validation import Scheme, validate_model
            report = validate_model([series], DEFAULT_MODEL, Scheme())
            for obj in (report, report.estimator, report.model):
                assert pickle.loads(pickle.dumps(obj)) is not None
            return "pickled"
        if case.startswith("plant ") or case.startswith("robot "):
            return poison(case)
        import gymnasium as gym, hexapod_pb, humanoid_pb
        env = gym.make(case.split()[-1])
        env.reset(seed=0)
        return copy.deepcopy(env) if "deepcopy" in case else pickle.dumps(env)
    try:
        run()
        print(json.dumps({"raised": None}))
    except Exception as exc:
        print(json.dumps({"raised": type(exc).__name__, "lines": len(str(exc).strip().splitlines()),
                          "chars": len(str(exc))}))
""")
API_CASES = (("read_log(mapping='effort=effort')", "raise"), ("read_log(mapping=42)", "raise"),
             ("fit 0 samples (output error)", "raise"), ("fit 2 samples (output error)", "raise"),
             ("fit 2 samples (least squares)", "raise"), ("ThermalModel betaR nan", "raise"),
             ("ThermalModel betaR -1e9", "raise"), ("ThermalModel betaR 1e300", "pass"),
             ("pickle a fitted FreeRunLeastSquares, FitReport and ThermalModel", "pass"),
             (f"pickle a live {HEX}", "raise"), (f"deepcopy a live {HUM}", "raise"))
_kind([f"API: {case}" for case, _ in API_CASES], 2, "the Python API")
THIRD_API = tuple((f"plant {what}", "raise") for what in (
    "ambient_C=nan", "ambient_C=-273", "ambient_C=5000", "initial_C=-inf", "set_temperatures one of three",
    "set_temperatures -400", "winding_limit_C=0", "continuous above peak", "step dt=nan")) + tuple(
    (f"robot {what}", "raise") for what in ("foot_friction=-1", "physics_hz=nan", "torque_noise_Nm=-1",
                                              "ambient_C=inf", "payload_kg=nan", "complex action")) + (
    ("plant step with a NaN and an inf effort: faulted, the state finite", "pass"),
    ("plant step 1e6 N m: saturated at the peak", "pass"))
API_CASES = API_CASES + THIRD_API
_kind([f"API: {case}" for case, _ in THIRD_API], 3, "the Python API")


def run_api(d: Path, case: str, expected: str) -> dict:
    """``clear`` when a misuse raises one line naming it (or, for what must work, works)."""
    try:
        done = subprocess.run([sys.executable, "-c", API_SNIPPET, case], cwd=d, capture_output=True, text=True,
                              timeout=TIMEOUT_S * 2)
    except subprocess.TimeoutExpired:
        return {"input": f"API: {case}", "outcome": "hang"}
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines()
        return {"input": f"API: {case}", "outcome": "traceback", "message": lines[-1] if lines else ""}
    result = json.loads(done.stdout.strip().splitlines()[-1])
    if expected == "pass":
        outcome = "clear" if result["raised"] is None else "traceback"
    elif result["raised"] is None:
        outcome = "silent"
    else:
        outcome = "clear" if result["lines"] == 1 and result["chars"] < 2000 else "traceback"
    return {"input": f"API: {case}", "outcome": outcome, "message": result["raised"] or ""}


OUTCOMES = ("clear", "wrong reason", "silent", "traceback", "lost", "left behind", "hang", "skipped")


def by_class(records: list[dict]) -> dict[str, dict]:
    """Each class's outcome counts, keyed "round N: class" (a class two rounds added to has a row for each), in
    the order of the rounds."""
    table: dict[str, dict] = {}
    for r in sorted(records, key=lambda r: KIND.get(r["input"], (1, ""))[0]):
        round_, cls = KIND.get(r["input"], (1, "other"))
        table.setdefault(f"round {round_}: {cls}", {"round": round_, "class": cls, **dict.fromkeys(OUTCOMES, 0)})[
            r["outcome"]] += 1
    return table


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", action="store_true", help="print one record per input, and the counts by class")
    parser.add_argument("--only", default="", help="run only inputs whose name contains this")
    parser.add_argument("--round", type=int, choices=(1, 2, 3, 4, 5, 6), help="run only that round's classes")
    parser.add_argument("--class", dest="cls", default="", help="run only classes whose name contains this")
    parser.add_argument("--code", metavar="DIR", help="run the inputs against the thermolimb checkout in DIR (an "
                        "earlier commit's worktree: the 'before' of a round), not the installed one")
    args = parser.parse_args()
    if args.code:
        # every command, fixture and snippet runs it: first on the path, and no working folder put before it
        os.environ.update(PYTHONPATH=str(Path(args.code).resolve()), PYTHONSAFEPATH="1")
    cli, envs, faults, special, interrupts, recordings = (cli_cases(), env_cases(), fault_cases(), special_cases(),
                                                          interrupt_cases(), recording_cases())

    def chosen(name: str) -> bool:
        round_, cls = KIND.get(name, (1, "other"))
        return args.only in name and args.cls in cls and args.round in (None, round_)

    names = [case[0] for group in (cli, envs, special, interrupts, recordings, faults) for case in group]
    if not any(map(chosen, names + [f"API: {case[0]}" for case in API_CASES])):
        parser.error(f"no input is chosen by --only {args.only!r}, --class {args.cls!r} and --round {args.round}; "
                     f"an input's name holds --only (e.g. {names[0]!r}) and a class's name --class")
    records = []
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        write_fixtures(d)
        records += [run_cli(d, *case) for case in cli if chosen(case[0])]
        records += [run_env(*case) for case in envs if chosen(case[0])]
        records += [run_api(d, *case) for case in API_CASES if chosen(f"API: {case[0]}")]
        records += [run_special(d, *case) for case in special if chosen(case[0])]
        records += [run_interrupt(d, *case) for case in interrupts if chosen(case[0])]
        records += [run_recording(d, *case) for case in recordings if chosen(case[0])]
        faults = [case for case in faults if chosen(case[0])]
        can_fill = bool(faults) and _mount_full(d)
        try:
            records += [run_fault(d, *case, can_fill) for case in faults]
        finally:
            if can_fill:
                subprocess.run(["umount", str(d / FULL)], capture_output=True)
    table = by_class(records)
    if args.json:
        print(json.dumps({"code": args.code or "installed", "counts": Counter(r["outcome"] for r in records),
                          "by_class": table, "inputs": records}, indent=1))
        return
    for r in records:
        print(f"{r['outcome']:12s} {r['input'][:70]:70s} {r.get('message', '')[:110]}")
    shown = [k for k in OUTCOMES if any(row[k] for row in table.values())]
    print(f"\n{'round':5s}  {'class':48s} {'inputs':>6s} " + " ".join(f"{k:>12s}" for k in shown))
    for row in table.values():
        print(f"{row['round']:5d}  {row['class'][:48]:48s} {sum(row[k] for k in OUTCOMES):6d} "
              + " ".join(f"{row[k]:12d}" for k in shown))
    print(f"{'':5s}  {'all':48s} {len(records):6d} "
          + " ".join(f"{sum(row[k] for row in table.values()):12d}" for k in shown))


if __name__ == "__main__":
    main()
