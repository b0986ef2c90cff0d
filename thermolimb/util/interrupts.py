"""The signals that end a command (Ctrl-C, SIGTERM from timeout/systemd/CI, SIGHUP from a closed terminal),
and holding them while something must finish whole (closing a recording, ending worker processes).

Holding is done twice over.  The signals are blocked (``pthread_sigmask``), and the handler the command line
installs (:func:`on_signal`) defers a signal that reaches it inside a held block: Python runs a handler at its
next bytecode, so a signal that arrived just before the mask took effect would otherwise raise inside the
block, in the middle of what it holds (a writer's chunk half indexed).  A deferred signal is raised where the
outermost block ends, as it would have been raised there.  Once one signal has been raised the command is
ending, and the handler ignores the next: a second SIGTERM sent right behind the first must not break the
clean-up the first began (a recording's close) before that clean-up has even held the signals.

A raise can still be lost where the handler runs: inside a finalizer (an object's ``__del__``, a weak
reference's callback) Python prints "Exception ignored" and goes on, and inside library code it can vanish
without a word -- seen in 3 monitors of 100 ended by SIGTERM on a loaded machine, each time with the handler
run inside pandas' ``read_csv`` (its NA-value set-up, an ``int()`` inside ``try ... except ValueError``), the
follow loop going on for ever.  A loop that waits (the monitor's ``--follow``, a pool's results) calls
:func:`check` at each turn, which raises again the signal taken but lost."""

from __future__ import annotations

import contextlib
import os
import signal
import threading

ENDING = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
_held = {"depth": 0, "pending": [], "ending": None, "pid": None}  # ending: the signal raised, once raised


class Terminated(KeyboardInterrupt):
    """SIGTERM (what timeout, systemd, containers and CI send) or SIGHUP (the terminal closed), met like
    Ctrl-C: writers remove their temporaries, or complete what they were writing."""

    def __init__(self, signum: int = signal.SIGTERM):
        super().__init__(signum)
        self.signum = signum


def install() -> dict:
    """:func:`on_signal` for every signal of :data:`ENDING`, nothing pending; returns the handlers it
    replaced."""
    _held.update(pending=[], ending=None, pid=os.getpid())
    previous = {signum: signal.getsignal(signum) for signum in ENDING}
    for signum in ENDING:
        signal.signal(signum, on_signal)
    return previous


def restore(previous: dict) -> None:
    """The handlers :func:`install` replaced, back; nothing pending or ending (a call of the command line
    inside a longer program, a test, leaves no trace)."""
    for signum, handler in previous.items():
        signal.signal(signum, handler)
    _held.update(pending=[], ending=None)


def on_signal(signum, frame) -> None:
    """The handler of :data:`ENDING`: raises where the program is, or, inside a held block, when the block
    ends; after the first raise, does nothing.  In a process forked from the command (a worker, which its
    parent ends with SIGTERM) the signal takes its default action: the worker ends without a traceback."""
    if os.getpid() != _held["pid"]:
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    if _held["ending"] is not None:
        return
    if _held["depth"] > 0:
        _held["pending"].append(signum)
        return
    _raise(signum)


def _raise(signum: int):
    _held.update(pending=[], ending=signum)
    raise KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)


def check() -> None:
    """For a loop that waits, at each turn: a signal already raised whose raise did not end the loop was lost
    on its way (module docstring); it is raised again, here."""
    if (_held["ending"] is not None and _held["pid"] == os.getpid() and _held["depth"] == 0
            and threading.current_thread() is threading.main_thread()):
        _raise(_held["ending"])


@contextlib.contextmanager
def held():
    """Signals that end the command wait until the block is done (then arrive as they would have); only the
    main thread receives them, so elsewhere this does nothing.  Blocks nest: a signal waits for the outermost
    end."""
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
    """The command is already ending: a second Ctrl-C, SIGTERM or SIGHUP must not break its last words, nor
    kill the process by the signal after them."""
    if threading.current_thread() is threading.main_thread():
        for signum in ENDING:
            signal.signal(signum, signal.SIG_IGN)
        _held["pending"].clear()
