"""Where the monitor's estimates go: an MCAP of standard ROS 2 messages, Foxglove's live WebSocket, JSON
lines.

Every output gets, for each actuator at each publication, its :class:`~.estimator.Estimate`:

* ``/thermolimb/<actuator>/winding_temperature``: ``sensor_msgs/msg/Temperature``, the estimated winding
  temperature (degC) and its variance (K^2);
* ``/thermolimb/<actuator>/measured_temperature``: ``sensor_msgs/msg/Temperature``, the reading it was
  corrected with;
* ``/diagnostics``: ``diagnostic_msgs/msg/DiagnosticArray``, one status per actuator named
  ``thermolimb/<actuator>`` (OK, WARN, ERROR; its message in words) with key-values ``winding_C``,
  ``winding_std_K``, ``time_to_limit_s`` (``inf`` when never at the current effort), ``derating``,
  ``limit_C`` and ``model``.

Stamps are the log's time (seconds since the Unix epoch when the log's times are that large, else from
:data:`~thermolimb.logs.bag_writer.START_NS`, as the suite's own MCAP logs are).
"""

from __future__ import annotations

import json
import sys

from ..logs.bag_writer import START_NS
from .estimator import Estimate

EPOCH_S = 1e9  # log times at least this large are taken as Unix time


def stamp_ns(time_s: float) -> int:
    return int(round(time_s * 1e9)) + (0 if time_s >= EPOCH_S else START_NS)


def topic(actuator: str, what: str) -> str:
    return f"/thermolimb/{actuator}/{what}"


def diagnostic_values(e: Estimate, model: str) -> list[tuple[str, str]]:
    ttl = "inf" if e.time_to_limit_s is None else f"{e.time_to_limit_s:.1f}"
    return [("winding_C", f"{e.winding_C:.2f}"), ("winding_std_K", f"{e.winding_std_K:.2f}"),
            ("time_to_limit_s", ttl), ("derating", f"{e.derating:.3f}"), ("limit_C", f"{e.limit_C:g}"),
            ("model", model)]


class JsonLinesOutput:
    """One JSON object per publication on standard output: the time and each actuator's estimate."""

    def __init__(self, stream=None):
        self.stream = stream or sys.stdout

    def publish(self, estimates: list[Estimate], models: dict[str, str]) -> None:
        record = {
            "time_s": max(e.time_s for e in estimates),
            "actuators": {e.actuator: e.to_json() for e in estimates},
        }
        self.stream.write(json.dumps(record, allow_nan=False) + "\n")
        self.stream.flush()

    def close(self) -> None:
        self.stream.flush()


TEMPERATURE_SCHEMA = {
    "type": "object",
    "title": "sensor_msgs/msg/Temperature",
    "properties": {
        "header": {
            "type": "object",
            "properties": {
                "stamp": {
                    "type": "object",
                    "properties": {"sec": {"type": "integer"}, "nanosec": {"type": "integer"}},
                },
                "frame_id": {"type": "string"},
            },
        },
        "temperature": {"type": "number", "description": "degC"},
        "variance": {"type": "number", "description": "K^2"},
    },
}
DIAGNOSTICS_SCHEMA = {
    "type": "object",
    "title": "diagnostic_msgs/msg/DiagnosticArray",
    "properties": {
        "header": TEMPERATURE_SCHEMA["properties"]["header"],
        "status": {
            "type": "array",
            "items": {
                "type": "object",
                "properties": {
                    "level": {"type": "integer"},
                    "name": {"type": "string"},
                    "message": {"type": "string"},
                    "hardware_id": {"type": "string"},
                    "values": {
                        "type": "array",
                        "items": {
                            "type": "object",
                            "properties": {"key": {"type": "string"}, "value": {"type": "string"}},
                        },
                    },
                },
            },
        },
    },
}


class FoxgloveOutput:
    """A live view: the Foxglove SDK's WebSocket server (``pip install thermolimb[live]``), JSON-encoded
    messages with the ROS 2 messages' fields on the same topics as the MCAP; an actuator's channels are made
    when it is first published (a simulated world's actuators come with it)."""

    def __init__(self, port: int, actuators: list[str], host: str = "127.0.0.1"):
        try:
            import foxglove
        except ImportError:
            from ..util.errors import UsageError

            raise UsageError("--foxglove needs the Foxglove SDK: pip install 'thermolimb[live]' "
                             "(the package foxglove-sdk)") from None
        try:
            self.server = foxglove.start_server(name="thermolimb monitor", host=host, port=port)
        except RuntimeError as exc:  # the SDK's FoxgloveError: the port is taken, or not ours to bind
            from ..util.errors import UsageError

            reason = "is in use by another program" if "in use" in str(exc) else f"cannot be served ({exc})"
            raise UsageError(f"--foxglove {port}: port {port} on {host} {reason}; give another port "
                             f"(--foxglove 0 picks a free one)") from None
        self.winding, self.measured = {}, {}
        for a in actuators:
            self._channels(a)
        self.diagnostics = foxglove.Channel("/diagnostics", schema=DIAGNOSTICS_SCHEMA)

    def _channels(self, actuator: str) -> None:
        """The actuator's channels, made the first time it is seen (a simulation's actuators come with its
        world)."""
        if actuator not in self.winding:
            import foxglove

            self.winding[actuator] = foxglove.Channel(topic(actuator, "winding_temperature"),
                                                      schema=TEMPERATURE_SCHEMA)
            self.measured[actuator] = foxglove.Channel(topic(actuator, "measured_temperature"),
                                                       schema=TEMPERATURE_SCHEMA)

    @property
    def port(self) -> int:
        return self.server.port

    def publish(self, estimates: list[Estimate], models: dict[str, str]) -> None:
        for e in estimates:
            self._channels(e.actuator)
            ns = stamp_ns(e.time_s)
            header = {"stamp": {"sec": ns // 10**9, "nanosec": ns % 10**9}, "frame_id": e.actuator}
            self.winding[e.actuator].log({"header": header, "temperature": e.winding_C,
                                          "variance": e.winding_std_K**2}, log_time=ns)
            self.measured[e.actuator].log({"header": header, "temperature": e.measured_C, "variance": 0.0},
                                          log_time=ns)
        ns = stamp_ns(max(e.time_s for e in estimates))
        self.diagnostics.log(
            {
                "header": {"stamp": {"sec": ns // 10**9, "nanosec": ns % 10**9}, "frame_id": ""},
                "status": [
                    {
                        "level": e.level,
                        "name": f"thermolimb/{e.actuator}",
                        "message": e.message(),
                        "hardware_id": e.actuator,
                        "values": [
                            {"key": k, "value": v} for k, v in diagnostic_values(e, models[e.actuator])
                        ],
                    }
                    for e in estimates
                ],
            },
            log_time=ns,
        )

    def close(self) -> None:
        self.server.stop()
