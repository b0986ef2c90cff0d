"""Follow an MCAP (or a ROS 2 bag folder holding one) while it is being recorded.

An MCAP is a sequence of records, each ``opcode (1 byte), length (8 bytes), content``; a recorder appends
them as it goes (messages inside chunks, a chunk written when full).  The follower frames the records itself,
keeps the offset of the last complete one, and decodes each new complete record with the ``mcap`` package's
:class:`~mcap.stream_reader.StreamReader` (a chunk gives its messages); ROS 2 messages (CDR) are deserialised
with ``rosbags``, their definitions read from the file's schemas.  A chunk is seen when the recorder has
written it whole: ``ros2 bag record`` writes one every few hundred kilobytes, so the monitor lags by a chunk.

Which fields are efforts, velocities and temperatures is a mapping in the syntax of the bag readers
(``effort=/joint_states.effort,velocity=/joint_states.velocity,temperature=/thermal.temperature``; the
default is the layout :mod:`thermolimb.logs.bag_writer` writes).  A field is an array of one value per actuator,
named by the message's ``name`` field; a topic with ``{j}`` (``temperature=/{j}/temperature.temperature``)
is one actuator's, named by what ``{j}`` matched.  Each temperature message makes a sample of its actuators,
with the latest effort and velocity held (zero-order hold).
"""

from __future__ import annotations

import io
import os
import re
import struct
from pathlib import Path

from ..logs import LogError
from ..logs.bag_writer import MAPPING as SUITE_LAYOUT
from ..logs.mapping import parse_mapping
from .follow import Piece

MAGIC = b"\x89MCAP0\r\n"
HEADER = struct.Struct("<BQ")
CHANNELS = ("effort", "velocity", "temperature")


def mcap_file(path: str | Path) -> Path:
    """The MCAP to follow: the file itself, or the one a ROS 2 bag folder holds (waiting until it appears)."""
    path = Path(path)
    if path.is_dir():
        found = sorted(path.glob("*.mcap"))
        return found[0] if found else path / "(not yet written).mcap"
    return path


class McapFollower:
    """The samples a growing MCAP gained since the last :meth:`poll`, by actuator."""

    def __init__(self, path: str | Path, mapping: str | None = None):
        self.source = Path(path)
        self.mapping = _targets(parse_mapping(mapping or SUITE_LAYOUT))
        self.offset = 0
        self.schemas: dict[int, object] = {}
        self.channels: dict[int, tuple[str, str]] = {}  # id -> (topic, message type)
        self.latest: dict[str, dict[str, float]] = {"effort": {}, "velocity": {}}
        self.last_time: dict[str, float] = {}
        from rosbags.typesys import Stores, get_typestore

        self.store = get_typestore(Stores.ROS2_HUMBLE)

    def poll(self) -> dict[str, Piece]:
        path = mcap_file(self.source)
        try:
            size = os.path.getsize(path)
        except FileNotFoundError:
            return {}
        if size <= self.offset:
            return {}
        with open(path, "rb") as f:
            f.seek(self.offset)
            data = f.read(size - self.offset)
        start = 0
        if self.offset == 0:
            if len(data) < len(MAGIC):
                return {}
            if not data.startswith(MAGIC):
                raise LogError(f"{path}: not an MCAP file (its first bytes are not the MCAP magic)")
            start = len(MAGIC)
        pieces: dict[str, Piece] = {}
        end = start
        while end + HEADER.size <= len(data):
            _, length = HEADER.unpack_from(data, end)
            if end + HEADER.size + length > len(data):
                break  # the recorder has not finished this record yet
            end += HEADER.size + length
        if end > start:
            self._decode(data[start:end], pieces)
        self.offset += end
        return pieces

    def _decode(self, records: bytes, pieces: dict[str, Piece]) -> None:
        from mcap.records import Channel, Message, Schema

        for record in _records(records):
            if isinstance(record, Schema):
                self.schemas[record.id] = record
            elif isinstance(record, Channel):
                schema = self.schemas.get(record.schema_id)
                if schema is not None and schema.encoding == "ros2msg":
                    self._register(schema)
                self.channels[record.id] = (record.topic, schema.name if schema is not None else "")
            elif isinstance(record, Message) and record.channel_id in self.channels:
                topic, msgtype = self.channels[record.channel_id]
                self._message(topic, msgtype, record.data, record.log_time * 1e-9, pieces)

    def _register(self, schema) -> None:
        from rosbags.typesys import get_types_from_msg

        if schema.name in self.store.types:
            return
        text = schema.data.decode()
        types = {}
        for i, block in enumerate(re.split(r"\n=+\nMSG: ", text)):  # a definition and the ones it uses
            if i == 0:
                types.update(get_types_from_msg(block, schema.name))
            else:
                name, _, body = block.partition("\n")
                types.update(get_types_from_msg(body, name.strip()))
        self.store.register(types)

    def _message(self, topic: str, msgtype: str, data: bytes, time_s: float, pieces: dict[str, Piece]) -> None:
        wanted = [(key, t) for key, t in self.mapping.items() if t.matches(topic)]
        if not wanted:
            return
        msg = self.store.deserialize_cdr(data, msgtype)
        for key, target in wanted:
            values = target.values(msg, topic, self.source)
            if key in self.latest:
                self.latest[key].update(values)
                continue
            for name, temperature in values.items():
                if name not in self.latest["effort"] or (name in self.last_time and time_s <= self.last_time[name]):
                    continue  # no effort yet, or a reading no later than the last: not a new sample
                self.last_time[name] = time_s
                piece = pieces.setdefault(name, Piece())
                piece.time_s.append(time_s)
                piece.effort.append(self.latest["effort"][name])
                piece.temperature_C.append(float(temperature))
                if "velocity" in self.mapping:
                    piece.channels.setdefault("velocity", []).append(self.latest["velocity"].get(name, 0.0))


def _records(data: bytes):
    """The records of whole top-level records ``data`` (a chunk's messages among them)."""
    from mcap.exceptions import EndOfFile
    from mcap.stream_reader import StreamReader

    reader = StreamReader(io.BytesIO(data), skip_magic=True).records
    while True:
        try:
            yield next(reader)
        except (StopIteration, EndOfFile):  # the end of the records given: the rest is not written yet
            return


class _Target:
    """One mapping entry: a topic (``{j}``: one per actuator) and a field of its messages."""

    def __init__(self, key: str, text: str):
        topic, _, field = text.rpartition(".")
        if not topic.startswith("/") or not field:
            raise LogError(f"--map {key}={text}: expected /TOPIC.FIELD (e.g. {key}=/joint_states.{key})")
        self.field = field
        self.pattern = re.compile("^" + re.escape(topic).replace(re.escape("{j}"), "(?P<j>[^/]+)") + "$")

    def matches(self, topic: str) -> bool:
        return bool(self.pattern.match(topic))

    def values(self, msg, topic: str, source) -> dict[str, float]:
        value = getattr(msg, self.field, None)
        if value is None:
            raise LogError(f"{source}: messages on {topic} have no field {self.field!r}")
        joint = self.pattern.match(topic).groupdict().get("j")
        if joint is not None:
            return {joint: float(value)}
        names = list(getattr(msg, "name", []) or [])
        return {str(n): float(v) for n, v in zip(names, list(value))}


def _targets(mapping: dict[str, str]) -> dict[str, _Target]:
    missing = [c for c in ("effort", "temperature") if c not in mapping]
    if missing:
        raise LogError(f"--map for a followed MCAP needs {', '.join(missing)}=/TOPIC.FIELD")
    return {k: _Target(k, v) for k, v in mapping.items() if k in CHANNELS}
