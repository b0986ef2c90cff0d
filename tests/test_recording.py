"""The monitor's recording loses nothing: killed without a word it leaves a file readable up to its last chunk,
which the next monitor completes and says; ended by signals, once or twice, at any gap, it is complete and said; a
run that follows nothing never empties an earlier recording; two monitors never write one file."""

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from monitor_logs import model_and_run
from rosbags.highlevel import AnyReader

from thermolimb.cli.main import main
from thermolimb.monitor.recording import recover

THERMOLIMB = str(Path(sys.executable).parent / "thermolimb")
WRITER = """
import sys, time
src, dst, pause = sys.argv[1], sys.argv[2], float(sys.argv[3])
lines = open(src).read().splitlines(True)
with open(dst, "w") as f:
    f.write(lines[0])
    for line in lines[1:]:
        f.write(line)
        f.flush()
        time.sleep(pause)
"""


@pytest.fixture(scope="module")
def model_and_log(tmp_path_factory):
    return model_and_run(tmp_path_factory.mktemp("recording"), 1200, 900)


def messages_in(path: Path) -> int:
    with AnyReader([path]) as reader:
        return sum(1 for _ in reader.messages())


def whole_messages_in(partial: Path, scratch: Path) -> int:
    """The messages of the whole chunks a monitor has written so far (what :func:`recover` would keep)."""
    copy = scratch / "probe.mcap.partial"
    copy.write_bytes(partial.read_bytes())
    out, kept = recover(copy, scratch / "probe.mcap")
    out.unlink()
    copy.unlink()
    return kept


def start(model, live, out, *extra):
    """A monitor following ``live`` (written by another process, a row every 10 ms) into ``out``; its Python
    stacks are dumped to its standard error if it is aborted (:func:`ended`)."""
    return subprocess.Popen([THERMOLIMB, "monitor", str(model), "--follow", str(live), "--mcap", str(out),
                             "--publish-hz", "1", *extra], stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONFAULTHANDLER": "1"})


def ended(monitor, timeout_s=60.0) -> str:
    """The standard error of a monitor that was signalled to end; one that does not end in time fails the test with
    where it was (a signal's end that never came must show what the process was doing)."""
    try:
        return monitor.communicate(timeout=timeout_s)[1]
    except subprocess.TimeoutExpired:
        monitor.send_signal(signal.SIGABRT)
        pytest.fail(f"the monitor did not end within {timeout_s:g} s of its signal; its stacks:\n"
                    + monitor.communicate()[1])


def writer(run, live, pause=0.01):
    return subprocess.Popen([sys.executable, "-c", WRITER, str(run), str(live), str(pause)])


def wait_for(condition, timeout_s=60.0):
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.05)


