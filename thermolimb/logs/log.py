"""The canonical thermal log, its validation, and one actuator's series and runs."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Iterable, Mapping, Sequence

import numpy as np

from ..model.signals import Signals
from ..util.atomic import atomic_path
from ..util.frozen import FrozenMapping
from ..util.lazy import pandas as pd
from ..util.memory import release_freed
from . import extras
from .align import align, series_of
from .bag_writer import write_mcap
from .bags import is_bag, read_bag
from .mapping import EXTRA, OPTIONAL, REQUIRED, TIME_OF, UNITS, expand_joints, is_pattern, parse_mapping
from .table import (
    LogError,
    first_stamp,
    key_values,
    kind_of,
    read_table,
    refuse_duplicates,
    rows_where,
    shown_names,
    time_seconds,
)
from .units import (
    CANONICAL,
    CELSIUS,
    NOT_GIVEN,
    SCALED,
    base_name,
    canonical_headers,
    channel_units,
    header_unit,
    split_unit,
)

CANONICAL_UNITS = FrozenMapping(CANONICAL)

# no working actuator's winding, housing or air reads outside this: readings beyond are not degC
TEMPERATURE_RANGE_C = (-100.0, 500.0)
VELOCITY_UNITS = {"rad/s": 1.0, "m/s": 1.0, "rpm": 2.0 * np.pi / 60.0, "deg/s": np.pi / 180.0}
MIN_SAMPLES = 20
# A pause in logging longer than this many sampling intervals (and than GAP_MIN_S) splits a log into runs.
GAP_FACTOR = 20.0
GAP_MIN_S = 60.0


@dataclass(frozen=True)
class ActuatorSeries:
    """One thermal channel of a log (or of one run of it): its inputs and its measured temperature."""

    actuator: str
    signals: Signals
    temperature_C: np.ndarray
    run: str = ""
    units: Mapping[str, str] = CANONICAL_UNITS  # of effort, velocity, current, power (see thermolimb.logs.units)

    @property
    def time_s(self) -> np.ndarray:
        return self.signals.time_s

    @property
    def n(self) -> int:
        return self.signals.n

    @property
    def duration_s(self) -> float:
        return float(self.time_s[-1] - self.time_s[0])

    @property
    def median_dt_s(self) -> float:
        return float(np.median(np.diff(self.time_s)))

    def rate_K_per_s(self, at_end: bool = False, window_s: float = 60.0) -> float:
        """Slope of the measured temperature over the first (or last) ``window_s`` seconds (least squares)."""
        t = self.time_s
        if at_end:
            sel = slice(int(np.searchsorted(t, t[-1] - window_s, side="left")), None)
        else:
            sel = slice(0, int(np.searchsorted(t, t[0] + window_s, side="right")))
        if t[sel].size < 3:
            return 0.0
        return float(np.polyfit(t[sel] - t[sel][0], self.temperature_C[sel], 1)[0])

    def slice(self, start: int, stop: int) -> "ActuatorSeries":
        return replace(self, signals=self.signals.slice(start, stop), temperature_C=self.temperature_C[start:stop])

    def split_index(self, fraction: float) -> int:
        """First sample after the first ``fraction`` of the time span (training is ``[0, index)``)."""
        if not 0.0 < fraction < 1.0:
            raise LogError(f"the split fraction must be between 0 and 1 (exclusive), got {fraction}")
        t = self.time_s
        cut = int(np.searchsorted(t, t[0] + fraction * (t[-1] - t[0]), side="right"))
        if cut < MIN_SAMPLES // 2 or self.n - cut < MIN_SAMPLES // 4:
            raise LogError(
                f"actuator {self.actuator}{self.run_label}: {self.n} samples are too few to split at {fraction:.2f} "
                f"(need at least {MIN_SAMPLES // 2} for training and {MIN_SAMPLES // 4} for validation); use a longer "
                f"log, several runs with --validate-on, or another --split"
            )
        return cut

    def split(self, fraction: float) -> tuple["ActuatorSeries", "ActuatorSeries"]:
        """Split by time span: training is the first ``fraction`` of it, validation the rest.

        The validation part starts at the last training sample, so that a
        free run restarted at the split starts from the measured temperature there.
        """
        cut = self.split_index(fraction)
        return self.slice(0, cut), self.slice(cut - 1, self.n)

    @property
    def run_label(self) -> str:
        return f" (run {self.run})" if self.run else ""


@dataclass(frozen=True)
class ThermalLog:
    """A validated log in canonical long format (``frame`` sorted by actuator, then time).

    ``notes`` says what reading changed: rows without a measurement dropped,
    timestamps turned into seconds.
    """

    frame: pd.DataFrame
    source: str = "<memory>"
    notes: tuple[str, ...] = field(default=())
    units: Mapping[str, str] = CANONICAL_UNITS  # of effort, velocity, current, power, from the log (logs.units)
    # read for some actuators only (read_log(actuators=...)): every actuator of the file in its order, and the
    # (time s, temperature degC) of those beside a kept one, which a kept actuator's neighbour coupling reads
    # (none when read with neighbours=False: its series then have no neighbour temperatures)
    order: tuple[str, ...] = ()
    neighbours: Mapping[str, tuple] = FrozenMapping({})

    @cached_property
    def actuators(self) -> tuple[str, ...]:
        return tuple(pd.unique(self.frame["actuator"]))

    @cached_property
    def _groups(self) -> dict:
        """Each actuator's rows, split once (a log's frame is not changed after reading); a log of one actuator
        (read with ``actuators=``) is its own group, not a copy."""
        if len(self.actuators) == 1:
            return {self.actuators[0]: self.frame}
        return {name: g for name, g in self.frame.groupby("actuator", sort=False)}

    @property
    def columns(self) -> tuple[str, ...]:
        return tuple(c for c in REQUIRED + OPTIONAL if c in self.frame.columns)

    @cached_property
    def extras(self) -> tuple[str, ...]:
        """Names of the channels the log carries beyond the canonical ones (:mod:`.extras`); their units are in
        ``units`` as ``extra.NAME``."""
        return tuple(c[len(EXTRA):] for c in self.frame.columns if c.startswith(EXTRA))

    def series(self, actuator: str) -> ActuatorSeries:
        """The channel of one actuator; its neighbours are the actuators before and after it in the log's order."""
        if actuator not in self.actuators:
            raise LogError(f"{self.source}: no actuator {actuator!r}; the log has {', '.join(self.actuators)}")
        groups = self._groups
        g = groups[actuator]
        t = g["time"].to_numpy(float)

        def col(name):
            return g[name].to_numpy(float) if name in g.columns else None

        order = self.order or self.actuators
        i = order.index(actuator)
        others = [order[j] for j in (i - 1, i + 1)
                  if 0 <= j < len(order) and (order[j] in groups or order[j] in self.neighbours)]
        neighbors = None
        if others:
            neighbors = np.column_stack([np.interp(t, *self._temperature_of(o)) for o in others])
        signals = Signals(
            time_s=t, effort=col("effort"), velocity=col("velocity"), current_A=col("current"),
            ambient_C=col("ambient"), neighbor_temperature_C=neighbors, neighbor_names=tuple(others),
            housing_C=col("housing"), power_W=col("power"),
            extra={name: col(EXTRA + name) for name in self.extras},
        )
        return ActuatorSeries(actuator, signals, col("temperature"), units=self.units)

    def _temperature_of(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        if name in self._groups:
            g = self._groups[name]
            return g["time"].to_numpy(float), g["temperature"].to_numpy(float)
        return self.neighbours[name]

    def runs(self, actuator: str) -> list[ActuatorSeries]:
        """The actuator's series cut at pauses in logging (see :func:`gaps`); each run starts from its own reading."""
        whole = self.series(actuator)
        cuts = gaps(whole.time_s)
        if not cuts:
            return [whole]
        edges = [0] + cuts + [whole.n]
        stem = Path(self.source).stem if self.source != "<memory>" else "log"
        pieces = [whole.slice(a, b) for a, b in zip(edges[:-1], edges[1:])]
        return [replace(p, run=f"{stem}#{k + 1}") for k, p in enumerate(pieces) if p.n >= MIN_SAMPLES]

    def describe_gaps(self, actuator: str) -> str | None:
        """A sentence on the runs a log was cut into, or ``None``."""
        whole = self.series(actuator)
        cuts = gaps(whole.time_s)
        if not cuts:
            return None
        lengths = np.diff([0] + cuts + [whole.n])
        dropped = int(np.sum(lengths < MIN_SAMPLES))
        pauses = ", ".join(f"{whole.time_s[c] - whole.time_s[c - 1]:.0f} s at t = {whole.time_s[c - 1]:.0f} s"
                           for c in cuts)
        tail = f"; {dropped} run(s) shorter than {MIN_SAMPLES} samples left out" if dropped else ""
        return (f"{self.source}: actuator {actuator}: logging pauses ({pauses}) cut the log into {len(cuts) + 1} runs, "
                f"each simulated from its own first reading{tail}")

    def write(self, path: str | Path) -> Path:
        """Write CSV, Parquet or a ROS 2 MCAP file (by suffix; see :mod:`.bag_writer`), whole or not at all."""
        path = Path(path)
        if path.suffix.lower() == ".mcap":
            return write_mcap(self, path)
        return write_pieces([self], path)

    def file_frame(self) -> pd.DataFrame:
        """The frame as a file holds it: extra channels under their headers, with units."""
        return self.frame.rename(columns={EXTRA + name: _header(name, self.units.get(EXTRA + name))
                                          for name in self.extras})


def write_pieces(pieces: Iterable[ThermalLog], path: str | Path) -> Path:
    """Write consecutive pieces of one log (the same actuators and columns, later times in each) as one CSV or
    Parquet file, each piece as it comes, the file whole or not at all.  It reads back as the whole log (a log's
    rows are grouped by actuator on reading); only one piece is held at a time."""
    path = Path(path)
    kind = kind_of(path)
    with atomic_path(path) as tmp:
        if kind == "csv":
            for i, piece in enumerate(pieces):
                piece.file_frame().to_csv(tmp, index=False, header=i == 0, mode="w" if i == 0 else "a")
            return path
        import pyarrow as pa
        import pyarrow.parquet as pq

        writer = None
        try:
            for piece in pieces:
                table = pa.Table.from_pandas(piece.file_frame(), preserve_index=False)
                writer = writer or pq.ParquetWriter(tmp, table.schema)
                writer.write_table(table.cast(writer.schema))
        finally:
            if writer is not None:
                writer.close()
    return path


def _header(name: str, unit: str | None) -> str:
    """An extra channel's column header, with its unit when known (read back to the same name and unit)."""
    return name if not unit or unit == NOT_GIVEN else f"{name} [{unit}]"


def gaps(time_s: np.ndarray) -> list[int]:
    """Indices where a run starts after a pause longer than ``GAP_FACTOR`` median intervals and ``GAP_MIN_S``."""
    if time_s.size < 3:
        return []
    dt = np.diff(time_s)
    limit = max(GAP_FACTOR * float(np.median(dt)), GAP_MIN_S)
    return [int(k) + 1 for k in np.flatnonzero(dt > limit)]


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
    """
    path = Path(path)
    if isinstance(mapping, str):  # the command line's form, "effort=torque,temperature=winding"
        mapping = parse_mapping(mapping)
    elif mapping is not None and not isinstance(mapping, Mapping):
        raise LogError(f"mapping must be a dict {{channel: column}} or a string 'channel=column,...', got "
                       f"{type(mapping).__name__}")
    given = {"effort": effort_unit}
    if is_bag(path):
        mapping, from_map = _split_units(mapping)
        frames, notes = read_bag(path, mapping or None, actuator_name, drop_incomplete)
        # a bag's fields carry no units (ROS says N m for JointState.effort; servo drivers often publish mA there)
        units = channel_units({c: "" for c in SCALED}, {**given, **from_map, "velocity": velocity_unit})
        units.update({k: v for k, v in from_map.items() if k.startswith(EXTRA) or k not in SCALED})
        log = from_frame(pd.concat([pd.DataFrame(f) for f in frames], ignore_index=True), source=str(path),
                         units=units)
        return replace(log, notes=tuple(notes) + log.notes)
    options = dict(source=str(path), velocity_unit=velocity_unit, drop_incomplete=drop_incomplete, units=given)
    if actuators and not mapping:
        return _read_selected(path, list(actuators), sep, decimal, options, neighbours)
    frame = read_table(path, sep=sep, decimal=decimal)
    return from_frame(frame, mapping=mapping, actuator_name=actuator_name or path.stem, **options)


def _read_selected(path: Path, names: list[str], sep, decimal, options: dict, neighbours: bool) -> ThermalLog:
    """:func:`read_log` of some actuators of a canonical long table, read in pieces (see its ``actuators``)."""
    order = key_values(path, _is_actuator, sep, decimal)
    if order is None:
        return from_frame(read_table(path, sep=sep, decimal=decimal), actuator_name=path.stem, **options)
    missing = [n for n in names if n not in order]
    if missing:
        raise LogError(f"{path}: no actuator {missing[0]!r}; the log has {', '.join(order)}")
    beside = {order[j] for n in names for j in (order.index(n) - 1, order.index(n) + 1) if 0 <= j < len(order)}
    beside = beside - set(names) if neighbours else set()
    groups = [(set(names), None)] + ([(beside, lambda c: base_name(c) in ("time", "temperature"))] if beside else [])
    frames = rows_where(path, _is_actuator, groups, sep, decimal)
    log = from_frame(frames.pop(0), copy=False, **options)  # popped: the log takes the rows as read
    near_temperatures = {}
    if beside:
        near = frames.pop()
        near["effort"] = 0.0  # a canonical log needs one; the neighbours' are not read
        around = from_frame(near, copy=False, **{**options, "source": f"{options['source']} (neighbours)"})
        del near
        near_temperatures = {n: around._temperature_of(n) for n in around.actuators}
    release_freed()  # the pieces' pages
    return replace(log, order=tuple(order), neighbours=FrozenMapping(near_temperatures))


def _as_text(column: pd.Series) -> pd.Series:
    """A column as text.  A categorical one (a large log read in pieces) stays categorical, with its few
    categories turned into text: converting row by row would make a string per row (144 MB for 2 M rows)."""
    if not isinstance(column.dtype, pd.CategoricalDtype):
        return column.astype(str)
    return column.cat.rename_categories([str(c) for c in column.cat.categories])


def _blank(names: pd.Series) -> np.ndarray:
    """Where a column of actuator names (:func:`_as_text`) is missing or blank."""
    if isinstance(names.dtype, pd.CategoricalDtype):
        codes = names.cat.codes.to_numpy()
        empty = np.array([c.strip() == "" for c in names.cat.categories] + [True])
        return empty[codes]
    return (names.isna() | (names.str.strip() == "")).to_numpy()


def _is_actuator(column: str) -> bool:
    return base_name(column) == "actuator"


def _split_units(mapping: Mapping[str, str] | None) -> tuple[dict[str, str], dict[str, str]]:
    """``{channel: "COLUMN:UNIT"}`` -> ``({channel: COLUMN}, {channel: UNIT})`` (see :func:`~.units.split_unit`)."""
    columns, units = {}, {}
    for key, value in (mapping or {}).items():
        columns[key], unit = split_unit(value)
        if unit:
            units[key] = unit
    return columns, units


def _apply_mapping(frame: pd.DataFrame, mapping: Mapping[str, str], source: str, actuator_name: str,
                   drop_incomplete: bool = False) -> pd.DataFrame:
    if is_pattern(mapping):
        parts = []
        joints = expand_joints(frame.columns, mapping, source)
        per_joint, shared = extras.joint_extras(frame.columns, {k: v for k, v in mapping.items() if k != "actuator"},
                                                [j for j, _, _ in joints])
        for j, name, cols in joints:
            part = pd.DataFrame({k: frame[v] for k, v in cols.items()})
            part.insert(1, "actuator", name)
            for stem, column in per_joint[j].items():
                part[EXTRA + stem] = frame[column].to_numpy()
            for column in shared:
                part[EXTRA + column] = frame[column].to_numpy()
            parts.append(part)
        return pd.concat(parts, ignore_index=True)
    if any(TIME_OF in v for v in mapping.values()):
        return _aligned(frame, mapping, source, actuator_name, drop_incomplete)
    absent = {k: v for k, v in mapping.items() if v not in frame.columns and not (k == "actuator" and "{" in v)}
    if absent:
        k, v = next(iter(absent.items()))
        raise LogError(
            f"{source}: --map {k}={v} names column {v!r}, which the file does not have; "
            f"its columns are {shown_names(frame.columns)}"
        )
    unmapped = [c for c in REQUIRED if c != "actuator" and c not in mapping]
    if unmapped:
        raise LogError(
            f"{source}: --map does not name the column(s) for {', '.join(unmapped)}; add "
            f"{','.join(c + '=COLUMN' for c in unmapped)} with COLUMN among {shown_names(frame.columns)}"
        )
    out = pd.DataFrame({k: frame[v] for k, v in mapping.items()})
    for column in extras.unmapped(frame.columns, mapping):
        out[EXTRA + column] = frame[column]
    if "actuator" not in out.columns:
        out["actuator"] = actuator_name
    return out


def _aligned(frame: pd.DataFrame, mapping: Mapping[str, str], source: str, actuator_name: str,
             drop_incomplete: bool) -> pd.DataFrame:
    """A wide file whose channels have time columns of their own, put on the temperature's samples."""
    if is_pattern(mapping):
        raise LogError(f"{source}: --map cannot mix joint patterns ({{j}}) with per-channel time columns (@)")
    if "temperature" not in mapping or ("time" not in mapping and TIME_OF not in mapping["temperature"]):
        raise LogError(f"{source}: with per-channel time columns, --map names temperature=COLUMN@TIME_COLUMN "
                       f"(or time=COLUMN for the channels without their own)")
    columns, notes = {}, []
    targets = {key: value.partition(TIME_OF) for key, value in mapping.items() if key not in ("time", "actuator")}
    stamps = [first_stamp(frame[t or mapping["time"]]) for _, _, t in targets.values()
              if (t or mapping.get("time")) in frame.columns]
    origin = min((s for s in stamps if s is not None), default=None)
    for key, (column, _, time_column) in targets.items():
        value = mapping[key]
        time_column = time_column or mapping.get("time")
        if time_column is None:
            raise LogError(f"{source}: --map {key}={value} has no time column; write {key}={column}@TIME_COLUMN or "
                           f"give time=COLUMN")
        for c in (column, time_column):
            if c not in frame.columns:
                raise LogError(f"{source}: --map {key}={value} names column {c!r}, which the file does not have; "
                               f"its columns are {shown_names(frame.columns)}")
        columns[key] = series_of(time_seconds(frame[time_column].dropna(), source, time_column, origin),
                                 pd.to_numeric(frame.loc[frame[time_column].notna(), column], errors="coerce"),
                                 source, key, drop_incomplete, notes)
    aligned, more = align(columns.pop("temperature"), columns, source)
    notes += more
    out = pd.DataFrame(aligned)
    out.insert(1, "actuator", actuator_name)
    out.attrs["notes"] = notes
    return out


TIME_SCALES = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "min": 60.0, "h": 3600.0}
# Numbers that are the seconds since 1970 of a day in 2000-2099: a time column counting milliseconds,
# microseconds or nanoseconds since 1970 reads 1e3, 1e6 or 1e9 times as much.
EPOCH_S = (9.46e8, 4.1e9)
EPOCH_UNITS = (("milliseconds", 1e-3), ("microseconds", 1e-6), ("nanoseconds", 1e-9))
# A temperature column whose every reading lies here is in kelvin: no actuator stays at 200 degC or more
# for a whole log (the hottest insulation class is rated 180-220 degC), while 200-500 K is -73 to 227 degC.
KELVIN_READINGS = (200.0, 500.0)
KELVIN_JUMP = (263.15, 283.15)  # a step this large between two readings is a switch between degC and K


