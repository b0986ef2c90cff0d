"""Reading a log file into a table, as it is written in the wild.

CSV files come with commas, semicolons or tabs, decimal points or decimal
commas (``27,875`` in a ``;``-separated file), ``#`` comment lines, a byte-order
mark, sometimes a preamble of metadata lines before the header (data
loggers write one) and a row of units under it; an Excel workbook's sheet is read as the CSV text it holds.
:func:`read_table` finds the header and the dialect from the file itself; ``sep`` and ``decimal`` override the
guess.  Time
columns may hold numbers (s), ISO-8601 timestamps or datetimes, or clock-style
elapsed times (``1:02.5``, ``0:01:02.5``): :func:`time_seconds` turns each
into seconds from the first sample.
"""

from __future__ import annotations

import csv
import functools
import io
import re
from pathlib import Path

import numpy as np

from ..util.errors import LogError
from ..util.lazy import pandas as pd
from .dialect import check_names, csv_dialect, file_dialect, separator_name
from .formats import kind_of

CHUNK_ROWS = 250_000  # rows per frame when a file is read in pieces
DAY_S = 86400.0
_CLOCK = re.compile(r"^\s*(?:(\d+):)?(\d+):(\d+(?:\.\d*)?)\s*$")


def read_table(path: Path, sep: str | None = None, decimal: str | None = None, names=None) -> pd.DataFrame:
    """The file as a data frame of raw columns (nothing validated yet).

    ``names``: the column names of a CSV file written without a header row (``--columns``); such a file read
    without them has its columns named ``column1``, ``column2``, ... (``frame.attrs["headerless"]`` holds its
    first line, for the note that says so).
    """
    if _kind_checked(path) == "parquet":
        try:
            frame = pd.read_parquet(path)
        except (ValueError, OSError) as exc:
            raise LogError(f"{path}: cannot be read as Parquet: {exc}") from None
        check_names(names, list(frame.columns), None, path)
        return frame
    source, dialect = _csv_source(path, sep, decimal)
    options = dialect.named(names, path)
    try:
        frame = pd.read_csv(source, low_memory=False, **options)
    except (ValueError, OSError, pd.errors.ParserError) as exc:
        raise LogError(f"{path}: cannot be read as a "
                       f"{separator_name(options['sep'])}-separated CSV file: {exc}") from None
    frame.columns = [str(c).strip() for c in frame.columns]
    frame.attrs["duplicate_columns"] = dialect.duplicates
    frame.attrs["headerless"] = dialect.header_line if dialect.headerless else None
    frame.attrs["read_as"] = dialect.read_as
    frame.attrs["named"] = bool(names) and dialect.headerless
    return frame


def column_names(path: Path, sep: str | None = None, decimal: str | None = None, names=None) -> list[str]:
    """The file's column names as its header gives them (stripped), without reading its rows (a file without a
    header row: ``names``, or ``column1``, ``column2``, ...)."""
    if _kind_checked(path) == "parquet":
        import pyarrow.parquet as pq

        try:
            return list(pq.ParquetFile(path).schema_arrow.names)
        except (ValueError, OSError) as exc:
            raise LogError(f"{path}: cannot be read as Parquet: {exc}") from None
    source, dialect = _csv_source(path, sep, decimal)
    options = dialect.named(names, path)
    if "names" in options:
        return list(options["names"])
    header = pd.read_csv(source, nrows=0, **options)
    return [str(c).strip() for c in header.columns]


def table_chunks(path: Path, sep: str | None = None, decimal: str | None = None, columns=None,
                 rows: int = CHUNK_ROWS, names=None):
    """The file's rows in frames of at most ``rows`` rows, with only the ``columns`` kept (a set of names, or
    ``None`` for all): what a large file is read through, in constant memory.  ``names``: as
    :func:`read_table`'s."""
    if _kind_checked(path) == "parquet":
        for batch in _parquet_batches(path, columns, rows):
            yield batch.to_pandas()
        return
    yield from _csv_chunks(path, sep, decimal, columns, rows, names)


