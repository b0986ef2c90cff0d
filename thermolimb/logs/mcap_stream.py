"""An MCAP read as far as it is written: a file still being recorded, or one a crash cut off.

An MCAP is a sequence of records, each ``opcode (1 byte), length (8 bytes), content``; a recorder appends them
as it goes (messages inside chunks, a chunk written when full) and writes the summary last.
:class:`McapStream` frames the records itself, keeps the offset of the last complete one, and decodes each new
complete record with the ``mcap`` package's :class:`~mcap.stream_reader.StreamReader` (a chunk gives its
messages); ROS 2 message definitions are read from the file's schemas and registered with ``rosbags``, which
deserialises the CDR. ``thermolimb monitor --follow`` reads a growing file with it; :class:`PartialMcap` reads
a cut-off one through the same interface the bag readers use for a whole one.
"""

from __future__ import annotations

import io
import os
import re
import struct
from dataclasses import dataclass
from pathlib import Path

from ..util.errors import LogError

MAGIC = b"\x89MCAP0\r\n"
HEADER = struct.Struct("<BQ")


def ends_early(path: Path) -> bool:
    """Whether an MCAP starts as one but lacks its closing magic (written in part)."""
    try:
        with open(path, "rb") as f:
            head = f.read(len(MAGIC))
            f.seek(max(0, path.stat().st_size - len(MAGIC)))
            return head == MAGIC and f.read() != MAGIC
    except OSError:
        return False


def register_definition(store, msgtype: str, text: str, name=lambda n: n) -> None:
    """Register ``msgtype`` and the types its definition carries after it (``===`` then ``MSG: pkg/Type``
    blocks, as recorders write them) with a ``rosbags`` type store; ``name`` turns a written type name into
    the store's (a ROS 1 ``pkg/Type`` into ``pkg/msg/Type``)."""
    from rosbags.typesys import get_types_from_msg

    if msgtype in store.types:
        return
    types = {}
    for i, block in enumerate(re.split(r"\n=+\nMSG: ", text)):
        if i == 0:
            types.update(get_types_from_msg(block, msgtype))
            continue
        written, _, body = block.partition("\n")
        if name(written.strip()) not in store.types:
            types.update(get_types_from_msg(body, name(written.strip())))
    store.register(types)


def _records(data: bytes):
    """The records of whole top-level records ``data`` (a chunk's messages among them)."""
    from mcap.exceptions import EndOfFile
    from mcap.stream_reader import StreamReader

    reader = StreamReader(io.BytesIO(data), skip_magic=True).records
    while True:
        try:
            yield next(reader)
        except (StopIteration, EndOfFile):  # the end of the records given
            return


class McapStream:
    """The messages an MCAP gained since the last :meth:`read`, as ``(topic, message type, time ns, raw
    CDR)``."""

    def __init__(self, path: str | Path):
        from rosbags.typesys import Stores, get_typestore

        self.path = Path(path)
        self.offset = 0
        self.schemas: dict[int, object] = {}
        self.channels: dict[int, tuple[str, str]] = {}  # id -> (topic, message type)
        self.store = get_typestore(Stores.ROS2_HUMBLE)

    def read(self) -> list[tuple[str, str, int, bytes]]:
        try:
            size = os.path.getsize(self.path)
        except FileNotFoundError:
            return []
        if size <= self.offset:
            return []
        with open(self.path, "rb") as f:
            f.seek(self.offset)
            data = f.read(size - self.offset)
        start = 0
        if self.offset == 0:
            if len(data) < len(MAGIC):
                return []
            if not data.startswith(MAGIC):
                raise LogError(f"{self.path}: not an MCAP file (its first bytes are not the MCAP magic)")
            start = len(MAGIC)
        end = start
        while end + HEADER.size <= len(data):
            _, length = HEADER.unpack_from(data, end)
            if end + HEADER.size + length > len(data):
                break  # the recorder has not finished this record
            end += HEADER.size + length
        self.offset += end
        return self._decode(data[start:end]) if end > start else []

    def _decode(self, data: bytes) -> list[tuple[str, str, int, bytes]]:
        from mcap.records import Channel, Message, Schema

        out = []
        for record in _records(data):
            if isinstance(record, Schema):
                self.schemas[record.id] = record
            elif isinstance(record, Channel):
                schema = self.schemas.get(record.schema_id)
                if schema is None:
                    raise LogError(f"{self.path}: its channels carry no message "
                                   "schema (a schemaless MCAP); messages "
                                   "are decoded by their definitions: record "
                                   "with schemas (ros2 bag record writes "
                                   f"them)")
                if schema.encoding == "ros2msg":
                    self._register(schema)
                self.channels[record.id] = (record.topic, schema.name)
            elif isinstance(record, Message) and record.channel_id in self.channels:
                topic, msgtype = self.channels[record.channel_id]
                out.append((topic, msgtype, record.log_time, record.data))
        return out

    def _register(self, schema) -> None:
        register_definition(self.store, schema.name, schema.data.decode())

    def deserialize(self, raw: bytes, msgtype: str):
        return self.store.deserialize_cdr(raw, msgtype)


@dataclass
class _Connection:
    topic: str
    msgtype: str
    msgcount: int


class PartialMcap:
    """A cut-off MCAP read up to its last complete record, with the reader interface of ``rosbags``' AnyReader
    that the bag readers use (connections, start and end times, messages, deserialize)."""

    def __init__(self, path: Path):
        self.stream = McapStream(path)
        self.records = self.stream.read()
        if not self.records:
            raise LogError(f"{path}: the MCAP ends before its summary, at "
                           f"byte {path.stat().st_size}, and before any "
                           f"complete chunk of messages (a recording cut off by a crash or power loss?)")
        counts: dict[str, _Connection] = {}
        for topic, msgtype, _, _ in self.records:
            conn = counts.setdefault(topic, _Connection(topic, msgtype, 0))
            conn.msgcount += 1
        self.connections = list(counts.values())
        self.start_time = min(r[2] for r in self.records)
        self.end_time = max(r[2] for r in self.records)
        self.note = (f"{path}: the MCAP ends before its summary, at byte "
                     f"{path.stat().st_size} (a recording cut off by "
                     f"a crash or power loss?): read up to its last complete chunk, "
                     f"{(self.end_time - self.start_time) / 1e9:g} s of messages")

    def messages(self, connections=None):
        topics = None if connections is None else {c.topic for c in connections}
        by_topic = {c.topic: c for c in self.connections}
        for topic, _, ns, raw in self.records:
            if topics is None or topic in topics:
                yield by_topic[topic], ns, raw

    def deserialize(self, raw: bytes, msgtype: str):
        return self.stream.deserialize(raw, msgtype)
