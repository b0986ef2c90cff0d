"""A bag message's fields as the readers take them: numbers, arrays of numbers per joint and the names that
index them, fields inside sub-messages (``imu.temperature``) and across an array of sub-messages, one number
per element (a Unitree ``LowState``'s ``motor_state.temperature``, its motors numbered from 0), and
ros2_control's ``DynamicJointState`` as one array per state interface.  Shared by the recorded bag's reader
(:mod:`.bags`) and the followed recording's (:mod:`.follow_mcap`)."""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

import numpy as np

from ..util.errors import LogError

NAME_FIELDS = ("name", "names", "joint_names", "joint_name")
NUMERIC_KINDS = "biuf"


@dataclass(frozen=True)
class Interfaces:
    """Per joint, named numbers, as one array per name over the joints that have it: a ros2_control
    ``DynamicJointState`` (each joint's state interfaces), so that ``/dynamic_joint_states.temperature`` maps
    as a JointState's ``effort`` does, or a ``diagnostic_msgs/DiagnosticArray`` (each status's key-value
    strings that read as numbers: ``/diagnostics.Motor_temperature``).  A name's characters other than letters
    and digits read as ``_`` (a field's path splits on dots)."""

    msgtype: str
    joint_names: tuple[str, ...]
    arrays: Mapping[str, tuple[tuple[str, ...], np.ndarray]]  # interface -> (its joints, their values)

    @classmethod
    def of(cls, msgtype: str, named: list[tuple[str, list[tuple[str, float]]]]) -> "Interfaces":
        """From ``[(joint, [(name, value), ...]), ...]``, a joint named twice taken once."""
        joints, values, seen = {}, {}, set()
        for joint, pairs in named:
            if joint in seen:
                continue
            seen.add(joint)
            for name, value in pairs:
                key = re.sub(r"[^0-9A-Za-z]+", "_", name).strip("_")
                joints.setdefault(key, []).append(joint)
                values.setdefault(key, []).append(value)
        return cls(msgtype, tuple(dict.fromkeys(j for j, _ in named)),
                   {k: (tuple(joints[k]), np.array(values[k])) for k in joints})


def _number(text: str) -> float | None:
    try:
        value = float(text)
    except (TypeError, ValueError):
        return None
    return value if np.isfinite(value) else None


def flat_message(msg):
    """``msg`` as the readers take it: a ros2_control ``DynamicJointState`` or a ``DiagnosticArray`` as
    :class:`Interfaces`, any other as is."""
    if hasattr(msg, "interface_values") and hasattr(msg, "joint_names"):
        return Interfaces.of(msg.__msgtype__, [
            (joint, list(zip(i.interface_names, np.asarray(i.values, float).tolist())))
            for joint, i in zip(msg.joint_names, msg.interface_values)])
    statuses = getattr(msg, "status", None)
    if isinstance(statuses, list) and all(hasattr(s, "values") and hasattr(s, "name") for s in statuses):
        return Interfaces.of(msg.__msgtype__, [
            (s.name, [(kv.key, v) for kv in s.values for v in [_number(kv.value)] if v is not None])
            for s in statuses])
    return msg


def named_within(names, joints) -> dict[str, str]:
    """``{name: joint}`` for each of ``names`` that holds one of ``joints`` as a word (bounded by anything but
    a letter or a digit; of several, the longest), a joint that two names hold being neither's."""
    rename = {}
    for name in names:
        found = [j for j in joints if re.search(rf"(?<![A-Za-z0-9]){re.escape(j)}(?![A-Za-z0-9])", name)]
        longest = [j for j in found if len(j) == max(map(len, found))]
        if len(longest) == 1:
            rename[name] = longest[0]
    taken = Counter(rename.values())
    return {n: j for n, j in rename.items() if taken[j] == 1}


def _fields(msg) -> dict[str, object]:
    if isinstance(msg, Interfaces):
        return {k: values for k, (_, values) in msg.arrays.items()}
    return {k: getattr(msg, k) for k in getattr(msg, "__dataclass_fields__", {}) if k != "__msgtype__"}