def key_values(
    path: Path, key: str, sep: str | None = None, decimal: str | None = None
) -> tuple[list[str], int]:
    """The distinct values (as text) of the column named ``key``, in the order they first appear, and how many
    rows leave it blank; read in pieces."""
    order: dict[str, None] = {}
    blank = 0
    if _kind_checked(path) == "parquet":
        import pyarrow as pa
        import pyarrow.compute as pc

        for batch in _parquet_batches(path, {key}, CHUNK_ROWS):
            values = pc.unique(pc.cast(batch.column(0), pa.string())).to_pylist()
            named = [v for v in values if v is not None and v.strip()]
            if len(named) < len(values):  # a blank or missing name: counted row by row, only then
                text = pc.cast(batch.column(0), pa.string())
                blank += batch.num_rows - int(pc.sum(pc.is_in(text, value_set=pa.array(named, pa.string())),
                                                     min_count=0).as_py() or 0)
            order.update(dict.fromkeys(named))
        pa.default_memory_pool().release_unused()
        return list(order), blank
    for chunk in _csv_chunks(path, sep, decimal, {key}, CHUNK_ROWS):
        column = chunk.iloc[:, 0]
        present = column.dropna().astype(str)
        named = present[present.str.strip() != ""]
        blank += len(column) - len(named)
        order.update(dict.fromkeys(str(a) for a in pd.unique(named)))
    return list(order), blank


def rows_where(
    path: Path, key: str, groups, sep: str | None = None, decimal: str | None = None
) -> list[pd.DataFrame]:
    """For each group ``(values, columns)``: the rows whose column named ``key`` holds one of ``values``
    (compared as text), with the ``columns`` named (a set; ``None``: all), as one frame whose key column is
    categorical (its categories: ``values``).  Read in pieces (Parquet: a row group
    and a column at a time, selected in Arrow) and joined a column at a time, so that the memory is that of
    the rows kept and one column more, not the file's."""
    if _kind_checked(path) == "parquet":
        pieces, attrs = _parquet_pieces(path, key, groups), {}
    else:
        pieces, attrs = _csv_pieces(path, key, groups, sep, decimal)
    return [_joined(columns, attrs) for columns in pieces]


def _csv_pieces(path: Path, key, groups, sep, decimal) -> tuple[list[dict[str, list]], dict]:
    pieces: list[dict[str, list]] = [{} for _ in groups]
    categories = [sorted(values) for values, _ in groups]
    attrs: dict = {}
    for chunk in _csv_chunks(path, sep, decimal, None, CHUNK_ROWS):
        attrs = chunk.attrs
        name = key
        who = chunk[name].astype(str)
        for (values, columns), piece, sorted_values in zip(groups, pieces, categories):
            keep = who.isin(values).to_numpy()
            for c in chunk.columns:
                if c == name:
                    piece.setdefault(c, []).append(pd.Categorical(who[keep], categories=sorted_values))
                elif columns is None or c in columns:
                    piece.setdefault(c, []).append(chunk[c].to_numpy()[keep])
        del chunk, who
    return pieces, attrs


def _parquet_pieces(path: Path, key, groups) -> list[dict[str, list]]:
    import pyarrow as pa
    import pyarrow.compute as pc
    import pyarrow.parquet as pq

    pieces: list[dict[str, list]] = [{} for _ in groups]
    try:
        f = pq.ParquetFile(path, pre_buffer=False)
        names = f.schema_arrow.names
        name = key
        sets = [pa.array(sorted(values), pa.string()) for values, _ in groups]
        for i in range(f.metadata.num_row_groups):
            who = pc.cast(f.read_row_group(i, columns=[name]).column(0), pa.string())
            masks = [pc.is_in(who, value_set=s) for s in sets]
            for s, mask, piece in zip(sets, masks, pieces):
                codes = pc.index_in(pc.filter(who, mask), value_set=s)
                piece.setdefault(name, []).append(pd.Categorical.from_codes(codes.to_numpy(), s.to_pylist()))
            del who
            for c in names:
                if c == name:
                    continue
                wanted = [j for j, (_, columns) in enumerate(groups) if columns is None or c in columns]
                if not wanted:
                    continue
                column = f.read_row_group(i, columns=[c]).column(0)
                for j in wanted:
                    pieces[j].setdefault(c, []).append(_numpy(pc.filter(column, masks[j])))
                del column
    except (ValueError, OSError, pa.ArrowException) as exc:
        raise LogError(f"{path}: cannot be read as Parquet: {exc}") from None
    pa.default_memory_pool().release_unused()
    return pieces


def _numpy(array) -> np.ndarray:
    """An Arrow array's values in memory of numpy's own (nulls as NaN, NaT or None): what is kept of a row
    group outlives it, and Arrow's allocator would hold the pages of every row group read."""
    values = array.to_numpy(zero_copy_only=False)
    return values if values.flags.owndata else values.copy()


