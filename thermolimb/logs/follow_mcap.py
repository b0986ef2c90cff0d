"""Follow an MCAP (or a ROS 2 bag folder holding one) while it is being recorded.

The records are read as far as they are written (:class:`~thermolimb.logs.mcap_stream.McapStream`): a chunk is
seen when the recorder has written it whole (``ros2 bag record`` writes one every few hundred kilobytes), so
the monitor lags by a chunk.

Which fields are efforts, velocities and temperatures is a mapping in the syntax of the bag readers
(``effort=/joint_states.effort,velocity=/joint_states.velocity,temperature=/thermal.temperature``; the default
is the layout :mod:`thermolimb.logs.bag_writer` writes).  Messages are read as :mod:`thermolimb.logs.bags`
reads a recorded bag (:mod:`.messages`): a field is an array of one value per actuator, named by the message's
name array (a ros2_control ``/dynamic_joint_states``: each state interface over the joints that have it; an
array naming none, in the order the efforts name them); a topic with ``{j}``
(``temperature=/{j}/temperature.temperature``) is one actuator's, named by what ``{j}`` matched.  Each
temperature message makes a sample of its actuators, with the latest effort and velocity held (zero-order
hold).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..util.errors import LogError
from .bag_writer import MAPPING as SUITE_LAYOUT
from .follow import Run
from .mapping import parse_mapping
from .mcap_stream import McapStream
from .messages import field_value, flat_message, joint_names, named_within

CHANNELS = ("effort", "velocity", "temperature")


def mcap_file(path: str | Path) -> Path:
    """The MCAP to follow: the file itself, or the one a ROS 2 bag folder holds (waiting until it appears)."""
    path = Path(path)
    if path.is_dir():
        found = sorted(path.glob("*.mcap"))
        return found[0] if found else path / "(not yet written).mcap"
    return path


class McapFollower:
    """The samples a growing MCAP gained since the last :meth:`poll`, by actuator, as :class:`~.follow.Run`
    pieces (the first of each actuator starts its run); :attr:`notes` as :class:`~.follow.CsvFollower`'s."""

    def __init__(self, path: str | Path, mapping: str | None = None):
        self.source = self.path = Path(path)
        self.mapping = _targets(parse_mapping(mapping or SUITE_LAYOUT))
        self.stream: McapStream | None = None
        self.latest: dict[str, dict[str, float]] = {"effort": {}, "velocity": {}}
        self.last_time: dict[str, float] = {}
        self.notes: list[str] = []
        self.rows = 0
        self.skipped = 0
        self.topics: set[str] = set()

    def why_nothing(self) -> str | None:
        """Why the recording gave no sample, when it says: no complete chunk, or none of the topics mapped."""
        if self.stream is None:
            return None
        if not self.topics:
            return (
                "holds no complete chunk of messages (an MCAP cut off before its first chunk, or still empty)"
            )
        wanted = ", ".join(sorted({t.topic for t in self.mapping.values()}))
        own = all(t.startswith("/thermolimb/") or t == "/diagnostics" for t in self.topics)
        return ("has the topics "
                f"{', '.join(sorted(self.topics)[:3])}{' ...' if len(self.topics) > 3 else ''}, none "
                f"of {wanted} that the mapping reads" + ("; it is a thermolimb monitor's "
                                                         "own recording, not a robot's "
                                                         "log" if own else "; give --map"))

    @property
    def started(self) -> bool:
        return bool(self.last_time)

    def poll(self, final: bool = False) -> dict[str, list[Run]]:
        if self.stream is None:
            path = mcap_file(self.source)
            if not path.exists():
                return {}
            self.stream = McapStream(path)
        pieces: dict[str, dict[str, list]] = {}
        new = set()
        for topic, msgtype, ns, raw in self.stream.read():
            self.topics.add(topic)
            self._message(topic, msgtype, raw, ns * 1e-9, pieces, new)
        out = {}
        for name, piece in pieces.items():
            self.rows += len(piece["time"])
            out[name] = [Run({k: np.array(v, float) for k, v in piece.items()}, name in new)]
        return out

    def _message(self, topic: str, msgtype: str, data: bytes, time_s: float, pieces: dict, new: set) -> None:
        wanted = [(key, t) for key, t in self.mapping.items() if t.matches(topic)]
        if not wanted:
            return
        msg = flat_message(self.stream.deserialize(data, msgtype))
        for key, target in wanted:
            values = target.values(msg, topic, self.source)
            # an array naming no joints: in the order the efforts name them, else numbered from 0
            if not values:
                order = list(self.latest["effort"]) if key not in self.latest else []
                values = target.in_order(msg, topic, self.source, order, self.notes)
            elif (
                key not in self.latest
                and self.latest["effort"]
                and not values.keys() & self.latest["effort"].keys()
            ):
                within = named_within(values, self.latest["effort"])  # a status per joint, named around it
                values = {within[n]: v for n, v in values.items() if n in within}
            if key in self.latest:
                self.latest[key].update(values)
                continue
            for name, temperature in values.items():
                if name not in self.latest["effort"] or (
                    name in self.last_time and time_s <= self.last_time[name]
                ):
                    continue  # no effort yet, or a reading no later than the last: not a new sample
                if name not in self.last_time:
                    new.add(name)
                self.last_time[name] = time_s
                piece = pieces.setdefault(name, {"time": [], "effort": [], "temperature": []})
                piece["time"].append(time_s)
                piece["effort"].append(self.latest["effort"][name])
                piece["temperature"].append(float(temperature))
                if "velocity" in self.mapping:
                    piece.setdefault("velocity", []).append(self.latest["velocity"].get(name, 0.0))


