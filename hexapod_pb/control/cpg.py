"""Central pattern generator: coupled Hopf oscillators producing the alternating tripod.

Each leg has an oscillator ``z_i = x_i + i y_i``:

    dz_i/dt = (alpha (radius_sq - |z_i|^2) + i omega) z_i + lam * sum_j K_ij z_j

``alpha`` forces the state onto the limit cycle of radius ``sqrt(radius_sq)``,
``omega`` sets the frequency, and the coupling matrix ``K`` (+1 within a
tripod, -1 across) with strength ``lam`` pulls legs of one tripod into
phase and the two tripods into anti-phase, from any start.

Phase ``phi = atan2(y, x)``: the leg swings while ``sin(phi)`` is above a
threshold set by the duty factor, and stands otherwise.  Foot targets in the
body frame: the nominal foot, shifted along the walking direction by
``-step/2 cos(phi)`` and lifted by ``height * (sin(phi) - thr) / (1 - thr)``
while swinging.  Everything here is a pure function of (state, parameters).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..constants import LEGS, TRIPODS


def tripod_coupling() -> np.ndarray:
    """``K`` (6 x 6): +1 between legs of the same tripod, -1 between tripods, 0 on the diagonal."""
    group = np.array([0 if leg in TRIPODS[0] else 1 for leg in LEGS])
    K = np.where(group[:, None] == group[None, :], 1.0, -1.0)
    np.fill_diagonal(K, 0.0)
    return K


@dataclass(frozen=True)
class CPGParams:
    period_s: float = 1.4  # one stride: each tripod swings for about half of it (HEBI: 0.7 s steps)
    radius_sq: float = 1.0  # squared limit-cycle radius (the CPG literature's mu)
    alpha: float = 10.0  # forcing to the limit cycle (1/s)
    coupling: float = 2.0  # lam (1/s)
    duty_factor: float = 0.55  # fraction of the stride a foot is on the ground (> 0.5: both tripods briefly)
    step_length_m: float = 0.08
    step_height_m: float = 0.04  # HEBI's stock gait
    heading_rad: float = 0.0  # walking direction in the body frame

    def __post_init__(self):
        if not (self.period_s > 0 and self.radius_sq > 0 and self.alpha > 0 and self.coupling >= 0):
            raise ValueError("CPG period, radius_sq and alpha must be positive, coupling non-negative")
        if not 0.5 <= self.duty_factor < 1.0:
            raise ValueError(f"duty_factor must be in [0.5, 1), got {self.duty_factor}")

    @property
    def omega_rad_s(self) -> float:
        return 2.0 * np.pi / self.period_s

    @property
    def swing_threshold(self) -> float:
        """``sin(phi)`` above which a leg swings."""
        return float(np.sin(np.pi * (self.duty_factor - 0.5)))

    @property
    def speed_m_s(self) -> float:
        """Body speed if feet do not slip: step length over stance time."""
        return self.step_length_m / (self.duty_factor * self.period_s)


def initial_state(rng: np.random.Generator | None = None, params: CPGParams = CPGParams()) -> np.ndarray:
    """``(6, 2)`` oscillator states: the ideal tripod, or random on the limit cycle when ``rng`` is given."""
    if rng is None:
        phase = np.array([0.0 if leg in TRIPODS[0] else np.pi for leg in LEGS]) + np.pi  # start in stance
    else:
        phase = rng.uniform(0, 2 * np.pi, len(LEGS))
    r = np.sqrt(params.radius_sq)
    return np.column_stack([r * np.cos(phase), r * np.sin(phase)])


def step(
    state: np.ndarray, params: CPGParams, dt_s: float, K: np.ndarray | None = None, substeps: int = 4
) -> np.ndarray:
    """Advance the oscillators by ``dt_s`` (explicit Euler in ``substeps``)."""
    K = tripod_coupling() if K is None else K
    z = state[:, 0] + 1j * state[:, 1]
    h = dt_s / substeps
    for _ in range(substeps):
        dz = (
            params.alpha * (params.radius_sq - np.abs(z) ** 2) + 1j * params.omega_rad_s
        ) * z + params.coupling * (K @ z)
        z = z + h * dz
    return np.column_stack([z.real, z.imag])


def phases(state: np.ndarray) -> np.ndarray:
    return np.arctan2(state[:, 1], state[:, 0])


def stance(state: np.ndarray, params: CPGParams) -> np.ndarray:
    """Boolean (6,): which feet are planned on the ground."""
    return np.sin(phases(state)) <= params.swing_threshold


def foot_targets(state: np.ndarray, params: CPGParams, nominal: np.ndarray) -> np.ndarray:
    """Body-frame foot targets (6 x 3) from the oscillator states and the nominal stance."""
    phi = phases(state)
    direction = np.array([np.cos(params.heading_rad), np.sin(params.heading_rad), 0.0])
    shift = -0.5 * params.step_length_m * np.cos(phi)
    thr = params.swing_threshold
    lift = params.step_height_m * np.clip((np.sin(phi) - thr) / (1.0 - thr), 0.0, 1.0)
    return nominal + shift[:, None] * direction + lift[:, None] * np.array([0.0, 0.0, 1.0])


def phase_locking_error(state: np.ndarray) -> float:
    """Largest deviation (rad) from the ideal tripod: same phase within, pi across."""
    phi = phases(state)
    ref = phi[LEGS.index(TRIPODS[0][0])]
    errs = []
    for i, leg in enumerate(LEGS):
        target = 0.0 if leg in TRIPODS[0] else np.pi
        d = np.angle(np.exp(1j * (phi[i] - ref - target)))
        errs.append(abs(d))
    return float(max(errs))