def _joined(columns: dict[str, list], attrs: dict) -> pd.DataFrame:
    """One frame of the pieces of each column, joined a column at a time (each column's pieces freed once it
    is joined)."""
    out = {}
    for c, parts in columns.items():
        if isinstance(parts[0], pd.Categorical):
            out[c] = pd.Categorical.from_codes(np.concatenate([p.codes for p in parts]), parts[0].categories)
        else:
            out[c] = np.concatenate(parts)
        parts.clear()
    frame = pd.DataFrame(out, copy=False)
    frame.attrs.update(attrs)
    return frame


def _parquet_batches(path: Path, columns, rows: int):
    """Record batches of at most ``rows`` rows with the ``columns`` picked (see :func:`table_chunks`)."""
    import pyarrow.parquet as pq

    try:
        f = pq.ParquetFile(path, pre_buffer=False)
        names = [n for n in f.schema_arrow.names if columns is None or n in columns]
        yield from f.iter_batches(batch_size=rows, columns=names)
    except (ValueError, OSError) as exc:
        raise LogError(f"{path}: cannot be read as Parquet: {exc}") from None


def _csv_chunks(path: Path, sep, decimal, columns, rows: int, names=None):
    source, dialect = _csv_source(path, sep, decimal)
    options, duplicates = dialect.named(names, path), dialect.duplicates
    usecols = (lambda c: str(c).strip() in columns) if columns is not None else None
    try:
        for chunk in pd.read_csv(source, chunksize=rows, usecols=usecols, **options):
            chunk.columns = [str(c).strip() for c in chunk.columns]
            chunk.attrs["duplicate_columns"] = duplicates
            chunk.attrs["headerless"] = dialect.header_line if dialect.headerless else None
            chunk.attrs["read_as"] = dialect.read_as
            yield chunk
    except (ValueError, OSError, pd.errors.ParserError) as exc:
        raise LogError(f"{path}: cannot be read as a "
                       f"{separator_name(options['sep'])}-separated CSV file: {exc}") from None


def _csv_source(path: Path, sep, decimal):
    """What pandas reads a CSV table from, and its dialect: the file itself, or an Excel workbook's sheet as
    CSV text (:func:`sheet_text`), whose preamble, units row and header are found as a CSV file's are."""
    if _kind_checked(path) == "xlsx":
        text = sheet_text(Path(path))
        return io.StringIO(text), csv_dialect(text, path, sep, decimal)
    return path, file_dialect(path, sep, decimal)


def sheet_text(path: Path) -> str:
    """An Excel workbook's first sheet that holds two rows or more, as CSV text: numbers as Python writes
    them, dates and times in ISO-8601, empty cells empty (read with openpyxl, values as last computed)."""
    stat = path.stat()
    return _sheet_text(str(path), stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=2)
def _sheet_text(path: str, mtime_ns: int, size: int) -> str:
    import openpyxl

    try:
        book = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as exc:  # noqa: BLE001 -- a file that is no workbook, whatever openpyxl raises
        raise LogError(f"{path}: cannot be read as an Excel workbook: {exc}") from None
    try:
        for sheet in book.worksheets:
            rows = [row for row in sheet.iter_rows(values_only=True) if any(v is not None for v in row)]
            if len(rows) >= 2:
                out = io.StringIO()
                writer = csv.writer(out, lineterminator="\n")
                for row in rows:
                    writer.writerow(["" if v is None else v.isoformat() if hasattr(v, "isoformat") else v
                                     for v in row])
                return out.getvalue()
    finally:
        book.close()
    raise LogError(f"{path}: no sheet of the workbook holds two rows or more; expected a header and samples")


def _kind_checked(path: Path) -> str:
    kind = kind_of(path)
    if not Path(path).is_file():
        raise LogError(f"{path}: " + ("not a regular file (a device or a pipe); expected a log file" if
                                      Path(path).exists() else "no such file"))
    return kind


def refuse_duplicates(frame: pd.DataFrame, used, source: str, notes: list[str]) -> None:
    """A header naming a column the log is read by more than once (two ``temperature`` columns) is refused:
    which one holds the reading cannot be known; other repeated names are said (read as ``NAME.1``, ...)."""
    for name, count in frame.attrs.get("duplicate_columns", {}).items():
        if name in used:
            raise LogError(f"{source}: the header names column {name!r} "
                           f"{count} times; expected each column once "
                           f"(rename all but one, or --map to another column)")
        notes.append(f"{source}: the header names column {name!r} {count} times; read as {name!r}, "
                     + ", ".join(repr(f"{name}.{k}") for k in range(1, count)))


