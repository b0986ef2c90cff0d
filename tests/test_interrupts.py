"""Signals from a terminal, a supervisor or the kernel end every worker and the command within seconds, and outputs
onto special files keep what they are."""

import json
import os
import random
import shutil
import signal
import stat
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from thermolimb.cli.main import main
from thermolimb.util import interrupts
from thermolimb.util.atomic import write_text
from thermolimb.util.parallel import STOP_GRACE_S, WORKER_MEMORY_BYTES, worker_limit

CLI = [sys.executable, "-m", "thermolimb.cli.main"]


@pytest.fixture(scope="module")
def fleet(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fleet")
    assert main(["simulate", "--duration", "7200", "--dt", "1", "--out", str(folder / "run00.csv"), "--quiet"]) == 0
    for k in range(1, 16):
        shutil.copy(folder / "run00.csv", folder / f"run{k:02d}.csv")
    return folder


def _alive(group: int) -> list[str]:
    """Processes of the group that still run (a zombie waiting for a PID 1 that does not reap is dead)."""
    out = subprocess.run(["ps", "-o", "pid=,stat=", "-g", str(group)], capture_output=True, text=True).stdout
    return [line.split()[0] for line in out.splitlines() if not line.split()[1].startswith("Z")]


def _start(argv, cwd):
    # a terminal's Ctrl-C goes to every process of the foreground group: a group of its own, SIGINT not ignored
    # (faulthandler: a process that does not end is aborted by the test, and its stacks -- every process's of the
    # group, workers included -- are in its standard error)
    return subprocess.Popen([*CLI, *argv], cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
                            env={**os.environ, "PYTHONFAULTHANDLER": "1"})


def _ended(proc, timeout_s=4 * STOP_GRACE_S) -> int:
    """The exit code of a command that was signalled to end; one that does not end in time fails the test with the
    stacks of every process of its group.  The time: a parent gives each of its two workers and the pool's manager
    up to STOP_GRACE_S to end before it kills them (util/parallel), and a loaded CI machine needs a margin (CI once
    saw a fleet not ended within 20 s of two Ctrl-C, with no stacks to say why: they are now shown)."""
    try:
        return proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGABRT)
        _, err = proc.communicate()
        pytest.fail(f"the command did not end within {timeout_s:g} s of its signals; the stacks of its group:\n"
                    + err.decode(errors="replace"))


def test_ctrl_c_twice_at_random_moments_ends_the_fleet_and_its_workers(fleet):
    rng = random.Random(20261124)
    for _ in range(3):
        proc = _start(["diagnose", str(fleet), "--fleet", "--quiet", "--workers", "2"], fleet)
        time.sleep(rng.uniform(2.0, 4.0))
        os.killpg(proc.pid, signal.SIGINT)
        time.sleep(rng.uniform(0.2, 1.0))
        try:
            os.killpg(proc.pid, signal.SIGINT)
        except ProcessLookupError:
            pass
        try:
            code = _ended(proc)
        finally:
            time.sleep(0.5)
            left = _alive(proc.pid)
            if left:
                os.killpg(proc.pid, signal.SIGKILL)
        err = proc.stderr.read().decode()
        assert not left, f"workers left behind: {left}"
        assert code == 130 and err.strip() == "thermolimb diagnose: interrupted", (code, err)


@pytest.mark.parametrize("signum, expected", [(signal.SIGTERM, 143), (signal.SIGKILL, -9)])
def test_the_main_process_ended_alone_takes_its_workers_with_it(fleet, signum, expected):
    proc = _start(["diagnose", str(fleet), "--fleet", "--quiet", "--workers", "2"], fleet)
    deadline = time.monotonic() + 30
    while len(_alive(proc.pid)) < 3 and time.monotonic() < deadline:  # the parent and both workers
        time.sleep(0.2)
    assert len(_alive(proc.pid)) == 3
    os.kill(proc.pid, signum)  # what timeout, systemd and the OOM killer send: to the main process only
    assert _ended(proc) == expected
    deadline = time.monotonic() + 10
    while _alive(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    left = _alive(proc.pid)
    if left:
        os.killpg(proc.pid, signal.SIGKILL)
    assert not left


def test_a_signal_that_reaches_the_handler_inside_a_held_block_waits_for_its_end_and_a_second_changes_nothing():
    # the race behind a recording closed half-indexed: the kernel delivered the signal just before the mask took
    # effect, and Python ran the handler inside the block; here the handler is run inside the block directly
    previous = interrupts.install()
    done = []
    try:
        with pytest.raises(interrupts.Terminated):
            with interrupts.held():
                with interrupts.held():
                    interrupts.on_signal(signal.SIGTERM, None)
                    done.append("inner")
                done.append("outer")  # the inner block's end does not raise: the outer one still holds
        assert done == ["inner", "outer"]
        interrupts.on_signal(signal.SIGTERM, None)  # the command is ending: a second signal changes nothing
        with interrupts.held():  # a signal blocked by the mask arrives when the block ends (once the command runs)
            interrupts.install()
            os.kill(os.getpid(), signal.SIGHUP)
            done.append("held")
    except interrupts.Terminated as exc:
        assert exc.signum == signal.SIGHUP and done[-1] == "held"
    else:
        pytest.fail("the signal held by the block was lost")
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


def test_workers_are_bounded_by_cores_and_memory_and_the_lowering_is_said():
    cores = len(os.sched_getaffinity(0))
    count, why = worker_limit(1024)
    assert count <= cores and f"--workers 1024 lowered to {count}" in why
    assert f"{WORKER_MEMORY_BYTES / 1e6:.0f} MB per worker" in why
    assert worker_limit(1) == (1, None)


def test_a_fifo_and_a_link_keep_what_they_are(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_text()))
    reader.start()
    write_text(fifo, "a,b\n1,2\n")
    reader.join(timeout=10)
    assert received == ["a,b\n1,2\n"] and stat.S_ISFIFO(os.lstat(fifo).st_mode)
    target = tmp_path / "target.csv"
    target.write_text("old\n")
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    write_text(link, "new\n")
    assert link.is_symlink() and target.read_text() == "new\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv", "pipe", "target.csv"]