def _numeric(value) -> bool:
    if isinstance(value, np.ndarray):
        return value.size > 0 and value.dtype.kind in NUMERIC_KINDS
    if isinstance(value, (list, tuple)):
        return bool(value) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _message_array(value) -> bool:
    """An array of sub-messages, one per motor (a Unitree ``LowState``'s ``motor_state``)."""
    return (
        isinstance(value, (list, tuple))
        and bool(value)
        and all(hasattr(v, "__dataclass_fields__") for v in value)
    )


def numeric_fields(msg, prefix: str = "", scalars: bool = False) -> list[str]:
    """The fields holding numbers (``a.b`` inside a sub-message; inside an array of sub-messages, its
    elements' numbers, one per element: ``motor_state.temperature``)."""
    out = []
    for k, v in _fields(msg).items():
        if hasattr(v, "__dataclass_fields__"):
            if k not in ("header", "stamp"):
                out += numeric_fields(v, f"{prefix}{k}.", scalars)
        elif _message_array(v) and not scalars:
            out += numeric_fields(v[0], f"{prefix}{k}.", scalars=True)
        elif _numeric(v) and not (scalars and isinstance(v, (list, tuple, np.ndarray))):
            out.append(prefix + k)
    return out


def joint_names(msg, field: str | None = None) -> tuple[str, ...]:
    """The joints a message names (those of ``field``'s values, where they are its own: an interface's);
    without a name array, those an array of sub-messages (on ``field``'s path, or the first) names in its
    elements' own ``name`` (a servo driver's list of motor states); else none (the readers then take another
    topic's order, or number them: :func:`numbered`)."""
    if isinstance(msg, Interfaces):
        return msg.arrays[field][0] if field in msg.arrays else msg.joint_names
    for k in NAME_FIELDS:
        v = getattr(msg, k, None)
        if isinstance(v, (list, tuple)) and all(isinstance(s, str) for s in v):
            return tuple(v)
    array = _array_on(msg, field)
    own = next(([getattr(v, k) for v in array] for k in NAME_FIELDS
                if all(isinstance(getattr(v, k, None), str) for v in array)), None) if array else None
    return tuple(own) if own and len(set(own)) == len(own) else ()


def numbered(msg, field: str | None = None) -> tuple[str, ...]:
    """The joints a message names, else its array of sub-messages' elements numbered from 0 (a Unitree
    ``LowState``'s motor slots)."""
    array = _array_on(msg, field)
    return joint_names(msg, field) or (tuple(str(k) for k in range(len(array))) if array else ())


def _array_on(msg, field: str | None):
    """The array of sub-messages on ``field``'s path (without a field, the message's first), or ``None``."""
    value, path = (
        msg,
        field.split(".") if field else [k for k, v in _fields(msg).items() if _message_array(v)][:1],
    )
    for part in path:
        value = _fields(value).get(part) if hasattr(value, "__dataclass_fields__") else None
        if _message_array(value):
            return value
    return None


def field_value(msg, field: str, topic: str, path: Path):
    """``msg``'s ``field`` (``a.b`` inside a sub-message): a number or an array of numbers, else a
    one-sentence refusal naming the message's numeric fields."""
    value, parts = msg, field.split(".")
    for k, part in enumerate(parts):
        # one number per element: the rest of the path
        if _message_array(value) and part in _fields(value[0]):
            each = [field_value(v, ".".join(parts[k:]), topic, path) for v in value]
            if any(np.ndim(v) for v in each):
                raise LogError(f"{path}: field {topic}.{field} holds several numbers in each element of "
                               f"{'.'.join(parts[:k])}; expected one number per element (per motor)")
            return np.array(each, float)
        fields = _fields(value) if hasattr(value, "__dataclass_fields__") else {}
        if part not in fields:
            have = ", ".join(numeric_fields(msg)) or "no numeric field"
            kind = msg.msgtype if isinstance(msg, Interfaces) else msg.__msgtype__
            raise LogError(f"{path}: topic {topic} ({kind}) has no field "
                           f"{field!r}; its numeric fields are {have}")
        value = fields[part]
    if not _numeric(value) and not (isinstance(value, (list, np.ndarray)) and len(value) == 0):
        raise LogError(f"{path}: field {topic}.{field} holds "
                       f"{type(value).__name__} values, not numbers; expected "
                       f"a number or an array of numbers per joint")
    return value