def _canonical_with_units(frame: pd.DataFrame, source: str, given: Mapping[str, str], channel: dict,
                          notes: list, stated: dict) -> pd.DataFrame:
    """A canonical log whose headers carry units (``time [s]``, ``effort [N m]``, ``temperature [degC]``):
    columns renamed to their canonical names, inputs' units taken from the header (an option still wins);
    the time's and temperatures' units go to ``stated`` (:func:`_convert_stated`)."""
    renames, units = canonical_headers(frame.columns, REQUIRED + OPTIONAL)
    if not renames:
        return frame
    frame = frame.rename(columns=renames)
    for name, unit in units.items():
        if name in SCALED:
            if name not in given:
                channel[name] = unit
        elif name == "time" or UNITS.get(name) == "degC":
            stated[name] = unit
    return frame


def _convert_stated(frame: pd.DataFrame, stated: Mapping[str, str], source: str, notes: list) -> pd.DataFrame:
    """Time in ms/min/h and temperatures in K, as their headers state, converted (said in the notes); any
    other unit of these refused."""
    for name, unit in stated.items():
        if name not in frame.columns:
            continue
        if name == "time":
            if unit not in TIME_SCALES:
                raise LogError(f"{source}: the time column's header gives the unit {unit!r}, which this suite does "
                               f"not read; expected one of {', '.join(TIME_SCALES)}")
            if unit != "s" and pd.api.types.is_numeric_dtype(frame[name]):
                frame[name] = frame[name] * TIME_SCALES[unit]
                notes.append(f"{source}: time read in {unit} (as stated), converted to s")
        elif unit == "K":
            frame[name] = pd.to_numeric(frame[name], errors="coerce") - 273.15
            notes.append(f"{source}: {name} read in K (as stated), converted to degC")
        elif unit not in CELSIUS:
            raise LogError(f"{source}: the {name} column's header gives the unit {unit!r}, which this suite does not "
                           f"read; expected degC or K")
    return frame


