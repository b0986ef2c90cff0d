"""The signals that end a command (Ctrl-C, SIGTERM from timeout/systemd/CI, SIGHUP from a closed terminal), and
holding them while something must finish whole (closing a recording, ending worker processes)."""

from __future__ import annotations

import contextlib
import signal
import threading

ENDING = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


@contextlib.contextmanager
def held():
    """Signals that end the command wait until the block is done (then arrive as they would have); only the main
    thread receives them, so elsewhere this does nothing.  Blocks nest: an inner one gives back the mask it found,
    so a signal held by an outer block still waits for the outer block's end."""
    on_main = threading.current_thread() is threading.main_thread()
    before = signal.pthread_sigmask(signal.SIG_BLOCK, ENDING) if on_main else None
    try:
        yield
    finally:
        if on_main:
            signal.pthread_sigmask(signal.SIG_SETMASK, before)


def ignore_further() -> None:
    """The command is already ending: a second Ctrl-C, SIGTERM or SIGHUP must not break its last words, nor kill the
    process by the signal after them."""
    if threading.current_thread() is threading.main_thread():
        for signum in ENDING:
            signal.signal(signum, signal.SIG_IGN)
