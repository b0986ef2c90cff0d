"""Writing a thermal log: CSV or Parquet (whole, or a piece at a time) and ROS 2 MCAP, each whole or not at
all.

A format is added here, in :data:`WRITERS` (reading: :mod:`.reading`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

from ..util.atomic import atomic_path
from ..util.lazy import pandas as pd
from .bag_writer import write_mcap
from .formats import kind_of, written_as
from .mapping import EXTRA, OPTIONAL, REQUIRED
from .units import NOT_GIVEN


def write_log(log, path: str | Path) -> Path:
    """Write a :class:`~.series.ThermalLog` as CSV, Parquet or a ROS 2 MCAP file (by suffix; see
    :mod:`.bag_writer`), whole or not at all."""
    path = Path(path)
    return WRITERS[written_as(path)](log, path)


def file_frame(log) -> pd.DataFrame:
    """The frame as a file holds it: extra channels under their headers, with units."""
    return log.frame.rename(columns={EXTRA + name: _header(name, log.units.get(EXTRA + name))
                                     for name in log.extras})


def write_pieces(pieces: Iterable, path: str | Path) -> Path:
    """Write consecutive pieces of one log (:class:`~.series.ThermalLog`) (the same actuators and columns,
    later times in each) as one CSV or Parquet file, each piece as it comes, the file whole or not at all.  It
    reads back as the whole log (a log's rows are grouped by actuator on reading); only one piece is held at a
    time."""
    path = Path(path)
    kind = kind_of(path)
    with atomic_path(path) as tmp:
        if kind == "csv":
            for i, piece in enumerate(pieces):
                file_frame(piece).to_csv(tmp, index=False, header=i == 0, mode="w" if i == 0 else "a")
            return path
        import pyarrow as pa
        import pyarrow.parquet as pq

        writer = None
        try:
            for piece in pieces:
                table = pa.Table.from_pandas(file_frame(piece), preserve_index=False)
                writer = writer or pq.ParquetWriter(tmp, table.schema)
                writer.write_table(table.cast(writer.schema))
        finally:
            if writer is not None:
                writer.close()
    return path


def _header(name: str, unit: str | None) -> str:
    """An extra channel's column header, with its unit when known (read back to the same name and unit); one
    named as a canonical column (a bench's room ``ambient`` beside the coolant mapped as ambient) is written
    as ``extra.NAME``, which reads back as the extra channel ``NAME``."""
    name = EXTRA + name if name in REQUIRED + OPTIONAL else name
    return name if not unit or unit == NOT_GIVEN else f"{name} [{unit}]"


def _write_table(log, path: Path) -> Path:
    return write_pieces([log], path)


WRITERS = {"mcap": write_mcap, "csv": _write_table, "parquet": _write_table}
