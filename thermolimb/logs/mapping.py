"""Naming a file's columns: ``--map canonical=column,...``, with joint patterns for multi-joint files.

A single-actuator wide file (a motor bench) maps each canonical channel to one
column.  A multi-joint wide file (one row per time, columns per joint, e.g.
``Current_J0 .. Current_J5``) maps with a pattern: ``{j}`` stands for the joint
number and ``*`` for any text, so ``effort=Current_J{j},temperature=Temperature_*{j}``
finds every joint that has both columns (``Temperature_T0`` and
``Temperature_J1`` alike).  Joints are named by ``actuator=NAME{j}`` (default
``J{j}``) and ordered by number, which makes consecutive joints neighbours.
Where no column has a number there, ``{j}`` stands for a joint's name (a PlotJuggler export's
``/joint_states/{j}/effort``: ``FR_hip``, ``FR_thigh``): joints are named so and kept in the file's order.
Columns without ``{j}`` (time, ambient) are shared by every joint.

A channel on a time base of its own names its time column after ``@``:
``temperature=Temp [C]@Temperature Time [s],effort=Effort [mA]@States Time [s]``;
channels are then aligned on the temperature's samples (:mod:`thermolimb.logs.align`).
"""

from __future__ import annotations

import os
import re
from typing import Mapping

from ..util.errors import LogError
from .dialect import shown_names
from .units import header_unit, split_unit

REQUIRED = ("time", "actuator", "effort", "temperature")
OPTIONAL = ("velocity", "current", "power", "ambient", "housing")
UNITS = {"time": "s", "actuator": "name", "effort": "N m or N", "temperature": "degC",
         "velocity": "rad/s or m/s", "current": "A", "power": "W", "ambient": "degC", "housing": "degC"}
JOINT = "{j}"
EXTRA = "extra."  # a channel the model does not read, kept for the diagnosis to try: --map extra.NAME=COLUMN
TIME_OF = "@"  # column@time_column: a channel sampled on a time base of its own
DEFAULT_JOINT_NAME = "J{j}"
STATE_WORDS = ("state", "feedback", "measured")  # a topic of measurements, not of commands
# a column naming each row's actuator
ACTUATOR_WORDS = ("actuator", "joint", "motor", "axis", "servo", "drive")
SUMMARY_VALUES = 20  # a column with fewer values than this, beside one with ten times as many, is no channel


def parse_mapping(text: str | None) -> dict[str, str]:
    """Parse ``"effort=torque,temperature=stator_winding"`` into ``{"effort": "torque", ...}``."""
    if not text:
        return {}
    mapping: dict[str, str] = {}
    for item in text.split(","):
        if not item.strip():
            continue
        if "=" not in item:
            raise LogError(f"--map item {item!r} is not of the form canonical=column, e.g. effort=torque")
        key, value = (s.strip() for s in item.split("=", 1))
        if key not in REQUIRED + OPTIONAL and not (key.startswith(EXTRA) and len(key) > len(EXTRA)):
            raise LogError(f"--map names {key!r}, which is not a log column; "
                           f"map any of: {', '.join(REQUIRED + OPTIONAL)}, "
                           f"or an extra channel as {EXTRA}NAME")
        if key in mapping:
            raise LogError(f"--map names {key!r} twice ({mapping[key]!r} "
                           f"and {value!r}); give each channel one column")
        if not value:
            raise LogError(f"--map {key}= names no column; expected {key}=COLUMN")
        if value.count(JOINT) > 1:
            raise LogError(f"--map {key}={value} uses {JOINT} "
                           f"{value.count(JOINT)} times; a pattern names the joint "
                           f"number once (e.g. {key}=Current_J{JOINT})")
        # an input may be read twice (a power logged as effort is also the power), but the measured
        # temperature and the time are columns of their own
        twice = [k for k, v in mapping.items() if v == value and k != "actuator"]
        if twice and key != "actuator" and {"temperature", "time"} & {key, twice[0]}:
            raise LogError(f"--map maps column {value!r} to both {twice[0]} "
                           f"and {key}; the measured temperature and "
                           f"the time each need a column of their own")
        mapping[key] = value
    return mapping


