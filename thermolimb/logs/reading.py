"""Reading a log file into a :class:`~.series.ThermalLog`, whatever its format.

A format is added here, in :data:`READERS`: a CSV or Parquet table (:mod:`.table`; a canonical table
read for some actuators only, in pieces), or a ROS 1 or ROS 2 bag (:mod:`.bags`).  What is read is
validated by :func:`~.validate.from_frame`; writing is :mod:`.writing`'s.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Mapping, Sequence

from ..util.errors import LogError
from ..util.frozen import FrozenMapping
from ..util.lazy import pandas as pd
from ..util.memory import release_freed
from .bags import read_bag
from .formats import log_format
from .mapping import EXTRA, parse_mapping
from .series import ThermalLog
from .table import column_names, key_values, read_table, rows_where
from .units import SCALED, base_name, channel_units
from .validate import from_frame
from .wide import split_units


def read_log(
    path: str | Path,
    mapping: Mapping[str, str] | None = None,
    velocity_unit: str | None = None,
    actuator_name: str | None = None,
    sep: str | None = None,
    decimal: str | None = None,
    drop_incomplete: bool = False,
    effort_unit: str | None = None,
    actuators: Sequence[str] | None = None,
    neighbours: bool = True,
    columns: Sequence[str] | None = None,
) -> ThermalLog:
    """Read and validate a log.

    Parameters
    ----------
    mapping
        For wide files: canonical name -> column in the file, or a joint
        pattern (see :mod:`thermolimb.logs.mapping`).  Without an ``actuator``
        entry a wide file is one actuator named ``actuator_name`` (default:
        the file's stem).  For a ROS bag (:mod:`thermolimb.logs.bags`):
        canonical name -> ``/topic.field``, suggested from the bag when omitted.
        A column read on its own time base is named ``column@time column``
        (:mod:`thermolimb.logs.align`).
    actuator_name
        For a bag: the joint to read (default every joint in the mapped topics).
    velocity_unit
        Unit of the velocity column: ``rad/s``, ``m/s``, ``rpm`` or ``deg/s``;
        converted to rad/s (m/s stays m/s).  Default: the column header's
        (``Speed [rpm]``), rad/s for a canonical log, else "unit not given".
    effort_unit
        Unit of the effort channel (``N m``, ``mA``, ``A``, ``W``, ...), when
        neither the header nor the mapping (``effort=COLUMN:mA``) gives it.
        Every channel's unit is in the log's ``units`` (:mod:`thermolimb.logs.units`).
    sep, decimal
        The CSV dialect; guessed from the file when not given.
    drop_incomplete
        Leave out samples with a missing value (said in ``notes``) instead of refusing the file.
    actuators
        For a table in the canonical long format: read only these actuators'
        rows, in pieces, and of the actuators beside them in the file only
        time and temperature (their neighbour coupling's input), so that one
        actuator of a large file takes memory for its own rows alone.
    neighbours
        With ``actuators``: ``False`` reads nothing of the actuators beside
        them, for models without neighbour coupling (their series then have
        no neighbour temperatures).
    columns
        The column names of a CSV file written without a header row, in the
        file's order (read without them, its columns are ``column1``, ...,
        and a note says so).
    """
    if isinstance(mapping, str):  # the command line's form, "effort=torque,temperature=winding"
        mapping = parse_mapping(mapping)
    elif mapping is not None and not isinstance(mapping, Mapping):
        raise LogError(f"mapping must be a dict {{channel: column}} or a string 'channel=column,...', got "
                       f"{type(mapping).__name__}")
    path = Path(path)
    request = _Request(mapping or {}, velocity_unit, actuator_name, sep, decimal, drop_incomplete,
                       effort_unit, tuple(actuators or ()), neighbours, tuple(columns or ()))
    return READERS[log_format(path)](path, request)


@dataclass(frozen=True)
class _Request:
    """What :func:`read_log` was asked, as its readers take it."""

    mapping: Mapping[str, str]
    velocity_unit: str | None
    actuator_name: str | None
    sep: str | None
    decimal: str | None
    drop_incomplete: bool
    effort_unit: str | None
    actuators: tuple[str, ...]
    neighbours: bool
    columns: tuple[str, ...] = ()

    def options(self, path: Path) -> dict:
        """The keyword arguments of :func:`~.validate.from_frame` every table reader passes."""
        return dict(source=str(path), velocity_unit=self.velocity_unit, drop_incomplete=self.drop_incomplete,
                    units={"effort": self.effort_unit})


def _read_bag(path: Path, request: _Request) -> ThermalLog:
    mapping, from_map = split_units(request.mapping)
    frames, notes = read_bag(path, mapping or None, request.actuator_name, request.drop_incomplete)
    # a bag's fields carry no units (ROS says N m for JointState.effort; servo drivers often publish mA there)
    units = channel_units({c: "" for c in SCALED},
                          {"effort": request.effort_unit, **from_map, "velocity": request.velocity_unit})
    units.update({k: v for k, v in from_map.items() if k.startswith(EXTRA) or k not in SCALED})
    log = from_frame(pd.concat([pd.DataFrame(f) for f in frames], ignore_index=True), source=str(path),
                     units=units)
    return replace(log, notes=tuple(notes) + log.notes)


def _read_table(path: Path, request: _Request) -> ThermalLog:
    if request.actuators and not request.mapping and not request.columns:
        return _read_selected(path, list(request.actuators), request)
    frame = read_table(path, sep=request.sep, decimal=request.decimal, names=request.columns)
    return from_frame(frame, mapping=request.mapping or None,
                      actuator_name=request.actuator_name or path.stem, **request.options(path))


READERS = {"bag": _read_bag, "csv": _read_table, "parquet": _read_table, "xlsx": _read_table}


def _read_selected(path: Path, names: list[str], request: _Request) -> ThermalLog:
    """:func:`read_log` of some actuators of a canonical long table, read in pieces (see its
    ``actuators``)."""
    sep, decimal, options = request.sep, request.decimal, request.options(path)
    columns = column_names(path, sep, decimal, request.columns)
    key = next((c for c in columns if base_name(c) == "actuator"), None)
    # a file of one actuator: read whole, named by the one actuator asked for (as a wide file is)
    if key is None:
        return from_frame(read_table(path, sep=sep, decimal=decimal, names=request.columns),
                          actuator_name=names[0] if len(names) == 1 else path.stem, **options)
    order, blank = key_values(path, key, sep, decimal)
    if not order:
        raise LogError(f"{path}: the log has no rows with measurements")
    if blank and not request.drop_incomplete:
        raise LogError(f"{path}: column {key!r} is blank in {blank} "
                       "row(s); expected an actuator name in every row "
                       f"(or leave those rows out with --drop-incomplete)")
    notes = ((f"{path}: {blank} row(s) with a blank actuator name left out (--drop-incomplete)",) if blank
             else ())
    missing = [n for n in names if n not in order]
    if missing:
        raise LogError(f"{path}: no actuator {missing[0]!r}; the log has {', '.join(order)}")
    beside = {
        order[j] for n in names for j in (order.index(n) - 1, order.index(n) + 1) if 0 <= j < len(order)
    }
    beside = beside - set(names) if request.neighbours else set()
    near_columns = {c for c in columns if base_name(c) in ("time", "temperature")}
    groups = [(set(names), None)] + ([(beside, near_columns)] if beside else [])
    frames = rows_where(path, key, groups, sep, decimal)
    log = from_frame(frames.pop(0), copy=False, **options)  # popped: the log takes the rows as read
    near_temperatures = {}
    if beside:
        near = frames.pop()
        near["effort"] = 0.0  # a canonical log needs one; the neighbours' are not read
        around = from_frame(near, copy=False, **{**options, "source": f"{options['source']} (neighbours)"})
        del near
        near_temperatures = {n: around._temperature_of(n) for n in around.actuators}
    release_freed()  # the pieces' pages
    return replace(log, order=tuple(order), neighbours=FrozenMapping(near_temperatures),
                   notes=notes + log.notes)