class _Target:
    """One mapping entry: a topic (``{j}``: one per actuator) and a field of its messages."""

    def __init__(self, key: str, text: str):
        topic, _, field = text.partition(".")
        if not topic.startswith("/") or not field:
            raise LogError(f"--map {key}={text}: expected /TOPIC.FIELD (e.g. {key}=/joint_states.{key})")
        self.topic, self.field = topic, field
        self.pattern = re.compile("^" + re.escape(topic).replace(re.escape("{j}"), "(?P<j>[^/]+)") + "$")

    def matches(self, topic: str) -> bool:
        return bool(self.pattern.match(topic))

    def values(self, msg, topic: str, source) -> dict[str, float]:
        value = field_value(msg, self.field, topic, source)
        joint = self.pattern.match(topic).groupdict().get("j")
        if joint is not None:
            return {joint: float(value)}
        return {str(n): float(v) for n, v in zip(joint_names(msg, self.field), list(value))}

    def in_order(self, msg, topic: str, source, names: list[str], notes: list[str]) -> dict[str, float]:
        """An array that names no joints, read in the order ``names`` (the efforts') where it holds as many,
        said once, or without ``names`` numbered from 0, as the recorded bag's reader does."""
        value = np.atleast_1d(field_value(msg, self.field, topic, source))
        # an empty array (a gripper's publisher): no sample
        if value.size == 0 or joint_names(msg, self.field):
            return {}
        if not names:
            return {str(k): float(v) for k, v in enumerate(value)}
        if len(value) != len(names):
            raise LogError(f"{source}: {topic} names no joints and holds "
                           f"{len(value)} values a message, where the "
                           f"efforts name {len(names)} ({', '.join(names[:8])}): "
                           "which value is whose cannot be told; "
                           f"map a topic that names its joints")
        said = (f"{source}: {topic} names no joints: its {len(names)} values are read in the order the "
                "efforts name them")
        if not any(n.startswith(said) for n in notes):
            notes.append(f"{said} ({', '.join(names)}); check that it is theirs")
        return {n: float(v) for n, v in zip(names, value)}


def _targets(mapping: dict[str, str]) -> dict[str, _Target]:
    missing = [c for c in ("effort", "temperature") if c not in mapping]
    if missing:
        raise LogError(f"--map for a followed MCAP needs {', '.join(missing)}=/TOPIC.FIELD")
    return {k: _Target(k, v) for k, v in mapping.items() if k in CHANNELS}