def on_time(value: str, time: str | None) -> str:
    """A mapped channel ``COLUMN[@TIME][:UNIT]`` read on ``time``'s samples (``COLUMN@TIME:UNIT``), or with
    ``None`` on the rows of the file (``COLUMN:UNIT``)."""
    column, unit = split_unit(value)
    column = column.partition(TIME_OF)[0]
    return (column if time is None else f"{column}{TIME_OF}{time}") + (f":{unit}" if unit else "")


def is_pattern(mapping: Mapping[str, str]) -> bool:
    return any(JOINT in v for k, v in mapping.items() if k != "actuator")


# what {j} stands for in a column: a joint's number, or its name (one path segment)
NUMBER, NAME = r"\d+", r"[^/]+"


def pattern_regex(template: str, joint: str = NUMBER) -> re.Pattern:
    """A column pattern (``{j}`` for the joint, ``*`` for any text) as an anchored regex, the joint as group
    ``j``."""
    parts = re.split(r"(\{j\}|\*)", template)
    body = "".join(f"(?P<j>{joint})" if p == JOINT else ".*?" if p == "*" else re.escape(p) for p in parts)
    return re.compile(f"^{body}$")


def expand_joints(columns, mapping: Mapping[str, str], source: str,
                  notes: list[str] | None = None) -> list[tuple[int | str, str, dict[str, str]]]:
    """``[(joint, actuator name, {canonical: column})]`` for every joint of a pattern mapping: joints numbered
    in the columns in the order of their numbers, joints named there (where a number finds no column) in the
    file's order.  A numbered joint with some of the patterns' columns and not others is refused; a named one
    is left out and said in ``notes`` (topics exported together name different joints: a gripper in the
    JointState, no temperature)."""
    columns = [str(c) for c in columns]
    templates = {k: v for k, v in mapping.items() if k != "actuator" and JOINT in v}
    def finds(template, joint):
        return any(pattern_regex(template, joint).match(c) for c in columns)

    # a pattern that finds no column by a joint's name finds none by number
    for key, template in templates.items():
        if not finds(template, NAME):
            raise LogError(f"{source}: --map {key}={template} matches no column; the file's columns are "
                           f"{shown_names(columns)}")
    # {j} stands for a name where a number finds none
    named = not all(finds(t, NUMBER) for t in templates.values())
    per_key: dict[str, dict[int | str, str]] = {}
    for key, template in templates.items():
        regex = pattern_regex(template, NAME if named else NUMBER)
        found: dict[int | str, str] = {}
        for c in columns:
            m = regex.match(c)
            if m:
                j = m.group("j") if named else int(m.group("j"))
                if j in found:
                    raise LogError(f"{source}: --map {key}={template} matches "
                                   f"both {found[j]!r} and {c!r} for joint "
                                   f"{j}; make the pattern specific to one column per joint")
                found[j] = c
        per_key[key] = found
    common = set.intersection(*(set(v) for v in per_key.values()))
    joints = [j for j in next(iter(per_key.values())) if j in common] if named else sorted(common)
    if not joints:
        raise LogError(f"{source}: no joint {'name' if named else 'number'} "
                       "has a column for every pattern of "
                       "--map " + "; ".join(f"{k}: joints {list(v)}" for k, v in per_key.items()))
    partial = {k: [j for j in v if j not in common] for k, v in per_key.items()}
    partial = {k: v for k, v in partial.items() if v}
    heated = [j for j in per_key.get("temperature", {}) if j not in common]
    if named and heated and notes is not None:
        notes.append(f"{source}: joint(s) {', '.join(heated)} not "
                     "read: the map finds their temperature but not "
                     + ", ".join(k for k in per_key if not set(heated) <= set(per_key[k])))
    if partial and not named:
        k, extra = next(iter(partial.items()))
        missing = [key for key in per_key if not set(extra) <= set(per_key[key])]
        raise LogError(f"{source}: joint(s) {extra} have a {k} column but no {', '.join(missing)} column; "
                       f"map patterns that every joint has, or name the columns one by one")
    absent = [(k, v) for k, v in mapping.items() if k != "actuator" and JOINT not in v and v not in columns]
    if absent:  # a channel every joint shares (time, ambient) is one column of the file
        k, v = absent[0]
        hint = " (a column per joint needs {j} where its number stands)" if "*" in v else ""
        raise LogError(f"{source}: --map {k}={v} names column {v!r}, "
                       f"which the file does not have{hint}; its columns "
                       f"are {shown_names(columns)}")
    name = mapping.get("actuator", JOINT if named else DEFAULT_JOINT_NAME)
    if JOINT not in name:
        raise LogError(f"{source}: with joint patterns, --map actuator= "
                       f"is a name pattern with {{j}}, e.g. actuator=J{{j}}")
    out = []
    for j in joints:
        cols = {k: (per_key[k][j] if k in per_key else v) for k, v in mapping.items() if k != "actuator"}
        out.append((j, name.replace(JOINT, str(j)), cols))
    return out