def _mapped_stated(mapping: Mapping[str, str]) -> dict[str, str]:
    """The time's and temperatures' units the mapped columns' headers give (``stamp [ms]``, ``T_winding [K]``)."""
    out = {}
    for name, column in mapping.items():
        if name == "time" or UNITS.get(name) == "degC":
            unit = header_unit(column.partition(TIME_OF)[0])
            if unit:
                out[name] = unit
    return out


def _plausible_units(out: dict[str, np.ndarray], stated: Mapping[str, str], numeric_time: bool, source: str,
                     notes: list) -> None:
    """Unit mistakes a log's numbers show, where no header states the unit: time counted in milliseconds (or
    micro-, nanoseconds) since 1970, converted; time steps too long for seconds, said; temperatures in
    kelvin, converted.  Each said in the notes with the numbers that show it."""
    t = out["time"]
    if "time" not in stated and numeric_time and t.size:
        lo, hi = float(np.min(t)), float(np.max(t))
        for unit, scale in EPOCH_UNITS:
            if EPOCH_S[0] <= lo * scale and hi * scale <= EPOCH_S[1] and not EPOCH_S[0] <= lo <= EPOCH_S[1]:
                day = pd.Timestamp(lo * scale, unit="s").strftime("%Y-%m-%d")
                out["time"] = t * scale
                notes.append(f"{source}: time reads {lo:.13g} at its first sample, which is {day} counted in {unit} "
                             f"since 1970: converted to s (to keep seconds, state them: a header 'time [s]' or --map "
                             f"time=COLUMN:s)")
                break
        else:
            if hi - lo >= 2 * 86400.0:  # only a log of days is looked at step by step
                step = float(np.median(np.diff(np.unique(t))))
                if step >= 100.0:
                        notes.append(f"{source}: time steps of {step:g} s (median) over {(hi - lo) / 86400:.1f} days: if "
                                 f"the time column counts milliseconds, state it: a header 'time [ms]' or --map "
                                 f"time=COLUMN:ms")
    for name in out:
        if UNITS.get(name) != "degC" or name in stated:
            continue
        values = out[name]
        lo, hi = float(np.min(values)), float(np.max(values))
        if KELVIN_READINGS[0] <= lo and hi <= KELVIN_READINGS[1]:
            out[name] = values - 273.15
            notes.append(f"{source}: {name} reads {lo:.1f} to {hi:.1f} throughout, which no actuator stays at in "
                         f"degC: taken as kelvin and converted to degC (to keep degC, state it: a header "
                         f"'{name} [degC]' or --map {name}=COLUMN:degC)")


