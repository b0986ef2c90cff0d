"""A ROS 1 bag cut off by a crash or power loss, read up to its last complete chunk.

A ROS 1 bag (format 2.0) is ``#ROSBAG V2.0`` then records, each ``header length (4 bytes), header fields
(length, name=value), data length (4 bytes), data``; messages and the connections they use sit inside chunks
(op 5, uncompressed or bz2), and the index that ``rosbags`` needs is written last.  :class:`PartialBag1` walks
the records while they are whole, collects each complete chunk's connections (op 7) and messages (op 2), and
offers them through the reader interface of ``rosbags``' AnyReader the bag readers use; messages are
deserialised with ``rosbags`` from the definitions the connections carry.
"""

from __future__ import annotations

import bz2
import struct
from dataclasses import dataclass
from pathlib import Path

from ..util.errors import LogError
from .mcap_stream import register_definition

MAGIC = b"#ROSBAG V2.0\n"
_U32 = struct.Struct("<I")


def ends_early(path: Path) -> bool:
    """Whether a ROS 1 bag's header points at an index beyond the end of the file (written in part)."""
    try:
        with open(path, "rb") as f:
            if f.read(len(MAGIC)) != MAGIC:
                return False
            fields, _, _ = _record(f.read(4096 + 8), 0)
    except (OSError, LogError, struct.error):
        return False
    index = int.from_bytes(fields.get(b"index_pos", b"\0" * 8), "little")
    return index == 0 or index >= path.stat().st_size


def _record(data: bytes, offset: int):
    """``(header fields, data, next offset)`` of the record at ``offset``; a LogError when it is not whole."""
    if offset + 4 > len(data):
        raise LogError("incomplete")
    header_length = _U32.unpack_from(data, offset)[0]
    start = offset + 4
    if start + header_length + 4 > len(data):
        raise LogError("incomplete")
    fields, k = {}, start
    while k < start + header_length:
        length = _U32.unpack_from(data, k)[0]
        name, _, value = data[k + 4:k + 4 + length].partition(b"=")
        fields[name] = value
        k += 4 + length
    data_length = _U32.unpack_from(data, start + header_length)[0]
    body = start + header_length + 4
    if body + data_length > len(data):
        raise LogError("incomplete")
    return fields, data[body:body + data_length], body + data_length


def _ros2_name(name: str) -> str:
    """``pkg/Type`` as ``pkg/msg/Type``, the name ``rosbags`` keys its types by."""
    parts = name.split("/")
    return f"{parts[0]}/msg/{parts[-1]}" if len(parts) == 2 else name


@dataclass
class _Connection:
    topic: str
    msgtype: str
    msgcount: int = 0


class PartialBag1:
    """The complete chunks of a cut-off ROS 1 bag, with the reader interface of ``rosbags``' AnyReader."""

    def __init__(self, path: Path):
        from rosbags.typesys import Stores, get_typestore

        self.store = get_typestore(Stores.ROS1_NOETIC)
        data = path.read_bytes()
        by_id: dict[int, _Connection] = {}
        self.records: list[tuple[_Connection, int, bytes]] = []
        offset = len(MAGIC)
        while True:
            try:
                fields, body, offset = _record(data, offset)
            except (LogError, struct.error):
                break  # the first record not written whole: the recording ends here
            if fields.get(b"op") != b"\x05":
                continue
            compression = fields.get(b"compression", b"none")
            if compression == b"bz2":
                body = bz2.decompress(body)
            elif compression != b"none":
                raise LogError(f"{path}: a chunk is compressed with "
                               f"{compression.decode()}, which the reading of a "
                               f"cut-off bag does not decompress (none and bz2 only)")
            self._chunk(body, by_id)
        if not self.records:
            raise LogError(f"{path}: the bag ends before its index, at "
                           f"byte {len(data)}, and before any complete "
                           f"chunk of messages (a recording cut off by a crash or power loss?)")
        self.connections = [c for c in by_id.values() if c.msgcount]
        self.start_time = min(ns for _, ns, _ in self.records)
        self.end_time = max(ns for _, ns, _ in self.records)
        self.note = (f"{path}: the bag ends before its index, at byte "
                     f"{len(data)} (a recording cut off by a crash or "
                     f"power loss?): read up to its last complete chunk, "
                     f"{(self.end_time - self.start_time) / 1e9:g} s of messages")

    def _chunk(self, data: bytes, by_id: dict[int, _Connection]) -> None:
        offset = 0
        while offset < len(data):
            fields, body, offset = _record(data, offset)
            op = fields.get(b"op")
            if op == b"\x07":  # a connection: its topic, type and message definition
                conn_id = _U32.unpack(fields[b"conn"])[0]
                info, k = {}, 0
                while k < len(body):
                    length = _U32.unpack_from(body, k)[0]
                    name, _, value = body[k + 4:k + 4 + length].partition(b"=")
                    info[name] = value
                    k += 4 + length
                msgtype = _ros2_name(info[b"type"].decode())
                register_definition(self.store, msgtype, info[b"message_definition"].decode(), _ros2_name)
                by_id.setdefault(conn_id, _Connection(fields[b"topic"].decode(), msgtype))
            elif op == b"\x02":  # a message
                conn = by_id[_U32.unpack(fields[b"conn"])[0]]
                sec, nsec = struct.unpack("<II", fields[b"time"])
                conn.msgcount += 1
                self.records.append((conn, sec * 10**9 + nsec, body))

    def messages(self, connections=None):
        wanted = None if connections is None else {id(c) for c in connections}
        for conn, ns, raw in self.records:
            if wanted is None or id(conn) in wanted:
                yield conn, ns, raw

    def deserialize(self, raw: bytes, msgtype: str):
        return self.store.deserialize_ros1(raw, msgtype)