def time_seconds(values: pd.Series, source: str, column: str, origin=None, notes=None) -> np.ndarray:
    """Seconds from the first sample, from numbers, datetimes, ISO timestamps or clock-style elapsed times.

    ``origin`` (a UTC timestamp) replaces the first sample as the zero of timestamps, so
    that several time columns share one clock.  A clock that passes midnight is said in ``notes``.
    """
    if pd.api.types.is_datetime64_any_dtype(values):
        stamps = pd.to_datetime(values, utc=True)
        return _from_stamps(stamps, source, column, origin)
    if pd.api.types.is_timedelta64_dtype(values):
        return values.dt.total_seconds().to_numpy(float)
    if pd.api.types.is_float_dtype(values):
        return values.to_numpy(float)
    numeric = pd.to_numeric(values, errors="coerce")
    if numeric.notna().sum() == values.notna().sum():
        return numeric.to_numpy(float)
    text = values.astype(str).str.strip()
    present = values.notna()
    clock = text[present].str.match(_CLOCK.pattern)
    if clock.all():
        parts = text[present].str.extract(_CLOCK.pattern).astype(float).fillna(0.0)
        seconds = np.full(len(values), np.nan)
        of_day = (parts[0] * 3600 + parts[1] * 60 + parts[2]).to_numpy()
        seconds[present.to_numpy()] = past_midnight(of_day)
        days = int(round((seconds[present.to_numpy()][-1] - of_day[-1]) / DAY_S)) if of_day.size else 0
        if days and notes is not None:
            notes.append(f"{source}: time column {column!r} holds times of day that pass midnight "
                         f"{days} time(s): a day added at each")
        return seconds
    try:
        stamps = pd.to_datetime(values, utc=True, format="ISO8601")
    except (ValueError, TypeError):
        each = pd.to_datetime(values, utc=True, format="ISO8601", errors="coerce")
        bad = np.flatnonzero((each.isna() & present).to_numpy())
        good = np.flatnonzero(each.notna().to_numpy())
        if good.size and bad.size:  # most rows are timestamps: the first that is not changes the format
            row = int(bad[0])
            before = int(good[good < row][-1]) if np.any(good < row) else int(good[0])
            raise LogError(f"{source}: time column {column!r} changes "
                           f"format at row {row} ({values.iloc[row]!r}, "
                           f"where row {before} reads {values.iloc[before]!r}); "
                           "expected one format of time stamp "
                           f"throughout (ISO-8601, 2022-10-26T08:17:21.8Z)") from None
        row = int(np.flatnonzero((numeric.isna() & present).to_numpy())[0])
        raise LogError(
            f"{source}: time column {column!r} is not a number "
            "of seconds, a timestamp or an elapsed time at row "
            f"{row} ({values.iloc[row]!r}); expected seconds, ISO-8601 timestamps (2022-10-26T08:17:21.8Z) "
            f"or elapsed times (m:ss.s)"
        ) from None
    return _from_stamps(stamps, source, column, origin)


def past_midnight(seconds: np.ndarray) -> np.ndarray:
    """Times of day (s) carried past midnight: where the clock falls by more than half a day (23:59:59.9, then
    00:00:00.0: a log running overnight beside its date column), a day is added to what follows."""
    days = np.concatenate([[0.0], np.cumsum(np.diff(seconds) < -DAY_S / 2)]) * DAY_S
    return seconds + days


def is_stamped(values: pd.Series) -> bool:
    """Whether a time column holds time stamps (datetimes, ISO-8601 text), not numbers (as text too),
    durations or elapsed times."""
    if pd.api.types.is_datetime64_any_dtype(values):
        return True
    if pd.api.types.is_numeric_dtype(values) or pd.api.types.is_timedelta64_dtype(values):
        return False
    numeric = pd.to_numeric(values, errors="coerce")
    text = values.dropna().astype(str).str.strip()
    return not (numeric.notna().sum() == values.notna().sum() or text.str.match(_CLOCK.pattern).all())


def first_stamp(values: pd.Series):
    """The first UTC timestamp of a time column, or ``None`` when it holds numbers or elapsed times."""
    if not is_stamped(values):
        return None
    if pd.api.types.is_datetime64_any_dtype(values):
        return pd.to_datetime(values, utc=True).dropna().min()
    stamps = pd.to_datetime(values, utc=True, format="ISO8601", errors="coerce")
    return stamps.dropna().min() if stamps.notna().any() else None


def _from_stamps(stamps: pd.Series, source: str, column: str, origin=None) -> np.ndarray:
    valid = stamps.notna()
    if not valid.any():
        raise LogError(f"{source}: time column {column!r} has no timestamp; expected seconds or timestamps")
    first = stamps[valid].iloc[0] if origin is None else origin
    seconds = (stamps - first).dt.total_seconds()
    return seconds.to_numpy(float)