def _refuse_unit_switch(g: pd.DataFrame, name: str, source: str) -> None:
    """A temperature jumping by about 273 K between two readings: part of the log is in kelvin."""
    for column in g.columns:
        if UNITS.get(column) != "degC":
            continue
        values = g[column].to_numpy()
        jump = np.abs(np.diff(values))
        switch = (jump >= KELVIN_JUMP[0]) & (jump <= KELVIN_JUMP[1])
        if switch.any():
            k = int(np.flatnonzero(switch)[0])
            t = g["time"].to_numpy()
            raise LogError(f"{source}: {column} of actuator {name!r} jumps by {values[k + 1] - values[k]:+.1f} K at "
                           f"row {g.index[k + 1]} (t = {t[k]:g} s to {t[k + 1]:g} s): part of the log reads kelvin, "
                           f"part degC; expected one unit throughout (convert one part)")


def from_frame(
    frame: pd.DataFrame,
    source: str = "<memory>",
    mapping: Mapping[str, str] | None = None,
    velocity_unit: str | None = None,
    actuator_name: str = "actuator",
    drop_incomplete: bool = False,
    units: Mapping[str, str | None] | None = None,
    copy: bool = True,
) -> ThermalLog:
    """Validate a data frame (canonical, or wide with ``mapping``) into a :class:`ThermalLog`.

    Samples with only a time stamp are left out (they hold nothing); a sample
    missing some values is an error unless ``drop_incomplete``.  ``units``
    gives channels' units the frame does not (see :mod:`thermolimb.logs.units`).
    ``copy=False`` lets the log share the frame's float columns instead of copying them: for a frame the
    caller hands over (a large log read once), not one it goes on changing.
    """
    mapping, from_map = _split_units(mapping)
    if velocity_unit is not None and velocity_unit not in VELOCITY_UNITS:
        raise LogError(f"unknown velocity unit {velocity_unit!r}; expected one of {', '.join(VELOCITY_UNITS)}")
    given = {**{k: v for k, v in (units or {}).items() if v}, **from_map}
    if velocity_unit is not None:
        given["velocity"] = velocity_unit
    channel = channel_units(mapping, given)
    notes = []
    stated = {**(_mapped_stated(mapping) if mapping else {}),
              **{k: v for k, v in given.items() if k == "time" or UNITS.get(k) == "degC"}}
    refuse_duplicates(frame, set(mapping.values()) if mapping else set(REQUIRED + OPTIONAL), source, notes)
    if channel["velocity"] not in VELOCITY_UNITS and channel["velocity"] != NOT_GIVEN:
        notes.append(f"{source}: velocity unit {channel['velocity']!r} (from the column's header) is not one this "
                     f"suite converts ({', '.join(VELOCITY_UNITS)}); taken as not given -- name it with --velocity-unit")
        channel["velocity"] = NOT_GIVEN
    if mapping:
        frame = _apply_mapping(frame, mapping, source, actuator_name, drop_incomplete)
        notes += frame.attrs.get("notes", [])
    else:
        frame = _canonical_with_units(frame, source, given, channel, notes, stated)
    frame = _convert_stated(frame, stated, source, notes)
    missing = [c for c in REQUIRED if c not in frame.columns]
    if missing:
        hint = "" if mapping else "; name them with --map canonical=column"
        raise LogError(
            f"{source}: missing column(s) {', '.join(missing)} (expected {', '.join(REQUIRED)}); "
            f"the file has {shown_names(frame.columns)}{hint}"
        )
    keep = [c for c in REQUIRED + OPTIONAL if c in frame.columns]
    frame = frame.reset_index(drop=True)
    measured = [c for c in keep if c not in ("time", "actuator")]
    empty = frame[measured].isna().all(axis=1).to_numpy()
    if empty.any():
        notes.append(f"{source}: {int(empty.sum())} sample(s) (rows times actuators) with no measured value, only a time stamp, left out")
        frame = frame.loc[~empty].reset_index(drop=True)
    if drop_incomplete:
        incomplete = frame[measured].isna().any(axis=1).to_numpy()
        if incomplete.any():
            notes.append(f"{source}: {int(incomplete.sum())} incomplete sample(s) left out (--drop-incomplete), first "
                         f"at row {int(np.flatnonzero(incomplete)[0])}; the inputs before them are held")
            frame = frame.loc[~incomplete].reset_index(drop=True)
    if frame.empty:
        raise LogError(f"{source}: the log has no rows with measurements")
    names = _as_text(frame["actuator"])
    blank = frame["actuator"].isna().to_numpy() | _blank(names)
    if blank.any():
        row = int(np.flatnonzero(blank)[0])
        raise LogError(f"{source}: column 'actuator' is blank at row {row}; expected an actuator name in every row")
    # the validated columns, as arrays (a float column of the frame is taken as it is, not copied)
    out = {"time": np.array(time_seconds(frame["time"], source, "time"), copy=copy), "actuator": names}
    numeric_time = pd.api.types.is_numeric_dtype(frame["time"])
    if not numeric_time:
        notes.append(f"{source}: time stamps turned into seconds from the first sample")
    for c in keep:
        if c in ("time", "actuator"):
            continue
        if pd.api.types.is_float_dtype(frame[c]):
            out[c] = frame[c].to_numpy(float, copy=copy)
            continue
        values = pd.to_numeric(frame[c], errors="coerce")
        bad = values.isna() & frame[c].notna()
        if bad.any():
            row = int(np.flatnonzero(bad.to_numpy())[0])
            raise LogError(f"{source}: column {c!r} is not numeric at row {row} ({frame[c].iloc[row]!r}); "
                           f"expected {UNITS[c]}")
        out[c] = values.to_numpy(float, copy=copy)
    explicit = {k: v for k, v in mapping.items() if k.startswith(EXTRA)}
    extra_values, extra_units, extra_notes = extras.collect(frame, given, explicit, source)
    notes += extra_notes
    for c, values in out.items():
        if c == "actuator":
            continue
        nan = ~np.isfinite(values)
        if nan.any():
            row = int(np.flatnonzero(nan)[0])
            raise LogError(
                f"{source}: column {c!r} has {int(nan.sum())} missing or non-finite value(s), "
                f"first at row {row}; expected finite numbers in {UNITS[c]} (fill them, or leave those samples out "
                f"with --drop-incomplete)"
            )
    _plausible_units(out, stated, numeric_time, source, notes)
    for c in (c for c in out if UNITS.get(c) == "degC"):
        values = out[c]
        outside = (values < TEMPERATURE_RANGE_C[0]) | (values > TEMPERATURE_RANGE_C[1])
        if outside.any():
            row = int(np.flatnonzero(outside)[0])
            raise LogError(
                f"{source}: column {c!r} reads {values[row]:g} at row {row}; expected degC between "
                f"{TEMPERATURE_RANGE_C[0]:g} and {TEMPERATURE_RANGE_C[1]:g} (a log in kelvin, in tenths of a degree "
                f"or in raw counts needs converting first)"
            )
    if "velocity" in out and channel["velocity"] in VELOCITY_UNITS and VELOCITY_UNITS[channel["velocity"]] != 1.0:
        out["velocity"] = out["velocity"] * VELOCITY_UNITS[channel["velocity"]]
        channel["velocity"] = "m/s" if channel["velocity"] == "m/s" else "rad/s"
    for name, values in extra_values.items():
        out[EXTRA + name] = values
        channel[EXTRA + name] = extra_units[name] or NOT_GIVEN
    out = pd.DataFrame(out, copy=False)
    parts = []
    for name, g in _by_actuator(out):
        t = g["time"].to_numpy()
        steps = np.diff(t)
        if np.any(steps <= 0):
            k = int(np.flatnonzero(steps <= 0)[0])
            raise LogError(
                f"{source}: time does not increase for actuator {name!r} at row {g.index[k + 1]} "
                f"(t = {t[k]:g} s then {t[k + 1]:g} s); expected strictly increasing time in seconds"
            )
        if len(g) < MIN_SAMPLES:
            raise LogError(f"{source}: actuator {name!r} has {len(g)} samples; at least {MIN_SAMPLES} are needed")
        _refuse_unit_switch(g, name, source)
        parts.append(g)
    whole = parts[0] if len(parts) == 1 else pd.concat(parts, ignore_index=True)
    return ThermalLog(whole, source, tuple(notes), FrozenMapping(channel))


