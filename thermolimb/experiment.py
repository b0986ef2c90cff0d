"""The next experiment: a test designed to answer what a log could not (``thermolimb plan``).

A log may leave a parameter unsized (a slow mass's time constant on a log shorter than it, a tempco
without hot and cool phases at one effort).  :func:`design` writes the test that sizes it, within the
actuator's limits:

* **the profile family**: piecewise-constant holds of effort (and velocity, where the model reads it) on
  the sample grid, each hold at least ``min_hold_s`` long, efforts within ``±max_effort``
  (``0..max_effort`` where the sign does not matter to the model), velocities within ``0..max_velocity``;
* **the criterion**: the standard errors the fit of the test will report for the named parameters, relative to
  their values (a sum over them, in logs).  They come from the Fisher information of the free run,
  ``F = S^T S / sigma^2``, with ``S`` the sensitivities of the simulated readings to every parameter (forward
  differences) over the samples a fit compares (the first ``split`` of the test, as ``fit`` and ``diagnose``
  split a run) and ``sigma`` the readings' noise: the covariance a fit reports is ``F^-1`` when the model's
  structure is right and the residual is the sensor's noise (Jorgensen et al.'s Eq. 5 with the named terms);
* **the constraint**: the winding stays ``margin_K`` below ``limit_C`` at the upper end of the model's
  own 90 % forecast interval (:func:`thermolimb.forecast.forecast`: the parameters' spread and the model's
  held-out error) at every instant; during the search a cheaper bound (the prediction, plus the model's
  held-out error quantile and the linearised parameter spread) is held, and the design found is checked
  with the forecast itself and scaled down until it holds;
* **the search**: bounded quasi-Newton (L-BFGS-B) from a few seeded starts, one of them a square wave.

What it assumes: the model's structure is right up to the open question, and the parameters are near the
values the model file holds (a local design, as every Fisher design is).  On a real robot, run the plan with
the robot's own thermal protection on.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize

from .forecast import LEVEL, forecast, model_error_K
from .model.saved import SavedModel
from .model.signals import Signals
from .model.terms import TERMS
from .util.errors import ThermolimbError

SPLIT = 0.7  # the share of the test a fit compares (fit's and diagnose's default --split)
MAX_HOLDS = 12  # holds in a plan at most (the search costs a free run per hold and parameter)
STARTS = 3  # the search's starts
STEP = 1e-4  # forward-difference step, relative to a parameter's size
COARSE_PER_HOLD = 12  # samples a hold on the search's grid
SUPPORTED = ("effort", "velocity", "ambient")  # the log columns a plan gives


@dataclass(frozen=True)
class Limits:
    """What the test may do: a winding limit (degC) and the margin kept below it at the forecast band's upper
    end (K), the largest effort (the model's effort unit) and velocity (rad/s), its length and sample period
    (s), the shortest hold (s; default ten samples), the start and the ambient (degC)."""

    limit_C: float
    max_effort: float
    duration_s: float
    start_C: float
    dt_s: float = 1.0
    margin_K: float = 5.0
    max_velocity: float = 0.0
    min_hold_s: float | None = None
    ambient_C: float = 25.0

    @property
    def shortest_hold_s(self) -> float:
        return self.min_hold_s if self.min_hold_s is not None else 10.0 * self.dt_s


@dataclass(frozen=True)
class Plan:
    """A designed test and what it promises before it is run."""

    actuator: str
    identify: tuple[str, ...]
    time_s: np.ndarray
    effort: np.ndarray
    velocity: np.ndarray | None
    hold_s: float
    predicted_C: np.ndarray  # the model's free run under the plan (degC)
    high_C: np.ndarray  # the upper end of its 90 % forecast interval
    limits: Limits
    noise_K: float  # the readings' noise as the fit will weigh it (inflated by their serial correlation)
    lag1: float  # the serial correlation assumed (the model file's held-out residual's)
    stderr_now: dict[str, float]  # each named parameter's standard error in the model file
    stderr_after: dict[str, float]  # ... and what the test's fit will report, by the criterion
    values: dict[str, float]
    units: dict[str, str]
    effort_unit: str = ""  # the model's effort unit (its log's)
    notes: tuple[str, ...] = field(default=())
    separate: tuple[str, str] | None = None  # the question of --separate: the term held and its rival
    separation_K: float | None = None  # rms of the rival's difference the model's parameters cannot absorb
    separation_sigma: float | None = None  # ... its norm over the fitted samples against the readings' noise

    @property
    def hottest_C(self) -> float:
        return float(np.max(self.high_C))

    def table(self):
        """The plan as a canonical log's inputs: ``time, actuator, effort[, velocity]`` (a robot's controller,
        or ``thermolimb simulate --profile plan.csv``, follows it)."""
        from .util.lazy import pandas as pd

        columns = {"time": self.time_s, "actuator": self.actuator, "effort": self.effort}
        if self.velocity is not None:
            columns["velocity"] = self.velocity
        return pd.DataFrame(columns)

    def lines(self) -> list[str]:
        """What the plan expects, said before it is run."""
        lim = self.limits
        out = [
            f"{self.actuator}: a {lim.duration_s:g} s test of holds of {self.hold_s:g} s, effort within "
            f"±{lim.max_effort:g}"
            + (f", velocity up to {lim.max_velocity:g} rad/s" if self.velocity is not None else "")
        ]
        for name in self.identify:
            now, after = self.stderr_now.get(name), self.stderr_after[name]
            unit = f" {self.units[name]}" if self.units.get(name) not in (None, "", "1") else ""
            was = f" (now ± {now:.3g}{unit})" if now is not None and np.isfinite(now) else ""
            out.append(f"  {name} = {self.values[name]:.4g}{unit}: expected ± {after:.3g}{unit} after the "
                       f"test{was}")
        if self.separate is not None:
            held, other = self.separate
            out.append(f"  {held} against {other}: the readings differ by {self.separation_K:.3g} K rms "
                       f"beyond what the model's parameters absorb, {self.separation_sigma:.3g} times the "
                       f"readings' noise over the fitted samples ({other} at its typical size: a guess)")
        out.append(f"  hottest winding: {self.hottest_C:.1f} degC at the upper end of the model's 90 % "
                   f"interval, kept {lim.margin_K:g} K under the {lim.limit_C:g} degC limit")
        out.append(f"  assumes: the model's structure right up to the question; readings whose noise weighs "
                   f"{self.noise_K:.3g} K in the fit (lag-1 correlation {self.lag1:.2f}, as the model's "
                   f"held-out residual's); fitted on the first {100 * SPLIT:.0f} % of the test")
        return out + [f"  note: {n}" for n in self.notes]

    def to_json(self) -> dict:
        return {
            "actuator": self.actuator,
            "identify": list(self.identify),
            "duration_s": self.limits.duration_s,
            "dt_s": self.limits.dt_s,
            "hold_s": self.hold_s,
            "limit_C": self.limits.limit_C,
            "margin_K": self.limits.margin_K,
            "max_effort": self.limits.max_effort,
            "max_velocity": self.limits.max_velocity,
            "hottest_C": self.hottest_C,
            "noise_K": self.noise_K,
            "lag1": self.lag1,
            "effort_unit": self.effort_unit,
            "values": self.values,
            "units": self.units,
            "stderr_now": self.stderr_now,
            "stderr_after": self.stderr_after,
            "notes": list(self.notes),
            "separate": None if self.separate is None else list(self.separate),
            "separation_K": self.separation_K,
            "separation_sigma": self.separation_sigma,
        }


def design(saved: SavedModel, identify, limits: Limits, noise_K: float | None = None, seed: int = 0) -> Plan:
    """The test that best sizes the parameters ``identify`` within ``limits`` (module docstring).

    Parameters
    ----------
    saved
        The actuator's model file entry: its structure, values, covariance and held-out error.
    identify
        Names of the model's parameters the test should size.
    limits
        What the test may do (:class:`Limits`).
    noise_K
        The readings' noise (K); default the model's held-out RMSE (an upper bound where the model misses
        physics: the promise is then conservative), said in the plan's notes.
    seed
        Seeds the search's random starts.

    Returns
    -------
    Plan
        The profile, its predicted and upper-band temperatures, and the standard errors it promises.
    """
    names = [p.name for p in saved.model.parameters]
    identify = tuple(identify)
    missing = [n for n in identify if n not in names]
    if not identify or missing:
        raise ThermolimbError(
            f"the model ({','.join(saved.model.terms)}) has no parameter {missing[0] if missing else ''!r}"
            f"; its parameters are {', '.join(names)} (add the term that has it: --model, or a "
            f"model file diagnose --save wrote)"
        )
    problem, notes = posed(saved, identify, limits, noise_K)
    return planned(problem, problem.coarse().search(np.random.default_rng(seed)), notes)


def _signed(model) -> bool:
    """Whether the model's heat depends on the effort's sign (an effort bias): its terms' contributions at
    efforts 1 and -1, at rest in still air, differ."""
    s = Signals(np.array([0.0, 1.0]), np.array([1.0, -1.0]), np.zeros(2), ambient_C=np.full(2, 25.0))
    for name in model.terms:
        contribution = TERMS[name]().contribution(model.params, s)
        rise, gain = (np.broadcast_to(np.asarray(x, float), (2,)) for x in contribution)
        if rise[0] != rise[1] or gain[0] != gain[1]:
            return True
    return False


def posed(saved: SavedModel, identify: tuple[str, ...], limits: Limits,
          noise_K: float | None) -> tuple["DesignProblem", list[str]]:
    """The design problem on the test's grid of holds, and the notes on what it assumes: the limits checked,
    the readings' noise (inflated by the serial correlation the model's held-out residual shows)."""
    model = saved.model
    unread = [c for c in model.columns if c not in SUPPORTED]
    if unread:
        raise ThermolimbError(
            f"the model reads the log column {unread[0]!r}, which a planned test does not set (it "
            f"sets effort and velocity, in the air of --ambient-C)"
        )
    _check(limits)
    notes = []
    if noise_K is None:
        noise_K = float(saved.validation.get("rmse_K", 0.1)) if saved.validation else 0.1
        notes.append(f"the readings' noise taken as the model's held-out RMSE, {noise_K:.3g} K (give "
                     f"--noise-K: the sensor's floor diagnose reports)")
    # the fit inflates its variance by the residual's serial correlation (identification.metrics): a right
    # structure's residual is the sensor's, whose lag-1 correlation the model file's held-out residual gives
    lag1 = float(np.clip(saved.residual.lag1, 0.0, 0.999)) if saved.residual is not None else 0.0
    noise_K = float(noise_K) * np.sqrt((1.0 + lag1) / (1.0 - lag1))
    t = np.arange(0.0, limits.duration_s + 0.5 * limits.dt_s, limits.dt_s)
    holds = int(min(MAX_HOLDS, max(2, limits.duration_s // limits.shortest_hold_s)))
    edges = np.minimum((np.arange(t.size) * holds) // t.size, holds - 1)
    signed = _signed(model)
    moves = "velocity" in model.columns and limits.max_velocity > 0
    return DesignProblem(saved, t, edges, holds, limits, noise_K, identify, signed, moves, lag1=lag1), notes


def planned(problem: "DesignProblem", best: np.ndarray, notes: list[str], **promise) -> Plan:
    """The plan of the search's ``best`` hold levels, scaled down until the forecast band keeps under the
    limit less its margin, with the standard errors its fit will report (``promise``: a question's own
    fields)."""
    saved, limits, identify = problem.saved, problem.limits, problem.identify
    names = [p.name for p in saved.model.parameters]
    x, band = problem.checked(best)
    effort, velocity = problem.inputs(x)
    cov = problem.covariance(x)
    after = {n: float(np.sqrt(cov[names.index(n), names.index(n)])) for n in identify}
    stderr = dict(saved.stderr)
    return Plan(saved.actuator, identify, problem.t, effort, velocity if problem.moves else None,
                float(limits.duration_s / problem.holds), band.predicted_C, band.high_C, limits,
                float(problem.noise), problem.lag1, {n: float(stderr.get(n, np.nan)) for n in identify},
                after, {n: float(saved.model.params[n]) for n in identify},
                {n: saved.units.get(n, "") for n in identify}, dict(saved.channel_units).get("effort", ""),
                tuple(notes), **promise)


def _inverse(information: np.ndarray) -> np.ndarray:
    """The covariance of an information matrix, a direction it holds no information on given a huge variance
    (a pseudo-inverse would give it none, and a search would seek a test that tells nothing): the inverse of
    its unit-diagonal form with a ridge of 1e-12, as :func:`~thermolimb.identification.metrics.scaled_inverse`
    scales it, so that parameters whose units differ by decades keep their covariance."""
    d = np.sqrt(np.clip(np.diag(information), 0.0, None))
    d = np.where(d > 0, d, 1e-100)
    unit = information / np.outer(d, d) + 1e-12 * np.eye(len(d))
    return np.linalg.inv(unit) / np.outer(d, d)


def _check(limits: Limits) -> None:
    if limits.limit_C - limits.margin_K <= limits.start_C:
        raise ThermolimbError(
            f"the winding starts at {limits.start_C:g} degC, at or above the limit less its margin "
            f"({limits.limit_C:g} - {limits.margin_K:g} degC): no test can keep under it; expected "
            f"a limit above the start"
        )
    if not limits.max_effort > 0:
        raise ThermolimbError(f"--max-effort must be above 0, got {limits.max_effort:g}")
    if limits.duration_s < 2 * limits.shortest_hold_s:
        raise ThermolimbError(
            f"--duration {limits.duration_s:g} s is too short for two holds of "
            f"{limits.shortest_hold_s:g} s (the shortest hold: ten samples of --dt, or "
            f"--min-hold); expected a longer test"
        )


class DesignProblem:
    """The search's state: the grid, the holds, and the cost of a vector of hold levels."""

    def __init__(self, saved, t, edges, holds, limits, noise_K, identify, signed, moves, weight=1.0,
                 lag1=0.0):
        self.saved, self.t, self.edges, self.holds, self.limits = saved, t, edges, holds, limits
        self.noise, self.identify, self.signed, self.moves, self.lag1 = noise_K, identify, signed, moves, lag1
        self.names = [p.name for p in saved.model.parameters]
        self.fit = t <= t[-1] * SPLIT
        self.margin = model_error_K(saved, LEVEL)
        self.ceiling = limits.limit_C - limits.margin_K
        self.weight = weight  # samples of the test each sample here stands for (the search's coarser grid)

    def coarse(self, per_hold: int = COARSE_PER_HOLD) -> "DesignProblem":
        """The same problem on a grid of ``per_hold`` samples a hold (the holds' edges among them): a free run
        under held inputs is exact at any instants, and the information scales with the samples it sums."""
        if self.t.size <= per_hold * self.holds:
            return self
        t = np.linspace(0.0, self.t[-1], per_hold * self.holds + 1)
        edges = np.minimum((t / self.t[-1] * self.holds).astype(int), self.holds - 1)
        return DesignProblem(self.saved, t, edges, self.holds, self.limits, self.noise, self.identify,
                             self.signed, self.moves, weight=self.t.size / t.size, lag1=self.lag1)

    def inputs(self, x):
        levels = x[: self.holds] * self.limits.max_effort
        effort = levels[self.edges]
        velocity = (
            (x[self.holds :][self.edges] * self.limits.max_velocity) if self.moves else np.zeros_like(effort)
        )
        return effort, velocity

    def signals(self, x) -> Signals:
        effort, velocity = self.inputs(x)
        ambient = np.full(self.t.size, self.limits.ambient_C)
        return Signals(self.t, effort, velocity, ambient_C=ambient)

    def sensitivities(self, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The free run, its sensitivities to every parameter (forward differences), and its responses to
        each hidden state's start (a slow mass, the winding behind a lagging sensor): a fit places them per
        run."""
        model, start = self.saved.model, self.limits.start_C
        s = self.signals(x)
        base = model.simulate(s, start)
        columns = []
        for p in model.parameters:
            value = model.params[p.name]
            h = STEP * max(abs(value), abs(p.typical), 1e-9)
            h = -h if value + h > p.upper else h
            columns.append(
                (model.with_params({**model.params, p.name: value + h}).simulate(s, start) - base) / h
            )
        hidden = [model.simulate(s, start, offsets={name: 1.0}) - base for name in model.hidden_states]
        return base, np.column_stack(columns), np.column_stack(hidden) if hidden else np.empty((base.size, 0))

    def information(self, S: np.ndarray, H: np.ndarray) -> np.ndarray:
        """``S^T S`` over the fitted samples, the hidden states' starts profiled out (as the fit places them
        by least squares at every step, its Jacobian is the part of ``S`` they cannot produce)."""
        fitted = S[self.fit]
        if H.shape[1]:
            starts = H[self.fit]
            fitted = fitted - starts @ np.linalg.lstsq(starts, fitted, rcond=None)[0]
        return self.weight * (fitted.T @ fitted)

    def covariance(self, x) -> np.ndarray:
        _, S, H = self.sensitivities(x)
        return self.noise**2 * _inverse(self.information(S, H))

    def cost(self, x) -> float:
        base, S, H = self.sensitivities(x)
        cov = self.noise**2 * _inverse(self.information(S, H))
        rel = [
            cov[self.names.index(n), self.names.index(n)] / max(self.saved.model.params[n] ** 2, 1e-300)
            for n in self.identify
        ]
        spread = np.sqrt(np.einsum("ij,jk,ik->i", S, np.asarray(self.saved.covariance, float), S).clip(0.0))
        over = np.max(base + self.margin + 1.645 * spread) - self.ceiling
        return float(np.sum(np.log(np.maximum(rel, 1e-300)))) + (1e3 * over**2 if over > 0 else 0.0)

    def search(self, rng: np.random.Generator) -> np.ndarray:
        low = -1.0 if self.signed else 0.0
        bounds = [(low, 1.0)] * self.holds + ([(0.0, 1.0)] * self.holds if self.moves else [])
        square = np.where(np.arange(self.holds) % 2 == 0, 1.0, 0.0)
        starts = [np.concatenate([square, square if self.moves else []])]
        starts += [rng.uniform([b[0] for b in bounds], [b[1] for b in bounds]) for _ in range(STARTS - 1)]
        best, best_cost = starts[0], np.inf
        for start in starts:
            result = minimize(self.cost, start, method="L-BFGS-B", bounds=bounds,
                              options={"maxiter": 25, "eps": 1e-3})
            if result.fun < best_cost:
                best, best_cost = result.x, result.fun
        return best

    def checked(self, x):
        """``x`` scaled down (effort and velocity alike) until the forecast band's upper end stays under the
        ceiling at every instant, and that forecast."""
        for _ in range(60):
            band = forecast(self.saved, self.signals(x), self.limits.start_C, self.limits.limit_C)
            if np.max(band.high_C) <= self.ceiling:
                return x, band
            x = x * 0.95
        raise ThermolimbError(
            f"no test within --max-effort keeps the winding's forecast under "
            f"{self.ceiling:g} degC; expected a lower start or a higher limit"
        )