# words in a column's name that say which channel it is, most specific first (a column is matched once); then
# short names that say it only as a whole word of the name ("joint_vel_rad_s", "tau_Nm"; "level" is no
# velocity)
CHANNEL_WORDS = (
    ("time", ("timestamp", "time"), ("stamp", "seconds")),
    ("temperature", ("winding temp", "stator_winding", "temperature", "temp"), ()),
    ("effort", ("torque", "effort"), ("tau", "nm", "load")),
    ("current", ("current",), ("amps", "iq")),
    ("power", ("power",), ()),
    ("velocity", ("velocity", "speed"), ("vel", "omega", "qd", "dq", "rpm")),
    ("ambient", ("ambient",), ()),
)
# a unit a column's name ends in (``tau_Nm``, ``speed_rpm``, ``current_A``), by channel: the suggestion states
# it
NAMED_UNITS = {
    "effort": {"nm": "Nm", "n": "N", "ma": "mA", "a": "A"},
    "current": {"a": "A", "ma": "mA", "amps": "A"},
    "velocity": {
        "rpm": "rpm",
        "rad_s": "rad/s",
        "rads": "rad/s",
        "deg_s": "deg/s",
        "dps": "deg/s",
        "rev_s": "rev/s",
        "rps": "rev/s",
        "turns_s": "turn/s",
        "m_s": "m/s",
    },
    "power": {"w": "W", "mw": "mW", "kw": "kW"},
    "time": {"ms": "ms", "us": "us", "ns": "ns", "min": "min"},
}  # seconds need no saying
# columns that count a clock's ticks, by the unit they count in: Arduino's millis() and micros(), a VESC
# log's milliseconds since midnight
CLOCK_COUNTERS = {"millis": "ms", "micros": "us", "ms_today": "ms"}
# words that name a motor's temperature or current, and words that name its electronics' (a driver's FETs, a
# board)
MOTOR_WORDS = ("motor", "winding", "stator", "coil")
ELECTRONICS_WORDS = ("fet", "mosfet", "driver", "board", "pcb", "mcu", "cpu", "inverter", "esc", "controller",
                     "heatsink", "igbt")
_JOINT_COLUMN = re.compile(r"^(?P<stem>.*?)(?P<j>\d+)$")
_JOINT_INSIDE = re.compile(r"^(?P<stem>\D+)(?P<j>\d+)(?P<rest>\D+)$")  # one number, inside the name


# a channel a column that never varies (all zeros, or one value throughout) is not suggested for while another
# can
VARYING_CHANNELS = ("temperature", "effort", "current", "power", "velocity")
# words that make a temperature column the air's or a reference junction's (a thermocouple chip's own), not
# the motor's
AMBIENT_WORDS = ("ambient", "ref", "reference", "room", "air", "coldjunction", "cj")