def _by_actuator(frame: pd.DataFrame):
    """``(name, rows)`` of each actuator in order of appearance; a frame of one actuator is its own rows (no
    copy: a large log read for one actuator is not held twice)."""
    first = frame["actuator"].iloc[0]
    if (frame["actuator"] == first).all():
        return [(first, frame)]
    return frame.groupby("actuator", sort=False, observed=True)


def log_from_arrays(
    time_s: np.ndarray,
    names: tuple[str, ...],
    effort: np.ndarray,
    temperature_C: np.ndarray,
    velocity: np.ndarray | None = None,
    current_A: np.ndarray | None = None,
    ambient_C: np.ndarray | None = None,
    source: str = "<memory>",
    housing_C: np.ndarray | None = None,
    extra: Mapping[str, np.ndarray] | None = None,
) -> ThermalLog:
    """Build a canonical log from ``(n_samples, n_actuators)`` arrays (``ambient_C``: ``(n_samples,)``);
    ``extra``: more channels by column header (unit in brackets, ``fan [%]``), each ``(n_samples, n_actuators)``."""
    n, m = effort.shape
    data = {
        "time": np.tile(time_s, m),
        "actuator": np.repeat(np.asarray(names, dtype=object), n),
        "effort": effort.T.ravel(),
        "temperature": temperature_C.T.ravel(),
    }
    if velocity is not None:
        data["velocity"] = velocity.T.ravel()
    if current_A is not None:
        data["current"] = current_A.T.ravel()
    if ambient_C is not None:
        data["ambient"] = np.tile(ambient_C, m)
    if housing_C is not None:
        data["housing"] = housing_C.T.ravel()
    for column, values in (extra or {}).items():
        data[column] = np.asarray(values).T.ravel()
    return from_frame(pd.DataFrame(data), source=source)
