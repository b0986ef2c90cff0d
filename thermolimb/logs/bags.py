"""ROS 1 bags and ROS 2 bags (SQLite or MCAP storage) read as thermal logs, with the pure-Python ``rosbags``.

No ROS installation is needed.  Message definitions stored in the bag are
used (ROS 1 connection headers, MCAP schemas), so custom messages read as
well as ``sensor_msgs``; a ROS 2 SQLite bag without definitions falls back
to the standard ROS 2 (Humble) types.

Mapping (``--map``): each canonical channel names ``/topic.field``, e.g.::

    effort=/wx200/joint_states.effort,temperature=/wx200/temperatures/joint_group.temps

A field that is an array is indexed by joint name through the message's string array (``name``, ``names``,
``joint_names``): one actuator per joint found in every mapped array topic (``--actuator`` picks one).  A
scalar field (``sensor_msgs/Temperature.temperature``) belongs to the actuator given by ``--actuator``, except
the ambient, which every joint shares.  ros2_control's ``control_msgs/DynamicJointState`` (a hardware's state
interfaces per joint, ``/dynamic_joint_states``) reads as one array per interface
(``temperature=/dynamic_joint_states.temperature``), an array of sub-messages across its elements
(:mod:`.messages`).  Time is each message's receive time in the bag (one clock for every topic), in seconds
from the bag's start.  Channels are put on the temperature's own samples by :mod:`thermolimb.logs.align`.

Without ``--map`` a mapping is suggested from the topics (see
:func:`suggest_mapping`, ``thermolimb inspect``) and used when it is unique.
"""

from __future__ import annotations

import re
from collections import Counter
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

import numpy as np

from ..util.errors import LogError
from .align import align, series_of
from .bag1_partial import PartialBag1
from .bag1_partial import ends_early as bag1_ends_early
from .mapping import EXTRA, JOINT, says_whole, suggest_table_mapping, the_motor_s
from .mcap_stream import PartialMcap, ends_early
from .messages import (
    field_value,
    flat_message,
    joint_names,
    named_within,
    numbered,
    numeric_fields,
)


@dataclass(frozen=True)
class TopicInfo:
    """One topic of a bag: what ``thermolimb inspect`` prints."""

    topic: str
    msgtype: str
    count: int
    rate_hz: float
    numeric_fields: tuple[str, ...]  # scalar or array fields holding numbers
    joint_names: tuple[str, ...]  # names in the first message's name array, if any