def suggest_table_mapping(columns, values: Mapping[str, int],
                          flat=frozenset()) -> tuple[dict[str, str], list[str]]:
    """A ``--map`` for a wide table from its column names, and what could not be decided.

    Columns with no value are ignored.  Per-joint columns (a name ending in
    the joint number, ``Current_J0 .. Current_J5``) give a joint pattern:
    ``{j}`` for the number and ``*`` where the names differ
    (``Temperature_T0``, ``Temperature_J1`` -> ``Temperature_*{j}``).  Without
    a torque or effort column, the current stands for effort (said in the
    reasons).  Only a suggestion: the user checks it against the listing.

    ``flat`` names the columns whose values never vary (all zeros, one value throughout): never suggested as a
    sensor or an input over columns that vary (a driver's three all-zero per-FET temperatures beside the
    motor's). A temperature whose name says the air's or a reference junction's (``tempRefCelsius``) is the
    ambient.
    """
    most = max(values.values(), default=0)
    # a column of a few values beside ones of many is a summary (Max Temp [C]: 1 value), not a channel
    names = [str(c) for c in columns if values.get(str(c), 0) >= min(SUMMARY_VALUES, 0.1 * most) > 0
             or values.get(str(c), 0) == most > 0]
    joint_groups: dict[str, list[tuple[str, int]]] = {}
    for name in names:
        m = _JOINT_COLUMN.match(name)
        inside = _JOINT_INSIDE.match(name)
        if m and m.group("stem"):
            joint_groups.setdefault(_word(m.group("stem")), []).append((name, int(m.group("j"))))
        elif inside:  # joint1_effort, motor_2_temp: the name around the number says what the column holds
            joint_groups.setdefault(f"{inside.group('stem')}{JOINT}{inside.group('rest')}", []).append(
                (name, int(inside.group("j"))))
    mapping, reasons, used, several = {}, [], set(), {}
    # one numbered column is no pattern
    grouped = {n for g in joint_groups.values() if len(g) > 1 for n, _ in g}
    def varies(group):
        return not all(n in flat for n, _ in group)

    for channel, words, whole in CHANNEL_WORDS:
        for word, says in [(w, _says_within) for w in words] + [(w, says_whole) for w in whole]:
            groups = {key: g for key, g in joint_groups.items() if says(word, key) and len(g) > 1}
            if channel in VARYING_CHANNELS and groups:
                # groups that never vary are no sensor while a column (grouped or single) saying the word
                # varies
                alive = {key: g for key, g in groups.items() if varies(g)}
                if alive or any(says(word, n) and n not in flat and n not in grouped for n in names):
                    groups = alive
            if groups and channel != "time":
                key = (the_motor_s(list(groups)) if channel == "temperature" else None) or next(iter(groups))
                mapping[channel] = _pattern([n for n, _ in groups[key]])
                used |= {n for n, _ in groups[key]}
                if len(groups) > 1:
                    reasons.append(
                        _others_left(
                            channel,
                            mapping[channel],
                            [_pattern([n for n, _ in g]) for k, g in groups.items() if k != key],
                        )
                    )
                break
            single = [n for n in names if says(word, n) and n not in used and n not in grouped
                      and (channel == "time" or "time" not in n.lower())]  # "Temperature Time [s]" is a time
            if channel in VARYING_CHANNELS and any(n not in flat for n in single):
                single = [n for n in single if n not in flat]
            if channel == "temperature" and len(single) > 1 and not all(map(_says_ambient, single)):
                air = [n for n in single if _says_ambient(n)]
                single = [n for n in single if not _says_ambient(n)]
                if len(air) == 1 and "ambient" not in mapping:
                    mapping["ambient"] = air[0]
                    used.add(air[0])
                    reasons.append(f"ambient={air[0]}: its name says the air's or a reference junction's "
                                   f"temperature, not the motor's")
            if len(single) == 1:
                mapping[channel] = single[0]
                used.add(single[0])
                break
            motor = the_motor_s(single) if channel in ("temperature", "current") else None
            if motor is not None:
                mapping[channel] = motor
                used.add(motor)
                reasons.append(_others_left(channel, motor, [c for c in single if c != motor]))
                break
            if len(single) > 1:
                several[channel] = single
                break
    label = next((g for key, g in joint_groups.items() if says_whole("name", key) and len(g) > 1), None)
    # field.name0 .. field.name3: each joint's name (rostopic echo -p)
    if label is not None and is_pattern(mapping):
        mapping["actuator"] = _pattern([n for n, _ in label])
        reasons.append(f"{mapping['actuator']} names each joint: its value names the joint's actuator")
    named = _named_joints(several) if not is_pattern(mapping) else None
    if named is not None and "temperature" not in mapping and ("effort" in named[0] or "current" in named[0]):
        mapping.update(named[0])
        reasons.append(f"the columns name their joints ({', '.join(named[1])}) "
                       f"rather than number them: {JOINT} in "
                       f"this map stands for a joint's name" + (f"; {', '.join(named[2])}, so it is not read"
                                                                if named[2] else ""))
        several = {k: v for k, v in several.items() if k not in named[0]}
    reasons += [f"{channel}: several columns could be it ({', '.join(cols[:4])}); name one"
                for channel, cols in several.items()]
    ids = [n for n in names if n not in mapping.values() and _names_actuators(n)]
    if len(ids) == 1 and not is_pattern(mapping):  # a long log: one row per actuator and time
        mapping["actuator"] = ids[0]
    bare = [n for n in names if _bare_time(n)]
    if "time" not in mapping and len(bare) == 1:  # a column named t alone, or with a unit (t_s, t_ms, t [s])
        mapping["time"] = bare[0]
    if "effort" not in mapping and "current" in mapping:
        mapping["effort"] = mapping.pop("current")
        reasons.append("no torque or effort column: the motor current stands for effort")
    if "effort" not in mapping and "power" in mapping:
        mapping["effort"] = mapping["power"]
        reasons.append("no torque or effort column: the electrical power stands for effort")
    for channel, column in list(mapping.items()):
        unit = named_unit(channel, column)
        if unit is not None:
            mapping[channel] = f"{column}:{unit}"
            reasons.append(f"{channel}={column}: its name ends in a "
                           f"unit, so the suggestion states it ({unit}); "
                           f"change it if the name means otherwise")
    clocks = [n for n in names if n.lower() in CLOCK_COUNTERS]
    if "time" not in mapping and len(clocks) == 1:  # an Arduino's millis(), a VESC's ms_today
        unit = CLOCK_COUNTERS[clocks[0].lower()]
        mapping["time"] = f"{clocks[0]}:{unit}"
        reasons.append(f"time={clocks[0]}:{unit}: a clock's count of {unit} (an Arduino's millis(), a VESC "
                       f"log's ms_today); change it if the column counts otherwise")
    timed = _own_time_columns(mapping, several.get("time", []), values) if "time" not in mapping else None
    if timed is not None:
        reasons = [r for r in reasons if not r.startswith("time: several")]
        by_time = {t: [k for k in timed if timed[k] == t] for t in timed.values()}
        reasons.append("each channel has a time column of its own: " + "; ".join(
            f"{' and '.join(ks)} on {t} ({values[t]} values)" for t, ks in by_time.items()))
        mapping.update({k: on_time(mapping[k], t) for k, t in timed.items()})
    missing = [c for c in ("time", "effort", "temperature") if c not in mapping
               and not (c == "time" and TIME_OF in mapping.get("temperature", ""))]
    if missing:
        reasons.append(f"no column found for {', '.join(missing)}")
    return mapping, reasons