def test_a_killed_monitor_leaves_a_readable_partial_that_the_next_one_completes(model_and_log, tmp_path):
    model, run = model_and_log
    live, out = tmp_path / "live.csv", tmp_path / "out.mcap"
    partial = tmp_path / "out.mcap.partial"
    w = writer(run, live)
    monitor = start(model, live, out)
    try:
        # chunks reach the disk at least every 2 s: wait until a whole one has (the schemas alone pass 4 KB), then
        # kill without a word
        wait_for(lambda: partial.exists() and whole_messages_in(partial, tmp_path) > 0)
        monitor.kill()
        monitor.wait(timeout=30)
    finally:
        w.kill()
    assert not out.exists() and partial.exists()
    done = subprocess.run([THERMOLIMB, "monitor", str(model), "--follow", str(run), "--mcap", str(out),
                           "--idle-exit", "0.3"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    recovered = tmp_path / "out.recovered.mcap"
    assert "left by a monitor that did not finish it" in done.stderr and str(recovered) in done.stderr
    kept = messages_in(recovered)
    assert kept > 0 and f"its {kept} messages" in done.stderr
    assert not partial.exists() and messages_in(out) > kept


@pytest.mark.parametrize("signals, gap_s", [(("TERM",), 0.0), (("TERM", "TERM"), 0.0), (("TERM", "TERM"), 0.05),
                                            (("HUP",), 0.0), (("INT", "TERM"), 0.01), (("HUP", "TERM"), 0.2)])
def test_signals_once_or_twice_end_with_a_complete_file_and_say_so(model_and_log, tmp_path, signals, gap_s):
    model, run = model_and_log
    live, out = tmp_path / "live.csv", tmp_path / "out.mcap"
    w = writer(run, live, 0.002)
    monitor = start(model, live, out)
    try:
        # once messages are on the disk (before the recording opens, the default action loses nothing)
        partial = tmp_path / "out.mcap.partial"
        wait_for(lambda: partial.exists() and partial.stat().st_size > 4096)
        for name in signals:
            monitor.send_signal(getattr(signal, f"SIG{name}"))
            time.sleep(gap_s)
        err = ended(monitor)
    finally:
        w.kill()
    assert monitor.returncode == 0, err
    said = [line for line in err.splitlines() if line.startswith("wrote ")]
    assert len(said) == 1 and out.exists(), err
    assert f"({messages_in(out)} messages)" in said[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["live.csv", "out.mcap"]  # nothing left behind


def test_an_earlier_recording_is_never_emptied_by_a_run_that_follows_nothing(model_and_log, tmp_path, capsys):
    model, run = model_and_log
    out = tmp_path / "out.mcap"
    assert main(["monitor", str(model), "--follow", str(run), "--mcap", str(out), "--idle-exit", "0.2"]) == 0
    before = out.read_bytes()
    bad_header = tmp_path / "bad.csv"
    bad_header.write_text("when,what\n1,2\n")
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        for argv in (["--follow", str(tmp_path / "never.csv"), "--idle-exit", "0.3"],
                     ["--follow", str(bad_header), "--idle-exit", "0.3"],
                     ["--follow", "/dev/null"],
                     ["--follow", str(run), "--foxglove", str(port), "--idle-exit", "0.3"]):
            capsys.readouterr()
            assert main(["monitor", str(model), "--mcap", str(out), *argv]) == 2, argv
            err = capsys.readouterr().err
            assert "error:" in err and "wrote" not in err
    assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.csv", "out.mcap"]


def test_two_monitors_never_write_one_file_and_a_missing_folder_is_made(model_and_log, tmp_path):
    model, run = model_and_log
    live, out = tmp_path / "live.csv", tmp_path / "new" / "folder" / "out.mcap"
    w = writer(run, live)
    first = start(model, live, out)
    try:
        wait_for(lambda: (out.parent / "out.mcap.partial").exists())
        second = subprocess.run([THERMOLIMB, "monitor", str(model), "--follow", str(run), "--mcap", str(out),
                                 "--idle-exit", "0.3"], capture_output=True, text=True, timeout=120)
        assert second.returncode == 2 and "another monitor is writing it now" in second.stderr
        # the refusal can come before the first has read a row (it then ends writing nothing, by design): its end
        # is asked once a whole chunk of messages is on the disk
        wait_for(lambda: whole_messages_in(out.parent / "out.mcap.partial", tmp_path) > 0)
        first.terminate()
        err = ended(first)
    finally:
        w.kill()
    assert first.returncode == 0 and messages_in(out) > 0, err


def test_a_partial_appears_already_locked_and_one_made_meanwhile_by_another_monitor_is_refused(tmp_path):
    # made and then locked, a partial could be found unlocked by a monitor starting at the same moment, taken for a
    # killed one's and removed; it is made locked under a name of its own, then linked to its name
    from thermolimb.monitor.recording import McapOutput, _created_locked, partial_path
    from thermolimb.util.errors import UsageError

    out = tmp_path / "out.mcap"
    first = McapOutput(out, ["knee"])
    try:
        with pytest.raises(UsageError, match="another monitor is writing it now"):
            McapOutput(out, ["knee"])  # found locked
        with pytest.raises(UsageError, match="another monitor is writing it now"):
            _created_locked(partial_path(out), out)  # made meanwhile (after the check): the link fails
    finally:
        first.file.close()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.mcap.partial"]  # no temporary of its own left


ROOM_BYTES = 16 << 10  # the schemas and channels fit (about 4 KB); the run's messages do not


def _small_files():
    """In the monitor's process: files may not grow past :data:`ROOM_BYTES` (a write past it fails as on a full
    disk, with EFBIG, rather than killing the process)."""
    import resource

    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (ROOM_BYTES, ROOM_BYTES))


@pytest.mark.parametrize("others", [["--json-lines"], []])
def test_a_recording_without_room_is_said_once_kept_as_far_as_it_got_and_the_monitor_goes_on(model_and_log, tmp_path,
                                                                                                others):
    """A write that finds no room (here a file size limit, as a full disk or a quota would) ends the recording in
    one sentence naming the file, what happened and what is kept; the monitor goes on with its other outputs, and
    with none left ends with status 1.  The partial is kept, and the next monitor with room completes it."""
    model, run = model_and_log
    out, partial = tmp_path / "out.mcap", tmp_path / "out.mcap.partial"
    done = subprocess.run([THERMOLIMB, "monitor", str(model), "--follow", str(run), "--mcap", str(out),
                           "--idle-exit", "0.3", *others], capture_output=True, text=True, timeout=120,
                          preexec_fn=_small_files)
    said = [line for line in done.stderr.splitlines() if "stopped recording" in line]
    assert len(said) == 1 and str(out) in said[0] and "the file is too large for the file system" in said[0], \
        done.stderr
    assert f"{partial} keeps those flushed before" in said[0] and "Traceback" not in done.stderr
    if others:  # the JSON lines went on to the end of the log
        assert done.returncode == 0 and len(done.stdout.splitlines()) > 100
    else:  # the last output lost ends the monitor
        assert done.returncode == 1 and f"could not write {out}" in done.stderr
    assert not out.exists() and partial.exists()
    again = subprocess.run([THERMOLIMB, "monitor", str(model), "--follow", str(run), "--mcap", str(out),
                            "--idle-exit", "0.3"], capture_output=True, text=True, timeout=120)
    assert again.returncode == 0 and "did not finish it" in again.stderr, again.stderr
    assert messages_in(out) > 0 and not partial.exists()
