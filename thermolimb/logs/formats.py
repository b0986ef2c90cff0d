"""Which format a log path holds: the one place that decides, for reading, writing, following and finding
logs.

A format is told by the path's suffix, or, for a folder, by the ``metadata.yaml`` a ROS 2 bag's folder holds;
a device, a FIFO or standard output without a suffix is a CSV stream.  Readers (:mod:`.reading`), writers
(:mod:`.writing`), the monitor's follower (:mod:`.follow`) and a fleet's search of folders
(:mod:`~thermolimb.workbench.fleet`) each ask here, and none looks at a suffix itself.
"""

from __future__ import annotations

from pathlib import Path
from typing import Mapping

from ..util.atomic import is_stream
from ..util.errors import LogError

BAG_SUFFIXES = (".bag", ".mcap", ".db3")
TABLE_SUFFIXES = {".csv": "csv", ".tsv": "csv", ".txt": "csv", ".parquet": "parquet", ".pq": "parquet",
                  ".xlsx": "xlsx", ".xlsm": "xlsx"}
LOG_SUFFIXES = tuple(TABLE_SUFFIXES) + BAG_SUFFIXES


def is_bag(path: str | Path) -> bool:
    """Whether ``path`` is a ROS bag: a ROS 1 ``.bag``, a ROS 2 ``.mcap`` or ``.db3``, or a ROS 2 bag's
    folder."""
    path = Path(path)
    return path.suffix.lower() in BAG_SUFFIXES or (path.is_dir() and (path / "metadata.yaml").exists())


def is_log(path: str | Path) -> bool:
    """Whether a file or folder found in a search is a log a fleet reads: a log's suffix, or a bag's
    folder."""
    return Path(path).suffix.lower() in LOG_SUFFIXES or is_bag(path)


def kind_of(path: str | Path) -> str:
    """``csv``, ``parquet`` or ``xlsx`` (an Excel workbook), the table a path holds by its suffix; a device, a
    FIFO or standard output without one takes CSV.  Anything else is one sentence
    (:class:`~thermolimb.util.errors.LogError`)."""
    suffix = Path(path).suffix.lower()
    if not suffix and is_stream(path):
        return "csv"
    if suffix in TABLE_SUFFIXES:
        return TABLE_SUFFIXES[suffix]
    if Path(path).is_dir():
        raise LogError(f"{path}: a folder that is not a ROS 2 bag (it has no metadata.yaml); "
                       f"expected a log file, or a ROS 2 bag's folder")
    raise LogError(f"{path}: unknown log format {suffix!r}; expected .csv, .tsv, .txt, .xlsx or .parquet")


def log_format(path: str | Path) -> str:
    """How a log is read: ``bag`` (ROS 1 ``.bag``, ROS 2 ``.mcap``, ``.db3`` or a bag folder), ``csv`` or
    ``parquet``."""
    return "bag" if is_bag(path) else kind_of(path)


def written_as(path: str | Path) -> str:
    """How a log is written: ``mcap`` (a ROS 2 bag in one file, written whole), ``csv`` or ``parquet`` (an
    Excel workbook is read, not written)."""
    kind = "mcap" if Path(path).suffix.lower() == ".mcap" else kind_of(path)
    if kind == "xlsx":
        raise LogError(f"{path}: logs are written as .csv, .parquet or .mcap, not as Excel workbooks; "
                       "expected one of those")
    return kind


def followed_as(path: str | Path) -> str:
    """How a growing log is followed: ``mcap`` (a file, or a ROS 2 bag's folder), ``csv`` or ``parquet`` (an
    Excel workbook is not a log being written)."""
    path = Path(path)
    kind = "mcap" if path.suffix.lower() == ".mcap" or path.is_dir() else kind_of(path)
    if kind == "xlsx":
        raise LogError(f"{path}: an Excel workbook is not a log being written; follow a .csv, .parquet or "
                       ".mcap file")
    return kind


def asked_for(path: str | Path, actuator: str | None, mapping: Mapping[str, str] | None) -> dict:
    """What asking for one ``actuator`` means in this path's format, as :func:`~.reading.read_log`'s keywords:
    a bag's joint to read; a wide table's name for its one actuator (where the map names no actuator column);
    a long table's rows to read (with no map)."""
    if is_bag(path):
        return {"actuator_name": actuator, "actuators": None}
    named = actuator if mapping and "actuator" not in mapping else None
    return {"actuator_name": named, "actuators": [actuator] if actuator and not mapping else None}