def _own_time_columns(mapping: dict[str, str], times: list[str], values: Mapping[str, int]) -> dict | None:
    """Where a file has several time columns (one per topic: ``Temperature Time [s]`` beside ``States Time
    [s]``), each mapped channel's own: the one time column holding as many values as the channel, or of
    several such, the one whose name shares a word with the channel's column (``Temp`` in ``Temperature``),
    else the one of measured states (``States Time [s]``, a ROS joint_states topic, not ``Commands Time
    [s]``).  ``None`` unless the temperature and the effort each have one."""
    def words(name):
        return [w for w in re.split(r"[^a-z0-9]+", name.lower()) if len(w) >= 3 and w != "time"]

    out = {}
    for channel, column in ((k, split_unit(v)[0]) for k, v in mapping.items()):
        same = [t for t in times if values.get(t) == values.get(column)]
        if len(same) > 1:
            named = [t for t in same
                     if any(a.startswith(b) or b.startswith(a) for a in words(t) for b in words(column))]
            same = named or [t for t in same if any(w.startswith(STATE_WORDS) for w in words(t))]
        if len(same) == 1:
            out[channel] = same[0]
    return out if {"temperature", "effort"} <= set(out) else None


def named_unit(channel: str, column: str) -> str | None:
    """The unit a column's name ends in, where its header gives none and the unit fits the channel
    (``tau_Nm`` -> ``Nm`` for effort, ``wheel_speed_rad_s`` -> ``rad/s`` for velocity), else ``None``."""
    if header_unit(column) is not None:
        return None
    words, table = re.split(r"[^a-z0-9]+", str(column).lower()), NAMED_UNITS.get(channel, {})
    return next(
        (table[key] for n in (2, 1) for key in ["_".join(words[-n:])] if len(words) > n and key in table),
        None,
    )


