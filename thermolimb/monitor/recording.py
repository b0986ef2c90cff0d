"""The monitor's MCAP, written so that nothing is lost: ROS 2 messages (CDR, ``ros2msg`` schemas from
``rosbags``' type store) through the ``mcap`` package's writer, into ``OUT.mcap.partial`` beside the target.

* Chunks are flushed to the disk at least every :data:`FLUSH_S` seconds of wall time, so a monitor killed
  without a word (SIGKILL, a power cut) leaves a partial file that any stream reader reads up to its last
  chunk (Foxglove opens it as it is).
* A run that ends -- at ``--idle-exit``, on Ctrl-C, SIGTERM or SIGHUP -- finishes the file (its summary and
  footer) and renames it over the target; a run that published nothing (the followed log never appeared, its
  header was refused) removes its partial and leaves an earlier file at the target as it was.
* The partial is locked while it is written (``flock``): a second monitor given the same ``--mcap`` is refused
  in one sentence; a partial nobody holds is what a killed monitor left, and the next monitor given that
  target first completes it into ``OUT.recovered.mcap`` (:func:`recover`), says so, then starts its own.
"""

from __future__ import annotations

import fcntl
import os
import sys
import time
from contextlib import contextmanager, suppress
from pathlib import Path

from ..util.errors import WRITE_FAULTS, OutputLost, UsageError
from ..util.interrupts import held
from .estimator import Estimate
from .outputs import diagnostic_values, stamp_ns, topic

FLUSH_S = 2.0  # the longest a published message waits in memory before it is on the disk
CHUNK_BYTES = 1 << 20  # a chunk is also flushed when it holds this much


def partial_path(path: Path) -> Path:
    return path.with_name(path.name + ".partial")


