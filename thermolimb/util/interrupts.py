"""The signals that end a command (Ctrl-C, SIGTERM from timeout/systemd/CI, SIGHUP from a closed terminal), and
holding them while something must finish whole (closing a recording, ending worker processes).

Holding is done twice over.  The signals are blocked (``pthread_sigmask``), and the handler the command line
installs (:func:`on_signal`) defers a signal that reaches it inside a held block: Python runs a handler at its next
bytecode, so a signal that arrived just before the mask took effect would otherwise raise inside the block, in the
middle of what it holds (a writer's chunk half indexed).  A deferred signal is raised where the outermost block
ends, as it would have been raised there.  Once one signal has been raised the command is ending, and the handler
ignores the next: a second SIGTERM sent right behind the first must not break the clean-up the first began (a
recording's close) before that clean-up has even held the signals."""

from __future__ import annotations

import contextlib
import os
import signal
import threading

ENDING = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
_held = {"depth": 0, "pending": [], "ending": False, "pid": None}


class Terminated(KeyboardInterrupt):
    """SIGTERM (what timeout, systemd, containers and CI send) or SIGHUP (the terminal closed), met like Ctrl-C:
    writers remove their temporaries, or complete what they were writing."""

    def __init__(self, signum: int = signal.SIGTERM):
        super().__init__(signum)
        self.signum = signum


def install() -> dict:
    """:func:`on_signal` for every signal of :data:`ENDING`, nothing pending; returns the handlers it replaced."""
    _held.update(pending=[], ending=False, pid=os.getpid())
    previous = {signum: signal.getsignal(signum) for signum in ENDING}
    for signum in ENDING:
        signal.signal(signum, on_signal)
    return previous


def on_signal(signum, frame) -> None:
    """The handler of :data:`ENDING`: raises where the program is, or, inside a held block, when the block ends;
    after the first raise, does nothing.  In a process forked from the command (a worker, which its parent ends
    with SIGTERM) the signal takes its default action: the worker ends without a traceback."""
    if os.getpid() != _held["pid"]:
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    if _held["ending"]:
        return
    if _held["depth"] > 0:
        _held["pending"].append(signum)
        return
    _raise(signum)


def _raise(signum: int):
    _held.update(pending=[], ending=True)
    raise KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)


@contextlib.contextmanager
def held():
    """Signals that end the command wait until the block is done (then arrive as they would have); only the main
    thread receives them, so elsewhere this does nothing.  Blocks nest: a signal waits for the outermost end."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _held["depth"] += 1  # first: from here on the handler defers
    before = signal.pthread_sigmask(signal.SIG_BLOCK, ENDING)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, before)  # a blocked signal arrives here, and is deferred
        _held["depth"] -= 1
    if _held["depth"] == 0 and _held["pending"]:  # only when the block ended without an exception of its own
        _raise(_held["pending"][0])


def ignore_further() -> None:
    """The command is already ending: a second Ctrl-C, SIGTERM or SIGHUP must not break its last words, nor kill the
    process by the signal after them."""
    if threading.current_thread() is threading.main_thread():
        for signum in ENDING:
            signal.signal(signum, signal.SIG_IGN)
        _held["pending"].clear()