def _named_joints(several: dict[str, list[str]]) -> tuple[dict[str, str], list[str], list[str]] | None:
    """Where a channel's several columns differ only in a joint's name between separators
    (``/joint_states/FR_hip/effort`` beside ``/joint_states/FR_calf/effort``), and the temperature's columns
    name the same joints: each such channel's pattern with ``{j}`` for the name, the joints' names in the
    temperature's order, and which of them lack an input's column; else ``None``."""
    joints = {channel: _name_pattern(cols) for channel, cols in several.items()}
    joints = {channel: found for channel, found in joints.items() if found is not None}
    heated = joints.get("temperature", (None, []))[1]
    inputs = [c for c in joints if c != "temperature" and len(set(joints[c][1]) & set(heated)) >= 2]
    if not inputs:
        return None
    lacking = [f"{j} has no {c} column" for c in inputs for j in heated if j not in joints[c][1]]
    return {channel: joints[channel][0] for channel in ["temperature", *inputs]}, heated, lacking


def _name_pattern(columns: list[str]) -> tuple[str, list[str]] | None:
    """The pattern of columns that differ only in the text between a common head and tail, cut at separators
    (``/`` and ``.`` first, then ``_``, ``-`` and spaces): ``("/joint_states/{j}/effort", ["FR_hip",
    "FR_calf"])``, or ``None``."""
    if len(columns) < 2:
        return None
    for separators in ("/.", "/._- "):
        head, tail = os.path.commonprefix(columns), os.path.commonprefix([c[::-1] for c in columns])[::-1]
        head = head[:max((head.rfind(s) + 1 for s in separators), default=0)]
        tail = tail[min((i for i, ch in enumerate(tail) if ch in separators), default=len(tail)):]
        names = [c[len(head):len(c) - len(tail)] for c in columns]
        if (
            (head or tail)
            and all(names)
            and len(set(names)) == len(names)
            and not any("/" in n for n in names)
        ):
            return f"{head}{JOINT}{tail}", names
    return None


# a joint's number joined to the word counts (motor1_temp beside fet1_temp)
def _says(words, name: str) -> bool:
    return bool(set(words) & set(re.findall(r"[a-z]+", name.lower())))