class McapOutput:
    """An MCAP of standard ROS 2 messages, written as the monitor goes (module docstring)."""

    def __init__(self, path: str | Path, actuators: list[str], clock=time.monotonic):
        from mcap.writer import CompressionType, Writer
        from rosbags.typesys import Stores, get_typestore

        self.path = Path(path)
        self.partial = partial_path(self.path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        _take_over(self.partial, self.path)
        self.file = _created_locked(self.partial, self.path)
        self.clock, self.flushed_at, self.messages = clock, clock(), 0
        self.store = get_typestore(Stores.ROS2_HUMBLE)
        types = self.store.types
        self.Temperature, self.Header, self.Time = (
            types["sensor_msgs/msg/Temperature"],
            types["std_msgs/msg/Header"],
            types["builtin_interfaces/msg/Time"],
        )
        self.Array, self.Status, self.KeyValue = (types["diagnostic_msgs/msg/DiagnosticArray"],
                                                  types["diagnostic_msgs/msg/DiagnosticStatus"],
                                                  types["diagnostic_msgs/msg/KeyValue"])
        self.writer = Writer(self.file, chunk_size=CHUNK_BYTES, compression=CompressionType.ZSTD)
        self.writer.start(profile="ros2", library="thermolimb monitor")
        schemas = {t.__msgtype__: self.writer.register_schema(
            t.__msgtype__, "ros2msg", self.store.generate_msgdef(t.__msgtype__, ros_version=2)[0].encode())
            for t in (self.Temperature, self.Array)}

        def channel(name, msgtype):
            return self.writer.register_channel(name, "cdr", schemas[msgtype])

        temperature = self.Temperature.__msgtype__
        self.winding = {a: channel(topic(a, "winding_temperature"), temperature) for a in actuators}
        self.measured = {a: channel(topic(a, "measured_temperature"), temperature) for a in actuators}
        self.diagnostics = channel("/diagnostics", self.Array.__msgtype__)
        self.writer.flush()

    def _header(self, ns: int, frame: str):
        return self.Header(stamp=self.Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id=frame)

    def _write(self, channel: int, ns: int, message, msgtype: str) -> None:
        self.writer.add_message(channel, log_time=ns, data=self.store.serialize_cdr(message, msgtype),
                                publish_time=ns)
        self.messages += 1

    def publish(self, estimates: list[Estimate], models: dict[str, str]) -> None:
        # a signal in the middle of the writer's bookkeeping would leave its chunk index wrong
        with held(), self._room():
            self._publish(estimates, models)

    @contextmanager
    def _room(self):
        """A write that finds no room (a full disk, a quota, a file size limit) ends the recording: its file
        is closed as it stands, the partial kept (readable up to its last chunk, completed by the next monitor
        given the same ``--mcap``), and :class:`~thermolimb.util.errors.OutputLost` says so."""
        try:
            yield
        except OSError as exc:
            if exc.errno not in WRITE_FAULTS:
                raise
            with suppress(OSError):
                self.file.close()
            raise OutputLost(exc.errno, self.path, (
                f"stopped recording {self.path}: {WRITE_FAULTS[exc.errno]} after {self.messages} messages; "
                f"{self.partial} keeps those flushed before, readable up to its last chunk (a monitor given "
                f"--mcap {self.path} again completes it into {self.path.stem}.recovered.mcap)")) from None

    def _publish(self, estimates: list[Estimate], models: dict[str, str]) -> None:
        temperature = self.Temperature.__msgtype__
        for e in estimates:
            if e.actuator not in self.winding:
                continue  # an actuator the recording was not opened for
            stamp = stamp_ns(e.time_s)
            header = self._header(stamp, e.actuator)
            self._write(self.winding[e.actuator], stamp,
                        self.Temperature(header=header, temperature=e.winding_C, variance=e.winding_std_K**2),
                        temperature)
            self._write(self.measured[e.actuator], stamp,
                        self.Temperature(header=header, temperature=e.measured_C, variance=0.0), temperature)
        ns = stamp_ns(max(e.time_s for e in estimates))
        statuses = [
            self.Status(
                level=e.level,
                name=f"thermolimb/{e.actuator}",
                message=e.message(),
                hardware_id=e.actuator,
                values=[self.KeyValue(key=k, value=v) for k, v in diagnostic_values(e, models[e.actuator])],
            )
            for e in estimates
        ]
        self._write(self.diagnostics, ns, self.Array(header=self._header(ns, ""), status=statuses),
                    self.Array.__msgtype__)
        self.flush_if_due()

    def flush_if_due(self) -> None:
        """The chunk so far onto the disk when :data:`FLUSH_S` has passed since the last: a kill loses at most
        that (called after each publication, and by the follow loop while the log does not grow)."""
        if self.clock() - self.flushed_at >= FLUSH_S and not self.file.closed:
            with held(), self._room():
                self.writer.flush()
                os.fsync(self.file.fileno())
            self.flushed_at = self.clock()

    def close(self) -> None:
        """Finish the file and put it at the target -- or, when nothing was published, remove the partial and
        leave the target as it was.  Says which, on standard error."""
        if self.file.closed:
            return
        try:
            if self.messages == 0:
                self.file.close()
                self.partial.unlink(missing_ok=True)
                if self.path.exists():
                    print(f"note: {self.path}: nothing was published; "
                          "the earlier file there is left as it was",
                          file=sys.stderr)
                return
            with self._room():
                self.writer.finish()
                self.file.flush()
                os.fsync(self.file.fileno())
            self.file.close()
            existed = self.path.exists()
            os.replace(self.partial, self.path)
            print(f"{'replaced' if existed else 'wrote'} {self.path} ({self.messages} messages)",
                  file=sys.stderr)
        finally:
            if not self.file.closed:
                self.file.close()


def _created_locked(partial: Path, target: Path):
    """``partial``, new, opened for writing and already locked when it appears: made and locked under a name
    of its own, then linked to ``partial`` (which fails if another monitor made it meanwhile).  Created and
    then locked, a second monitor starting at the same moment could find it unlocked, take it for a killed
    monitor's and remove it.  Where the file system has no hard links, created and locked as two steps."""
    own = partial.with_name(f".{partial.name}.{os.getpid()}")
    own.unlink(missing_ok=True)  # left by a killed process that had this one's number: no live one has it
    file = open(own, "xb")
    try:
        fcntl.flock(file, fcntl.LOCK_EX | fcntl.LOCK_NB)
        try:
            os.link(own, partial)
        except FileExistsError:
            raise _in_use(partial, target) from None
        except OSError:  # no hard links here
            file.close()
            file = open(partial, "xb")
            fcntl.flock(file, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BaseException:
        file.close()
        raise
    finally:
        own.unlink(missing_ok=True)
    return file


def _in_use(partial: Path, target: Path) -> UsageError:
    return UsageError(f"--mcap {target}: another monitor is writing it "
                      f"now ({partial.name} is in use); give another "
                      f"--mcap")


def _take_over(partial: Path, target: Path) -> None:
    """Before writing ``partial``: refuse if another monitor holds it; complete it if a killed one left it."""
    if not partial.exists():
        return
    with open(partial, "rb") as f:
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise _in_use(partial, target) from None
        recovered, messages = recover(partial)
        partial.unlink()
    if messages == 0:
        recovered.unlink()
        print(f"note: {partial}, left by a monitor that did not finish it (killed, or out of room) before "
              f"its first chunk, held no message; removed", file=sys.stderr)
    else:
        print(f"note: {partial} was left by a monitor that did not finish it (killed, or out of room); its "
              f"{messages} messages up to its last chunk are now in {recovered}", file=sys.stderr)


def recover(partial: str | Path, out: str | Path | None = None) -> tuple[Path, int]:
    """An MCAP cut off mid-write (no summary, a chunk half written), completed: every schema, channel and
    message of its whole chunks, into ``out`` (default ``NAME.recovered.mcap`` beside it, never over a file).
    Returns the path and the number of messages kept."""
    from mcap.exceptions import McapError
    from mcap.records import Channel, Message, Schema
    from mcap.stream_reader import StreamReader
    from mcap.writer import CompressionType, Writer

    partial = Path(partial)
    if out is None:
        stem = partial.name.removesuffix(".partial").removesuffix(".mcap")
        out = partial.with_name(f"{stem}.recovered.mcap")
        k = 1
        while out.exists():
            k += 1
            out = partial.with_name(f"{stem}.recovered-{k}.mcap")
    out = Path(out)
    kept = 0
    with open(partial, "rb") as source, open(out, "xb") as target:
        writer = Writer(target, compression=CompressionType.ZSTD)
        writer.start(profile="ros2", library="thermolimb monitor (recovered)")
        schemas, channels = {}, {}
        try:
            for record in StreamReader(source).records:
                if isinstance(record, Schema):
                    schemas[record.id] = writer.register_schema(record.name, record.encoding, record.data)
                elif isinstance(record, Channel) and record.schema_id in schemas:
                    channels[record.id] = writer.register_channel(record.topic, record.message_encoding,
                                                                  schemas[record.schema_id], record.metadata)
                elif isinstance(record, Message) and record.channel_id in channels:
                    writer.add_message(channels[record.channel_id], record.log_time, record.data,
                                       record.publish_time, record.sequence)
                    kept += 1
        except (McapError, EOFError, ValueError, KeyError, IndexError, OSError):
            pass  # the cut: everything before it is kept
        writer.finish()
    return out, kept
