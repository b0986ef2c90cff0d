"""Stance-wrench distribution: which ground forces should the stance feet push with, by a strategy's name or a
blend of them (:func:`distribute`).  The problem and its maths are :mod:`.stance`'s; the exact minimax
:mod:`.minimax`'s; the thermal minimax :mod:`.thermal_minimax`'s; Nair et al.'s own solver :mod:`.nair`'s.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from thermolimb.model import ModelArrays

from .minimax import closest_achievable, minimax, minimax_lex
from .stance import StanceProblem, StanceSolution, vertical_only
from .thermal_minimax import thermal_minimax

STRATEGIES = ("vertical_only", "minimax", "minimax_lex", "thermal_aware")  # what distribute() can do


def distribute(
    problem: StanceProblem,
    strategy: str | Mapping[str, float],
    warm: StanceSolution | None = None,
    bank: ModelArrays | None = None,
    temperature_C: np.ndarray | None = None,
    horizon_s: float = 20.0,
    smoothing_1_N2: float = 0.0,
    solver: str = "daqp",
    fallback: str | None = None,
) -> StanceSolution:
    """Stance forces by ``strategy`` (one of :data:`STRATEGIES`, or ``{name: weight}`` to blend them: a convex
    combination of balanced distributions is balanced), for the nearest wrench the contacts can supply.

    ``warm``: the previous control step's solution (its forces smooth the
    minimax, its active set starts the solver); ``bank``, ``temperature_C``
    (all 18 joints) and ``horizon_s``: what ``thermal_aware`` predicts with.
    Every program is solved by ``solver``, and by ``fallback`` only when it is
    named and ``solver`` fails: the solution's ``solver`` and ``fallback_from``
    say what ran.  Each program is solved once per call, also in a blend (the
    closest wrench once; the torque minimax once, shared by ``minimax``,
    ``minimax_lex`` and ``thermal_aware``'s first point).
    """
    weights = (
        {strategy: 1.0} if isinstance(strategy, str) else {k: float(v) for k, v in strategy.items() if v > 0}
    )
    unknown = [k for k in weights if k not in STRATEGIES]
    if unknown or not weights:
        raise ValueError(f"unknown strategy {unknown or strategy!r}; expected one of {', '.join(STRATEGIES)}")
    if "thermal_aware" in weights and (bank is None or temperature_C is None):
        raise ValueError("the thermal_aware strategy needs identified "
                         "models (bank) and the joints' temperatures")
    achievable = (
        problem if set(weights) == {"vertical_only"} else closest_achievable(problem, solver, fallback)
    )
    plain: list[StanceSolution] = []  # the torque minimax of `achievable`, solved at most once

    def torque_minimax() -> StanceSolution:
        if not plain:
            plain.append(minimax(achievable, solver, fallback=fallback))
        return plain[0]

    def one(name: str) -> StanceSolution:
        if name == "vertical_only":
            return vertical_only(problem)
        if name == "minimax":
            if smoothing_1_N2 <= 0:
                return torque_minimax()
            previous = np.zeros((achievable.n, 3))
            if warm is not None:
                last = dict(zip(warm.problem.legs, warm.forces_N))
                previous = np.array([last.get(i, np.zeros(3)) for i in achievable.legs])
            return minimax(achievable, solver, smoothing_1_N2=smoothing_1_N2, previous_N=previous,
                           fallback=fallback)
        if name == "minimax_lex":
            return minimax_lex(achievable, first=torque_minimax())
        joints = np.concatenate([np.arange(3 * i, 3 * i + 3) for i in achievable.legs])
        return thermal_minimax(achievable, bank.subset(joints), np.asarray(temperature_C)[joints], horizon_s,
                               first=torque_minimax(), solver=solver, fallback=fallback)

    parts = [(w, one(name)) for name, w in weights.items()]
    if len(parts) == 1:
        return parts[0][1]
    total = sum(w for w, _ in parts)
    first = parts[0][1]
    return StanceSolution(first.problem, sum(w / total * part.forces_N for w, part in parts), "blend",
                          ", ".join(sorted({part.solver for _, part in parts})),
                          sum(part.solve_time_s for _, part in parts), parts=tuple(part for _, part in parts))
