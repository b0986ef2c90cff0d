"""Files written whole or not at all, and output paths checked before any work is done.

Every file the suite writes goes to a temporary name beside its target and
is renamed over it only once complete, so that a failure or an interrupt
(Ctrl-C included) leaves the previous output intact and no temporary file
behind.  A symbolic link keeps being a link: its target is replaced.  A
target that is not a regular file -- a device (``/dev/null``), a FIFO, a
terminal or pipe behind ``/dev/stdout`` -- is written to as a stream once the
output is complete, never replaced by a file.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import stat
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path

from .errors import UsageError


@contextmanager
def atomic_path(path: str | Path):
    """Yield a temporary path beside ``path``; on success it replaces ``path``, on any exit by error it is
    removed."""
    path = Path(path)
    if is_stream(path):
        with _through_stream(path) as tmp:
            yield tmp
        return
    path = Path(os.path.realpath(path)) if path.is_symlink() else path
    check_output_file(path)
    with made_folder(path.parent):
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".partial" + path.suffix, dir=path.parent)
        os.close(fd)
        tmp = Path(name)
        try:
            yield tmp
            if tmp.is_file():
                # mkstemp makes 0600; the result gets the mode any new file would
                tmp.chmod(0o666 & ~_umask())
            os.replace(tmp, path)
        except OSError as exc:
            # name the file asked for, not its temporary
            if exc.filename is None or Path(exc.filename) == tmp:
                raise OSError(exc.errno, exc.strerror, str(path)) from exc
            raise
        finally:
            tmp.unlink(missing_ok=True)


@contextmanager
def made_folder(folder: str | Path):
    """Make ``folder`` (and its missing parents); if the block then fails or is interrupted, remove the ones
    made here that are still empty, so that a command that wrote nothing leaves nothing."""
    folder = Path(folder)
    made = [p for p in (folder, *folder.parents) if not p.exists()]
    folder.mkdir(parents=True, exist_ok=True)
    try:
        yield folder
    except BaseException:
        for p in made:  # deepest first
            try:
                p.rmdir()
            except OSError:  # not empty (something was written there) or already gone: keep it
                break
        raise


STEM_LIMIT = 100  # bytes of a name in a file name (file systems take 255; prefixes and suffixes go around it)


def file_stem(name: str) -> str:
    """A name (an actuator's, a joint's) as part of a file name: no path separator, and a long name cut to its
    start and a digest of the whole, so that two long names still give two files."""
    stem = str(name).replace("/", "_").replace("\0", "_")
    if len(stem.encode()) <= STEM_LIMIT:
        return stem
    digest = hashlib.sha1(stem.encode()).hexdigest()[:10]
    return f"{stem.encode()[:STEM_LIMIT - 11].decode(errors='ignore')}-{digest}"


def is_stream(path: str | Path) -> bool:
    """Whether ``path`` (through any links) is something other than a regular file or a folder, or one of this
    process's open files (``/dev/stdout``, ``/dev/fd/N``: replacing the file behind it would lose what else
    the process writes there): written as a stream."""
    if _open_file_of(path) is not None:
        return True
    try:
        mode = os.stat(path).st_mode
    except OSError:  # nothing there yet (or a dangling link): a file will be made
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


@contextmanager
def _through_stream(path: Path):
    """A temporary file (with ``path``'s suffix, which writers read the format from) copied into ``path`` when
    complete, then removed; nothing reaches the stream if the writer fails."""
    folder = Path(tempfile.mkdtemp(prefix=".thermolimb-"))
    tmp = folder / f"out{path.suffix}"
    try:
        yield tmp
        fd = _open_file_of(path)
        with open(tmp, "rb") as source:
            if fd is None:
                with open(path, "wb") as sink:
                    shutil.copyfileobj(source, sink)
            else:  # through the process's own descriptor: a new one would start over at the file's beginning
                sys.stdout.flush()
                sys.stderr.flush()
                with os.fdopen(os.dup(fd), "wb") as sink:
                    shutil.copyfileobj(source, sink)
    except OSError as exc:
        if exc.filename is None or Path(exc.filename) == tmp:
            raise OSError(exc.errno, exc.strerror, str(path)) from exc
        raise
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _open_file_of(path: Path) -> int | None:
    """The descriptor ``/dev/stdout``, ``/dev/stderr``, ``/dev/fd/N`` or ``/proc/self/fd/N`` names, else
    ``None``."""
    text = str(path)
    if text in ("/dev/stdout", "/dev/stderr"):
        return 1 if text.endswith("out") else 2
    for prefix in ("/dev/fd/", "/proc/self/fd/"):
        if text.startswith(prefix) and text[len(prefix):].isdigit():
            return int(text[len(prefix):])
    return None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` whole or not at all."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def _first_existing(path: Path) -> Path:
    for parent in (path, *path.parents):
        if parent.exists():
            return parent
    return Path(".")


def check_output_file(path: str | Path, what: str = "output file") -> Path:
    """Refuse, before any work, a file target that is a directory or whose folder cannot be made or written
    (a device, a FIFO or a terminal is written as a stream, so its folder need not be writable)."""
    path = Path(path)
    if is_stream(path):
        return path
    if path.is_dir():
        raise UsageError(f"{what} {path} is a directory; expected a file name")
    _check_folder(path.parent, what, path)
    return path


def check_output_dir(path: str | Path, what: str = "output folder") -> Path:
    """Refuse, before any work, a folder target that is a file or cannot be made or written."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise UsageError(f"{what} {path} is a file; expected a folder")
    _check_folder(path, what, path)
    return path


def _check_folder(folder: Path, what: str, target: Path) -> None:
    existing = _first_existing(folder)
    if not existing.is_dir():
        raise UsageError(f"{what} {target}: {existing} is a file, so the folder cannot be made")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise UsageError(f"{what} {target}: {existing} is not writable")
    try:  # permissions do not bind root, and a read-only or special file system answers only to a real write
        tempfile.TemporaryFile(dir=existing).close()
    except OSError as exc:
        raise UsageError(f"{what} {target}: {existing} cannot be written ({exc.strerror or exc})") from None


def replaces(path: str | Path, mine, flag: str) -> bool:
    """Whether writing ``path`` replaces a file: ``False`` where none is there, ``True`` where the one there
    is the suite's own (``mine(path)`` says so: a mark it writes), said "replaced" by the caller; a file the
    suite did not write is refused in one sentence before anything is written.

    Parameters
    ----------
    path
        The output about to be written.
    mine
        ``mine(path) -> bool``: whether the file there carries what the suite writes in such a file.
    flag
        The option that named it, for the sentence.
    """
    path = Path(path)
    if not path.exists():
        return False
    try:
        ours = bool(mine(path))
    except (OSError, ValueError):
        ours = False
    if not ours:
        raise UsageError(f"{flag} {path} exists and was not written by "
                         "thermolimb; the suite never replaces a file it "
                         f"did not write: move it away or name another file (nothing was written)")
    return True


def holds(mark: bytes, within: int = 65536):
    """``mine`` for :func:`replaces`: the file's first ``within`` bytes hold ``mark``."""
    def mine(path: Path) -> bool:
        with open(path, "rb") as f:
            return mark in f.read(within)

    return mine