def the_motor_s(columns: list[str]) -> str | None:
    """Of several temperature (or current) columns, the one whose name says the motor's where no other does
    (``motor_thermistor`` beside ``fet_thermistor``; moteus's ``servo1.motor_temperature`` beside its board's
    ``servo1.temperature``; a VESC's ``current_motor`` beside its battery's ``current_in``), else ``None``."""
    motor = [c for c in columns if _says(MOTOR_WORDS, c) and not _says(ELECTRONICS_WORDS, c)]
    return motor[0] if len(motor) == 1 else None


def _others_left(channel: str, chosen: str, others: list[str]) -> str:
    """Why one of several columns that could be a channel was taken, and what the others are left as."""
    if channel in ("temperature", "current") and _says(MOTOR_WORDS, chosen):
        kind = "its electronics" if all(_says(ELECTRONICS_WORDS, c) for c in others) else "no motor"
        return (f"{channel}: {chosen} names the motor, {', '.join(others)} {kind}; those are left to "
                f"diagnose --discover as extra channels")
    return f"{channel}: {chosen} taken of several that could be it ({', '.join([chosen, *others])}); check it"


def _names_actuators(name: str) -> bool:
    """Whether a column's name says it names the actuator of each row (``actuator``, ``joint``, ``motor_id``,
    ``Joint Name``, ``axis``): a word for an actuator, and no other words than ``id``, ``name``, ``nr``."""
    words = [w for w in re.split(r"[^a-z0-9]+", name.lower()) if w]
    return (
        bool(words) and words[0] in ACTUATOR_WORDS and all(w in ("id", "name", "nr", "no") for w in words[1:])
    )


def _bare_time(name: str) -> bool:
    """Whether a column's name is ``t`` alone or ``t`` and a unit of time (``t_s``, ``t_ms``, ``t [s]``)."""
    words = [w for w in re.split(r"[^a-z0-9]+", name.lower()) if w]
    units = ("s", "sec", *NAMED_UNITS["time"])
    return words[:1] == ["t"] and (len(words) == 1 or (len(words) == 2 and words[1] in units))


def _says_within(word: str, name: str) -> bool:
    return word in name.lower()


def says_whole(word: str, name: str) -> bool:
    """Whether ``word`` is one of the words of ``name`` (split at anything but letters and digits, and where a
    lower-case letter meets a capital: ``tempRefCelsius``)."""
    return word in re.split(r"[^a-z0-9]+", re.sub(r"(?<=[a-z])(?=[A-Z])", " ", str(name)).lower())


def _says_ambient(name: str) -> bool:
    return any(says_whole(w, name) for w in AMBIENT_WORDS)


def _word(stem: str) -> str:
    """The name part that says what a per-joint column holds, without the joint's label (``Temperature_T`` ->
    ``Temperature``, ``motor_temp_`` -> ``motor_temp``, ``/joint_states/effort.`` ->
    ``/joint_states/effort``)."""
    core = re.sub(r"[\s._\-\[(]+$", "", stem.strip())
    return re.sub(r"[\s._\-]+[A-Za-z]$", "", core) or stem


def _pattern(names: list[str]) -> str:
    """The joint pattern of per-joint column names: ``{j}`` for the number, ``*`` where they differ (a number
    inside the names, ``joint1_effort``, stands where it stands: ``joint{j}_effort``)."""
    inside = _JOINT_INSIDE.match(names[0])
    if inside and not _JOINT_COLUMN.match(names[0]):
        return f"{inside.group('stem')}{JOINT}{inside.group('rest')}"
    stems = [_JOINT_COLUMN.match(n).group("stem") for n in names]
    prefix = stems[0]
    for s in stems[1:]:
        while not s.startswith(prefix):
            prefix = prefix[:-1]
    return prefix + ("" if all(s == prefix for s in stems) else "*") + JOINT
