"""The monitor's loop: follow a log, update each actuator's estimate, publish, end cleanly."""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field

import numpy as np

from ..model.saved import ModelFile
from ..model.signals import Signals
from ..util.errors import OutputLost, UsageError
from ..util.interrupts import check, held
from .estimator import ActuatorMonitor, Estimate, update_together

CHANNELS = {"velocity": "velocity", "current": "current_A", "ambient": "ambient_C", "power": "power_W",
            "housing": "housing_C"}


@dataclass
class Session:
    """Per actuator, the monitor and the last sample (each piece starts from it); the outputs."""

    models: ModelFile
    limits: dict[str, float]
    outputs: list
    measurement_std_K: float = 0.1
    publish_every_s: float = 0.0  # at most one publication per this much log time (0: every piece)
    monitors: dict[str, ActuatorMonitor] = field(default_factory=dict)
    carry: dict[str, dict] = field(default_factory=dict)
    published_at: float = -np.inf
    ignored: set = field(default_factory=set)  # the log's actuators the model file does not hold
    converted: set = field(default_factory=set)  # the actuators whose effort is converted (said once)
    only: str | None = None  # watch this actuator alone (--actuator), whatever else the log holds
    samples: int = 0
    publications: int = 0
    together: bool = True  # actuators of model/arrays.py's models with one new sample step as arrays

    def feed(self, runs: dict, units: dict | None = None) -> list[Estimate]:
        """Update each actuator that has new rows (:class:`~thermolimb.logs.follow.Run` pieces; one that
        starts a new run, after a pause, starts the actuator's filter again), publishing once per
        ``publish_every_s`` of log time (a piece that spans several such periods, as a log already written
        when the monitor starts, is taken period by period, so that what is published does not depend on how
        often the file was polled). ``units``: the log's channel units, by which an effort in another unit of
        the model's kind is converted (mA for A) and one of another kind refused (a torque for a current).
        The estimates."""
        windows: dict[float, dict[str, dict]] = {}
        for name, pieces in runs.items():
            if self.only is not None and name != self.only:
                continue
            if name not in self.models.actuators:
                if name not in self.ignored:
                    self.ignored.add(name)
                    known = ", ".join(self.models.actuators)
                    print(f"note: the followed log's actuator {name!r} "
                          f"is not in the model file (it holds {known}); "
                          "it is not watched (a file of one actuator "
                          "is named after the file unless --actuator "
                          f"NAME names it)", file=sys.stderr)
                continue
            factor = self._effort_factor(name, units or {})
            for piece in pieces:
                arrays = piece.arrays
                if factor != 1.0:
                    arrays = {**arrays, "effort": arrays["effort"] * factor}
                if piece.new_run:
                    self.carry.pop(name, None)
                before = self.carry.get(name)
                if before is not None:
                    arrays = {k: np.concatenate([before[k], v]) for k, v in arrays.items() if k in before}
                if arrays["time"].size < 2:
                    self.carry[name] = arrays  # one sample: wait for the next
                    continue
                self.samples += arrays["time"].size - (0 if before is None else 1)
                self.carry[name] = {k: v[-1:] for k, v in arrays.items()}
                for k, (key, lo, hi) in enumerate(_periods(arrays["time"], self.publish_every_s)):
                    # a new run starts the actuator's filter again from its first reading
                    windows.setdefault(key, {}).setdefault(name, []).append(
                        ({c: v[lo:hi] for c, v in arrays.items()}, piece.new_run and k == 0))
        estimates = []
        for key in sorted(windows):
            together = []  # one new sample of an actuator whose filter runs, its model in a family: as arrays
            for name, parts in windows[key].items():
                for arrays, restart in parts:
                    if restart:
                        # an actuator already followed, its log written again from an earlier time (beyond a
                        # period): its first sample is published at once (not a first piece that comes late)
                        again = self.monitors.pop(name, None) is not None
                        if again and arrays["time"][0] < self.published_at - self.publish_every_s:
                            self.published_at = -np.inf
                    monitor = self.monitors.get(name)
                    if (self.together and len(parts) == 1 and monitor is not None and monitor.together
                            and monitor.state is not None and arrays["time"].size == 2
                            and all(c in arrays for c in monitor.columns)):
                        together.append((name, monitor, arrays))
                    else:
                        estimates.append(self._update(name, arrays))
            if len(together) > 1:
                estimates += update_together([m for _, m, _ in together], [a for _, _, a in together])
            elif together:
                estimates.append(self._update(together[0][0], together[0][2]))
            last = [m.last for m in self.monitors.values() if m.last is not None]
            if max(e.time_s for e in last) - self.published_at >= self.publish_every_s:
                self.publish(last)
        return estimates

    def _effort_factor(self, name: str, units: dict) -> float:
        """The factor from the log's effort unit to the model's
        (:func:`~thermolimb.model.parameter_units.effort_factor`), said once when it is not one."""
        from ..model.parameter_units import effort_factor

        model_unit = dict(self.models[name].channel_units).get("effort", "")
        factor = effort_factor(model_unit, units.get("effort", ""), f"the model of {name}")
        if factor != 1.0 and name not in self.converted:
            self.converted.add(name)
            print(f"note: {name}: the followed log's effort in {units['effort']} is read in {model_unit}, "
                  f"the model's unit", file=sys.stderr)
        return factor

    def _update(self, name: str, arrays: dict) -> Estimate:
        monitor = self.monitors.get(name) or self._monitor(name)
        signals = Signals(arrays["time"], arrays["effort"],
                          **{CHANNELS[c]: arrays[c] for c in CHANNELS if c in arrays})
        missing = [c for c in monitor.model.columns if not signals.has(c)]
        if missing:
            raise UsageError(f"the model of {name} reads the log column "
                             f"{missing[0]!r}, which the followed log does "
                             f"not have")
        estimate = monitor.update(signals, arrays["temperature"])
        if monitor.note:
            print(f"note: {monitor.note}", file=sys.stderr)
            monitor.note = ""
        return estimate

    def publish(self, estimates: list[Estimate]) -> None:
        names = {n: ",".join(m.model.terms) for n, m in self.monitors.items()}
        for out in list(self.outputs):
            self._each(out, out.publish, estimates, names)
        self.published_at = max(e.time_s for e in estimates)
        self.publications += 1

    def _monitor(self, name: str) -> ActuatorMonitor:
        limit = self.limits.get(name, self.models[name].limit_C)
        if limit is None:
            raise UsageError(f"the model of {name} stores no limit; give --limit-C C")
        self.monitors[name] = ActuatorMonitor(self.models[name], limit, self.measurement_std_K)
        return self.monitors[name]

    def idle(self) -> None:
        """The log did not grow: what the outputs hold goes to the disk when it is due."""
        for out in list(self.outputs):
            if hasattr(out, "flush_if_due"):
                self._each(out, out.flush_if_due)

    def close(self) -> None:
        """Publish what the last publication missed, then close every output (each complete)."""
        last = [m.last for m in self.monitors.values() if m.last is not None]
        try:
            if last and max(e.time_s for e in last) > self.published_at:
                self.publish(last)
        finally:
            for out in list(self.outputs):
                self._each(out, out.close)

    def _each(self, out, call, *args) -> None:
        """``call(*args)`` of one output; one that can no longer be written is said once and dropped, and the
        monitor goes on with the others (the last one lost ends it, said by the command line)."""
        try:
            call(*args)
        except OutputLost as lost:
            self.outputs.remove(out)
            print(f"note: {lost.words}", file=sys.stderr)
            if not self.outputs:
                raise


