"""A plant advanced over many control intervals at once, while thermal protection leaves it alone.

:func:`free_block` is :meth:`~thermolimb.plant.ThermalPlant.step` repeated, to rounding, without the
per-interval bookkeeping: where :attr:`~thermolimb.plant.ThermalPlant.steps_in_blocks` (no heat that depends
on the state or on a schedule), held inputs give a fixed linear map, and the network advances in one loop of
matrix products.  :func:`~thermolimb.plant.run.run_profile` uses it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Block:
    """What :func:`free_block` advanced: ``steps`` intervals, and per interval the efforts applied,
    the true winding, the measured and estimated temperatures and the ambient at its start, and the current
    over it."""

    steps: int
    effort: np.ndarray
    true_winding_C: np.ndarray
    measured_C: np.ndarray
    estimated_C: np.ndarray | None
    ambient_C: np.ndarray
    current_A: np.ndarray


def free_block(plant, effort: np.ndarray, velocity: np.ndarray, dt_s: float) -> Block:
    """Advance over the rows of ``effort`` and ``velocity`` (``(k, m)``, each held ``dt_s``) for as long as
    thermal protection would not act, and say how many intervals that was.

    The same intervals as :meth:`ThermalPlant.derate` then :meth:`ThermalPlant.step` each time: the network's
    exact map, the sensors' noise (the same draws), the observer's update; protection is then checked at every
    interval's start as :meth:`ThermalPlant.protection_fraction` would, and the block is cut before the first
    interval it would have derated or capped (its state, the observer's and the unused noise put back).  What
    it saves is the per-interval bookkeeping of a step: the network advances in one loop of matrix products.
    """
    if not plant.steps_in_blocks:
        raise ValueError("free_block needs a plant whose heat does not depend on its state or a schedule")
    effort = np.asarray(effort, float)
    velocity = np.asarray(velocity, float)
    if not (np.all(np.isfinite(effort)) and np.all(np.isfinite(velocity))):
        raise ValueError("free_block needs finite efforts and velocities; step() faults an actuator given a "
                         "command that is not a finite number")
    k = effort.shape[0]
    times = plant.time_s + dt_s * np.arange(k + 1)
    ambient = np.array([plant.ambient_at(t) for t in times])
    before = plant.current_A, plant._applied_fraction
    plant._applied_fraction = np.ones(plant.n)
    applied = plant.scale_efforts(effort, np.ones(plant.n))
    constant, _ = plant.heat_affine(applied, velocity)
    current, plant.current_A = plant.current_A, before[0]
    Phi, Gamma = plant._discretisation(dt_s)
    inputs = np.concatenate([constant, ambient[:-1, None]], axis=1) @ Gamma.T
    states = np.empty((k + 1, plant._n_states))
    states[0] = x = plant._x
    for i in range(k):
        x = Phi @ x + inputs[i]
        states[i + 1] = x
    sensed = np.concatenate([plant.layout.sensor, plant.layout.driver[plant._has_driver]])
    noise = (
        plant.sensors.standard_normal(k * len(sensed)).reshape(k, -1) if plant.effects.sensor_noise else None
    )
    readings = plant.read(states[1:, sensed], noise)
    measured = np.vstack([plant._measured_core, readings[:, : plant.n]])
    if plant.observer is not None:
        est, cov, Phis = plant.observer.run(current, readings[:, : plant.n], ambient, dt_s, velocity)
        std = np.sqrt(np.maximum(cov[:k, :, 0, 0], 0.0))
        commanded = np.sqrt(plant._current_sq(effort, np.abs(velocity), 1.0))

        def cap(below):
            return plant.observer.fraction_cap(est[:k], Phis, commanded, below, ambient[:k], dt_s)

        fraction = plant.protection.share(est[:k, :, 0] + plant.protection.sigmas * std,
                                          plant.winding_limits_C, std, cap)
    else:
        fraction = plant.protection.share(measured[:k], plant.winding_limits_C)
    acting = np.flatnonzero(np.any(fraction < 1.0, axis=1))
    done = int(acting[0]) if acting.size else k
    plant._x = states[done].copy()
    plant.time_s = float(times[done])
    plant._measured_core = measured[done].copy()
    plant._measured_driver = readings[done - 1, plant.n :].copy() if done else plant._measured_driver
    if noise is not None:
        plant.sensors.put_back(noise[done:])
    if plant.observer is not None:
        plant.observer.set_state(est[done], cov[done])
    if done:
        plant.current_A = current[done - 1].copy()
    else:
        plant._applied_fraction = before[1]
    return Block(done, applied[:done], states[:done][:, plant.layout.winding], measured[:done],
                 est[:done, :, 0] if plant.observer is not None else None, ambient[:done], current[:done])