def test_a_table_to_standard_output_is_printed_not_a_file(fleet, tmp_path):
    done = subprocess.run([*CLI, "fit", str(fleet / "run00.csv"), "--fleet", "--quiet", "--table", "/dev/stdout",
                           "--workers", "1"], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert done.returncode == 0 and done.stdout.startswith("source,actuator,run,samples,duration_s,")
    assert os.path.islink("/dev/stdout") and not list(tmp_path.iterdir())
    with open(tmp_path / "out.txt", "w") as out:  # standard output redirected to a file: written through it
        subprocess.run([*CLI, "fit", str(fleet / "run00.csv"), "--fleet", "--quiet", "--table", "/dev/stdout",
                        "--workers", "1"], stdout=out, timeout=120, cwd=tmp_path, check=True)
    text = (tmp_path / "out.txt").read_text()
    assert text.startswith("source,actuator,") and "drift:" in text  # the table, then the rows printed after it


def test_a_name_of_any_length_gives_a_bounded_file_name_and_message(tmp_path, capsys):
    import numpy as np
    import pandas as pd

    t = np.arange(300.0)
    name = "k" * 50_000
    pd.DataFrame({"time": t, "actuator": name, "effort": 5 + 3 * np.sin(t / 20),
                  "temperature": 30 + 0.02 * t}).to_csv(tmp_path / "long.csv", index=False)
    assert main(["fit", str(tmp_path / "long.csv"), "--quiet", "--plot", str(tmp_path / "plots")]) == 0
    (png,) = (tmp_path / "plots").iterdir()
    assert len(png.name.encode()) < 120 and png.name.startswith("fit_kkk")
    capsys.readouterr()
    assert main(["fit", str(tmp_path / "long.csv"), "--quiet", "--actuator", "nope"]) == 2
    err = capsys.readouterr().err
    assert len(err) < 600 and "(50000 characters)" in err


def test_a_signal_whose_raise_a_finalizer_swallowed_is_raised_again_where_the_loop_checks():
    # Python runs a handler at its next bytecode, which may be inside an object's __del__: the raise is "ignored"
    # there, and a loop that only a signal ends (monitor --follow) would go on for ever
    swallowed = []

    class DroppedAtOnce:
        def __del__(self):
            os.kill(os.getpid(), signal.SIGTERM)
            sum(range(100))  # bytecodes, inside the finalizer, where the handler runs

    previous, hook = interrupts.install(), sys.unraisablehook
    sys.unraisablehook = lambda unraisable: swallowed.append(unraisable.exc_type)
    try:
        DroppedAtOnce()
        assert swallowed == [interrupts.Terminated]  # lost: the program went on
        interrupts.on_signal(signal.SIGTERM, None)  # a second signal is still ignored ...
        with pytest.raises(interrupts.Terminated) as caught:
            interrupts.check()  # ... but the loop's check raises the first again
        assert caught.value.signum == signal.SIGTERM
    finally:
        sys.unraisablehook = hook
        interrupts.restore(previous)
    interrupts.check()  # restored: nothing is ending


def _with_shared(k: int) -> tuple[int, float]:
    from thermolimb.util.parallel import shared

    return os.getpid(), float(shared()[k])


def test_a_runners_shared_value_reaches_every_job_on_each_backend_and_is_gone_after():
    """A value every job reads (the log a stability check perturbs) goes to each worker once, not with each job;
    the jobs read the same on the process pool and serially, and nothing of it stays after the map."""
    from thermolimb.util.errors import UsageError
    from thermolimb.util.parallel import Runner, run_jobs, shared

    values = np.arange(10.0) ** 2
    pooled = run_jobs(_with_shared, [(k,) for k in range(6)], backend="process", workers=2, shared=values)
    serial = run_jobs(_with_shared, [(k,) for k in range(6)], backend="serial", shared=values)
    assert [v for _, v in pooled] == [v for _, v in serial] == [float(k * k) for k in range(6)]
    assert os.getpid() not in {pid for pid, _ in pooled} and {pid for pid, _ in serial} == {os.getpid()}
    assert shared() is None
    with pytest.raises(UsageError, match="local backends"):
        Runner("ray", shared=values)


def test_one_blas_thread_holds_scipys_openblas_too_when_limited_before_scipy_is_loaded():
    """A command that limits BLAS before its first fit (the command line imports lazily) holds SciPy's LAPACK,
    an OpenBLAS of its own beside NumPy's, at one thread too: a scan that missed it left two workers' SVDs spinning
    on two threads each (30 ms instead of 0.4 ms).  In a fresh interpreter, where nothing has loaded SciPy."""
    code = ("import json, sys; from thermolimb.util.parallel import one_blas_thread\n"
            "assert 'scipy.linalg' not in sys.modules\n"
            "with one_blas_thread():\n"
            "    from threadpoolctl import threadpool_info\n"
            "    blas = [(i['filepath'], i['num_threads']) for i in threadpool_info() if i['user_api'] == 'blas']\n"
            "print(json.dumps(blas))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    blas = json.loads(out)
    assert any("scipy_openblas-" in path or "scipy/" in path for path, _ in blas), blas  # SciPy's own is seen
    assert blas and all(threads == 1 for _, threads in blas), blas