def _periods(time_s: np.ndarray, period_s: float):
    """``(period, lo, hi)``: the stretches of ``time_s`` within each publication period, each from the last
    sample of the one before (a piece carries on from its predecessor's last sample)."""
    if period_s <= 0:
        yield 0.0, 0, time_s.size
        return
    index = np.floor(time_s / period_s)
    cuts = np.flatnonzero(np.diff(index) > 0) + 1
    lo = 0
    for cut in list(cuts) + [time_s.size - 1]:
        hi = int(cut) + 1
        if hi - lo >= 2:
            yield float(index[hi - 1]), lo, hi
            lo = hi - 1


def follow(session: Session, follower, poll_s: float = 0.05, idle_exit_s: float | None = None,
           clock=time.monotonic, sleep=time.sleep) -> None:
    """Poll ``follower`` until interrupted (Ctrl-C, SIGTERM) or, with ``idle_exit_s``, until the log has not
    grown for that long; what the follower says (a line skipped, a pause, a rotated file) is said as it comes;
    a log that does not exist yet is waited for, and said.  The outputs are closed complete either way.  A log
    that never gave a sample ends in a :class:`~thermolimb.util.errors.UsageError` saying so."""
    grew = clock()
    waiting = False
    try:
        while True:
            check()  # a signal whose raise was lost inside a library still ends the loop (util/interrupts)
            runs = follower.poll()
            _say(follower)
            if runs:
                session.feed(runs, getattr(follower, "units", None))
                grew = clock()
            elif idle_exit_s is not None and clock() - grew >= idle_exit_s:
                session.feed(follower.poll(final=True), getattr(follower, "units", None))
                _say(follower)
                break
            else:
                session.idle()
                if not waiting and not follower.path.exists():
                    waiting = True
                    print(
                        f"note: {follower.path} does not exist yet; waiting for it (Ctrl-C to stop"
                        + (f", or {idle_exit_s:g} s of --idle-exit" if idle_exit_s is not None else "")
                        + ")",
                        file=sys.stderr,
                    )
                sleep(poll_s)
    finally:
        with held():  # a second Ctrl-C or SIGTERM waits until every output is complete
            session.close()
    if session.samples == 0:
        reason = getattr(follower, "why_nothing", lambda: None)() if follower.path.exists() else None
        what = reason or ("did not appear" if not follower.path.exists() else "gave no sample" + (
            "" if follower.started else " (not even the rows its header and units are decided on)"))
        raise UsageError(f"--follow {follower.path}: the log {what}" + (
            "" if reason else f" within {idle_exit_s:g} s of --idle-exit") + "; nothing was monitored")


def _say(follower) -> None:
    for note in follower.notes:
        print(f"note: {note}", file=sys.stderr)
    follower.notes.clear()