@contextmanager
def _open(path: Path):
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    if not path.exists():
        raise LogError(f"{path}: no such file or folder; expected a "
                       "ROS 1 bag (.bag) or a ROS 2 bag (.mcap, .db3 "
                       f"or its folder)")
    bag = (
        path.parent
        if path.suffix.lower() in (".mcap", ".db3") and (path.parent / "metadata.yaml").exists()
        else path
    )
    reader = AnyReader([bag], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
    try:
        reader.open()
    except Exception as err:  # rosbags raises its own errors, struct and OS errors for damaged files
        if "__schemaless__" in str(err):
            raise LogError(SCHEMALESS.format(path=path)) from None
        partial = None
        if path.suffix.lower() == ".mcap" and ends_early(path):
            partial = PartialMcap(path)  # what the recording completed, read as far as it goes
        elif path.suffix.lower() == ".bag" and bag1_ends_early(path):
            partial = PartialBag1(path)
        if partial is not None:  # read whole already: nothing to close
            yield partial
            return
        raise LogError(f"{path}: cannot be read as a ROS bag "
                       f"({type(err).__name__}: {err}); expected an intact "
                       f"ROS 1 bag or ROS 2 bag (SQLite or MCAP)") from None
    try:
        yield reader
    finally:
        reader.close()


SCHEMALESS = ("{path}: its channels carry no message schema (a "
              "schemaless MCAP); messages are decoded by their "
              "definitions: record with schemas (ros2 bag record writes them)")


def _messages(reader, path: Path, connections):
    try:
        for conn, stamp_ns, raw in reader.messages(connections=connections):
            yield conn, stamp_ns, flat_message(reader.deserialize(raw, conn.msgtype))
    except LogError:
        raise
    except Exception as err:
        if "__schemaless__" in str(err):
            raise LogError(SCHEMALESS.format(path=path)) from None
        raise LogError(f"{path}: a message could not be read ({type(err).__name__}: {err}); the bag looks "
                       f"truncated or damaged") from None


def inspect_bag(path: str | Path) -> list[TopicInfo]:
    """Every topic with its type, message count, mean rate, numeric fields and joint names."""
    path = Path(path)
    with _open(path) as reader:
        return _topic_infos(reader, path)


def _topic_infos(reader, path: Path) -> list[TopicInfo]:
    """The topics of an open bag, reading only each topic's first message."""
    duration_s = max((reader.end_time - reader.start_time) / 1e9, 0.0)
    infos = []
    for conn in sorted(reader.connections, key=lambda c: c.topic):
        msg = next((m for _, _, m in _messages(reader, path, [conn])), None)
        count = conn.msgcount
        infos.append(TopicInfo(conn.topic, conn.msgtype, count,
                               (count - 1) / duration_s if duration_s > 0 and count > 1 else 0.0,
                               tuple(numeric_fields(msg)) if msg is not None else (),
                               numbered(msg) if msg is not None else ()))
    return infos


def _is_air(topic: str) -> bool:
    """A topic named for the air: ``ambient`` anywhere in it, ``air`` or ``room`` as words
    (``/repair/temperature`` is a joint's)."""
    return "ambient" in topic.lower() or any(says_whole(word, topic) for word in ("air", "room"))


def suggest_mapping(infos: list[TopicInfo]) -> tuple[dict[str, str] | None, list[str]]:
    """A mapping from the topics, and the reasons it is or is not unique.

    Effort and velocity come from the one ``JointState`` topic (or, without one, the one ``DynamicJointState``
    with an effort interface).  The temperature is the one numeric field naming a temperature in a topic with
    joint names (of several, the one naming the motor's where no other does, as in a table:
    ``motor_temperature`` beside ``fet_temperature``), or else the one ``Temperature`` topic (or ``std_msgs``
    number named for a temperature) not named for the air, one per joint making a ``{j}`` pattern; such a
    topic named ambient, air or room is the ambient, and fields named ``current`` or ``housing`` beside the
    temperature are mapped too.
    """
    reasons = []
    states = [i for i in infos if i.msgtype.endswith("/JointState")] or \
        [i for i in infos if i.msgtype.endswith("/DynamicJointState") and "effort" in i.numeric_fields]
    temps = [(i, f) for i in infos if i.joint_names for f in i.numeric_fields if "temp" in f.lower()]
    motor = the_motor_s([f"{i.topic}.{f}" for i, f in temps]) if len(temps) > 1 else None
    temps = [(i, f) for i, f in temps if motor in (None, f"{i.topic}.{f}")]
    scalars = [(i, "temperature") for i in infos if i.msgtype.endswith("/Temperature")] + \
        [(i, "data") for i in infos if "temp" in i.topic.lower() and i.msgtype.startswith("std_msgs/")
         and i.numeric_fields == ("data",)]  # a std_msgs/Float64 per joint, named for its temperature
    # an array named for temperature, no joint names: read in the joints' order
    if not temps and len(states) == 1:
        temps = [(i, "data") for i in infos if "temp" in i.topic.lower() and not _is_air(i.topic)
                 and not i.joint_names and i.msgtype.endswith("MultiArray") and "data" in i.numeric_fields]
    if not temps:
        temps = [(i, f) for i, f in scalars if not _is_air(i.topic)]
    # one Temperature topic per joint, named after it (/knee/temperature)
    if len(states) == 1 and len(temps) > 1:
        pattern = _joint_topic_pattern([i.topic for i, _ in temps], states[0].joint_names)
        if pattern is not None:
            temps = [(TopicInfo(pattern, temps[0][0].msgtype, 0, 0.0, (), ()), temps[0][1])]
    beside = _beside(*temps[0]) if not states and len(temps) == 1 else {}
    if len(states) != 1 and "effort" not in beside:
        reasons.append(f"{len(states)} sensor_msgs/JointState topics "
                       f"({', '.join(i.topic for i in states) or 'none'})")
    if len(temps) != 1:
        reasons.append(f"{len(temps)} temperature fields ("
                       f"{', '.join(f'{i.topic}.{f}' for i, f in temps) or 'none'})")
    if reasons:
        return None, reasons
    (temp, field) = temps[0]
    mapping = {"effort": f"{states[0].topic}.effort"} if states else {}
    mapping["temperature"] = f"{temp.topic}.{field}"
    if states and "velocity" in states[0].numeric_fields:
        mapping["velocity"] = f"{states[0].topic}.velocity"
    mapping.update(beside)
    for channel in ("current", "housing"):
        if channel in temp.numeric_fields:
            mapping[channel] = f"{temp.topic}.{channel}"
    air = [(i, f) for i, f in scalars if _is_air(i.topic)]
    if len(air) == 1:
        mapping["ambient"] = f"{air[0][0].topic}.{air[0][1]}"
    return mapping, reasons


def _beside(info: TopicInfo, field: str) -> dict[str, str]:
    """Effort and velocity among the fields beside the temperature's (in its sub-message, or its message),
    named as a table's columns are read (``tau_est``, ``dq``): where no JointState gives them (a Unitree
    ``LowState``'s ``motor_state``, a driver's own per-motor message)."""
    prefix = field.rpartition(".")[0]
    leaves = [
        f.rpartition(".")[2] for f in info.numeric_fields if f.rpartition(".")[0] == prefix and f != field
    ]
    leaves = [f for f in leaves if not says_whole("raw", f)] or leaves  # dq beside its unfiltered dq_raw
    found, _ = suggest_table_mapping(leaves, dict.fromkeys(leaves, 1))
    return {k: f"{info.topic}.{prefix + '.' if prefix else ''}{found[k].partition(':')[0]}"
            for k in ("effort", "velocity") if k in found}


def _joint_topic_pattern(topics: list[str], joints: tuple[str, ...]) -> str | None:
    """``/robot/{j}/temperature`` (or ``/motors/{j}_motor/temperature``) when every topic is one pattern with
    a joint's name in place of ``{j}``: the name as a word of the topic, bounded by anything but a letter or a
    digit, the longest such name where several fit (``left_knee`` over ``knee``)."""
    patterns = set()
    for topic in topics:
        found = [(j, m) for j in joints if j
                 for m in [re.search(rf"(?<![A-Za-z0-9]){re.escape(j)}(?![A-Za-z0-9])", topic)] if m]
        longest = [(j, m) for j, m in found if len(j) == max(len(k) for k, _ in found)]
        if len(longest) != 1:
            return None
        m = longest[0][1]
        patterns.add(topic[:m.start()] + JOINT + topic[m.end():])
    return patterns.pop() if len(patterns) == 1 else None


def _split_target(key: str, target: str, path: Path) -> tuple[str, str]:
    topic, _, field = target.partition(".")
    if not topic.startswith("/") or not field:
        raise LogError(f"{path}: --map {key}={target} is not of the form /topic.field for a bag, e.g. "
                       f"{key}=/joint_states.{key}")
    return topic, field


def _collect(reader, path: Path, mapping: Mapping[str, str]):
    """channel -> (times s, per-message values or arrays, joint names per message or None)."""
    wanted = {key: _split_target(key, target, path) for key, target in mapping.items() if key != "actuator"}
    topics = {t for t, _ in wanted.values()}
    have = {c.topic: c.msgtype for c in reader.connections}
    for key, (topic, _) in wanted.items():
        if topic not in have:
            raise LogError(f"{path}: --map {key} names topic {topic}, "
                           "which the bag does not have; its topics are "
                           + ", ".join(f"{t} ({m})" for t, m in sorted(have.items())))
    start = reader.start_time
    data = {key: ([], [], []) for key in wanted}
    connections = [c for c in reader.connections if c.topic in topics]
    for conn, stamp_ns, msg in _messages(reader, path, connections):
        for key, (topic, field) in wanted.items():
            if conn.topic == topic:
                times, values, names = data[key]
                times.append((stamp_ns - start) / 1e9)
                values.append(field_value(msg, field, topic, path))
                names.append(joint_names(msg, field))
    for key, (topic, _) in wanted.items():
        if not data[key][0]:
            raise LogError(f"{path}: topic {topic} (--map {key}) has no messages; expected a time series")
    return wanted, data


def _joint_series(key: str, topic: str, data, joint: str | None, path: Path, drop_incomplete: bool,
                  notes: list[str]) -> tuple[np.ndarray, np.ndarray]:
    times, values, names = data
    if np.ndim(values[0]) == 0:
        return series_of(times, values, str(path), key, drop_incomplete, notes)
    if joint is None:
        raise LogError(f"{path}: {topic} holds an array per message; name the joint with --actuator")
    out = np.full(len(values), np.nan)
    # a message that does not carry the joint holds no sample of it
    carried = np.zeros(len(values), dtype=bool)
    for i, (v, n) in enumerate(zip(values, names)):
        if joint in n:
            j = n.index(joint)
            if j < len(v):
                out[i] = v[j]
                carried[i] = True
    if not carried.any():
        listed = ", ".join(names[0]) if names[0] else "no joint names (no name array)"
        raise LogError(f"{path}: joint {joint!r} is not in {topic}; its messages name {listed}")
    return series_of(np.where(carried, times, np.nan), out, str(path), f"{key} of {joint}", drop_incomplete,
                     notes)


def auto_extras(infos: list[TopicInfo], mapping: Mapping[str, str]) -> dict[str, str]:
    """Every numeric field of a topic the mapping reads that the mapping does not use, as an extra channel
    (``extra.position=/joint_states.position``; named ``TOPIC_FIELD`` where two topics share a field name).
    Topics named with ``{j}`` are not searched; extras the user named stay as named; a field named for a
    channel the mapping reads from another topic (the effort a ros2_control recording holds in /joint_states
    and again in /dynamic_joint_states) is that channel again, no extra; a diagnostics topic's many keys are
    not searched."""
    used = set(mapping.values())
    topics = {v.partition(".")[0] for v in mapping.values() if JOINT not in v}
    fields = [(i.topic, f) for i in infos if i.topic in topics and not i.msgtype.endswith("/DiagnosticArray")
              for f in i.numeric_fields
              if f"{i.topic}.{f}" not in used and f not in mapping]
    counts = Counter(f for _, f in fields)
    out = {}
    for topic, field in fields:
        name = field if counts[field] == 1 else f"{topic.strip('/').replace('/', '_')}_{field}"
        key = EXTRA + name.replace(".", "_")
        if key not in mapping:
            out[key] = f"{topic}.{field}"
    return out


def read_bag(path: str | Path, mapping: Mapping[str, str] | None = None, actuator: str | None = None,
             drop_incomplete: bool = False):
    """Canonical columns per actuator: ``(frames, notes)`` with ``frames`` a list of dicts of arrays.

    ``actuator`` restricts a joint-array mapping to one joint, or names the
    actuator of scalar topics.  A missing or non-finite reading (NaN) is
    refused, as in a table, or left out with ``drop_incomplete`` (noted).
    Every other numeric field of the mapped topics comes along as an extra
    channel (:func:`auto_extras`).
    """
    path = Path(path)
    notes = []
    with _open(path) as reader:
        if getattr(reader, "note", None):
            notes.append(reader.note)
        infos = _topic_infos(reader, path)
        if not mapping:
            mapping, reasons = suggest_mapping(infos)
            if mapping is None:
                raise LogError(f"{path}: no --map given and none can be chosen from the bag: "
                               + "; ".join(reasons) + "; see `thermolimb inspect` and "
                                                      "give --map channel=/topic.field")
            notes.append(f"{path}: mapping chosen from the bag's topics: --map "
                         + ",".join(f"{k}={v}" for k, v in mapping.items()))
        missing = [k for k in ("effort", "temperature") if k not in mapping]
        if missing:
            raise LogError(f"{path}: --map does not name {', '.join(missing)}; expected e.g. "
                           f"effort=/joint_states.effort,temperature=/temperatures.temperature")
        if all(v.partition(".")[0] in {i.topic for i in infos} for v in mapping.values() if JOINT not in v):
            more = auto_extras(infos, mapping)
            if more:
                offered = ", ".join(f"{k[len(EXTRA):]}={v}" for k, v in more.items())
                notes.append(f"{path}: the mapped topics' other numeric "
                             "fields, offered as extra channels for "
                             f"diagnose --discover (kept where they vary): {offered}")
            mapping = {**mapping, **more}
        if any(JOINT in target for target in mapping.values()):
            return _read_joint_topics(reader, path, mapping, actuator, notes, drop_incomplete)
        wanted, data = _collect(reader, path, mapping)
    _in_joint_order(wanted, data, path, notes)
    _named_within(wanted, data, path, notes)
    joints = _joints(wanted, data, actuator, path)
    frames = []
    for joint in joints:
        series = _series_of_joint(wanted, data, joint, path, notes, drop_incomplete)
        temperature = series.pop("temperature")
        aligned, more = align(temperature, series, f"{path} ({joint or path.stem})")
        aligned["actuator"] = joint or actuator or path.stem
        frames.append(aligned)
        notes += more
    return frames, notes


def _read_joint_topics(reader, path: Path, mapping: Mapping[str, str], actuator: str | None, notes: list[str],
                       drop_incomplete: bool):
    """A mapping with ``{j}`` in topic names (one topic per joint, ``/{j}/temperature.temperature``): ``{j}``
    runs over the joint names of the mapped array topics (or ``actuator``); joints without such a topic are
    left out."""
    patterned = {k: v for k, v in mapping.items() if JOINT in v}
    shared = {k: v for k, v in mapping.items() if JOINT not in v}
    topics = {c.topic for c in reader.connections}
    wanted, data = _collect(reader, path, shared)
    names = [n for key in shared for n in (data[key][2][0] or ()) if np.ndim(data[key][1][0]) > 0]
    joints = [actuator] if actuator is not None else list(dict.fromkeys(names))
    if not joints:
        raise LogError(f"{path}: --map uses {{j}} in a topic name, but "
                       "no mapped array topic names joints; name the "
                       f"joint with --actuator")
    have = [j for j in joints if all(_split_target(k, v.replace(JOINT, j), path)[0] in topics
                                     for k, v in patterned.items())]
    if not have:
        example = next(iter(patterned.values())).replace(JOINT, joints[0])
        raise LogError(f"{path}: no joint has the topics --map names "
                       f"with {{j}} (e.g. {example.partition('.')[0]} "
                       f"for {joints[0]}); the bag's topics are {', '.join(sorted(topics))}")
    if len(have) < len(joints):
        notes.append(f"{path}: joint(s) {', '.join(j for j in joints if j not in have)} have no "
                     + ", ".join(v for v in patterned.values()) + " topic; left out")
    per_joint = {f"{k}|{j}": v.replace(JOINT, j) for j in have for k, v in patterned.items()}
    more_wanted, more_data = _collect(reader, path, per_joint)
    frames = []
    for joint in have:
        series = _series_of_joint(wanted, data, joint, path, notes, drop_incomplete)
        series.update(
            {
                k: _joint_series(
                    k,
                    more_wanted[f"{k}|{joint}"][0],
                    more_data[f"{k}|{joint}"],
                    joint,
                    path,
                    drop_incomplete,
                    notes,
                )
                for k in patterned
            }
        )
        temperature = series.pop("temperature")
        aligned, more = align(temperature, series, f"{path} ({joint})")
        aligned["actuator"] = joint
        frames.append(aligned)
        notes += more
    return frames, notes


def _series_of_joint(
    wanted, data, joint: str | None, path: Path, notes: list[str], drop_incomplete: bool
) -> dict:
    """Each mapped channel's series for ``joint``; an extra channel that has none for it is left out
    (noted)."""
    series = {}
    for key in wanted:
        try:
            series[key] = _joint_series(key, wanted[key][0], data[key], joint, path, drop_incomplete, notes)
        except LogError as exc:
            if not key.startswith(EXTRA):
                raise
            notes.append(f"{path}: extra channel {key[len(EXTRA):]} not kept for {joint or path.stem}: {exc}")
    return series


def _in_joint_order(wanted, data, path: Path, notes: list[str]) -> None:
    """An array topic that names no joints read in the order of the mapped topic that names them, where every
    message holds as many values (temperatures in a ``Float64MultiArray``, a Kinova's ``actuators``), said;
    where no mapped topic names them, its elements numbered from 0 (a Unitree ``LowState``'s motor slots)."""
    named = next(((k, data[k][2][0]) for k in wanted if np.ndim(data[k][1][0]) > 0 and data[k][2][0]), None)
    for key, (times, values, names) in data.items():
        if np.ndim(values[0]) == 0 or names[0]:
            continue
        if named is None and len({len(v) for v in values}) == 1:
            data[key] = (times, values, [tuple(str(k) for k in range(len(values[0])))] * len(values))
        elif named is not None and all(len(v) == len(named[1]) for v in values):
            data[key] = (times, values, [named[1]] * len(values))
            notes.append(f"{path}: {wanted[key][0]} names no joints: "
                         f"its {len(named[1])} values are read in the "
                         f"order {wanted[named[0]][0]} names them "
                         f"({', '.join(named[1])}); check that it is theirs")
        elif named is not None and not key.startswith(EXTRA):
            raise LogError(f"{path}: {wanted[key][0]} names no joints "
                           f"and holds {len(values[0])} values a message, "
                           f"where {wanted[named[0]][0]} names {len(named[1])} "
                           f"({', '.join(named[1][:8])}): which "
                           f"value is whose cannot be told; map a topic that names its joints")


def _named_within(wanted, data, path: Path, notes: list[str]) -> None:
    """A topic whose names share none with the effort's but hold them as words (a diagnostics status "Joint
    knee motor" for the JointState's "knee"; of several joints a name holds, the longest) read as the joints';
    said."""
    arrays = [k for k in wanted if not k.startswith(EXTRA) and np.ndim(data[k][1][0]) > 0 and data[k][2][0]]
    reference = set(data["effort"][2][0]) if "effort" in arrays else set()
    for key in arrays:
        names = set().union(*data[key][2])
        if not reference or names & reference:
            continue
        rename = named_within(names, reference)
        if rename:
            times, values, per_message = data[key]
            data[key] = (times, values, [tuple(rename.get(n, n) for n in names) for names in per_message])
            notes.append(f"{path}: {wanted[key][0]} names the joints within longer names, read as theirs: "
                         + ", ".join(f"{n!r} as {j}" for n, j in sorted(rename.items(), key=lambda x: x[1])))


def _joints(wanted, data, actuator: str | None, path: Path) -> list[str | None]:
    # extra channels follow the joints, not choose them
    mapped = [key for key in wanted if not key.startswith(EXTRA)]
    arrays = {key: data[key][2][0] for key in mapped if np.ndim(data[key][1][0]) > 0}
    if actuator is not None:
        return [actuator]
    if not arrays:
        return [None]
    scalars = [k for k in mapped if k not in arrays and k != "ambient"]  # the ambient is every joint's
    if scalars:
        scalar = wanted[scalars[0]][0]
        raise LogError(f"{path}: {scalar} holds one value per message "
                       "while other topics hold one per joint; name "
                       f"the joint it belongs to with --actuator")
    common = None
    for key, names in arrays.items():
        if not names:
            raise LogError(f"{path}: {wanted[key][0]} holds an array "
                           "without a name array; name the joint with "
                           f"--actuator")
        common = [n for n in names if common is None or n in common]
    if not common:
        raise LogError(f"{path}: no joint is named in every mapped array topic ("
                       + "; ".join(f"{wanted[k][0]}: {', '.join(n)}" for k, n in arrays.items()) + ")")
    return common
