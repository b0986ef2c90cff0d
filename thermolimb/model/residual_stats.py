"""The held-out free-run residual of a fitted model, summarised as a forecast's interval needs it
(:class:`ResidualStats`, stored in the model file, :mod:`.saved`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

RESIDUAL_QUANTILES = (0.5, 0.8, 0.9, 0.95, 0.99)


@dataclass(frozen=True)
class ResidualStats:
    """The held-out free-run residual (measured − simulated, K) of a fitted model: what an interval needs."""

    samples: int
    span_s: float
    mean_K: float
    rmse_K: float
    abs_quantiles_K: Mapping[str, float]  # "0.9": the 90 % quantile of |residual|
    lag1: float  # lag-1 autocorrelation of the residual
    rise_K: float  # the held-out free run's root-mean-square rise above the model's offset
    # how far a forecast started from a reading is off after each lead (s): per level, a quantile of |error|
    # (K)
    leads_s: tuple[float, ...] = ()
    lead_quantiles_K: Mapping[str, tuple[float, ...]] = field(default_factory=dict)

    @classmethod
    def of(cls, residual_K: np.ndarray, span_s: float, rise_K: float) -> "ResidualStats":
        r = np.asarray(residual_K, float)
        r = r[np.isfinite(r)]
        if r.size < 2:
            raise ValueError(f"residual statistics need at least 2 held-out samples, got {r.size}")
        centred = r - r.mean()
        denom = float(np.dot(centred, centred))
        lag1 = float(np.dot(centred[1:], centred[:-1]) / denom) if denom > 0 else 0.0
        quantiles = np.quantile(np.abs(r), RESIDUAL_QUANTILES)
        return cls(int(r.size), float(span_s), float(r.mean()), float(np.sqrt(np.mean(r * r))),
                   {f"{q:g}": float(v) for q, v in zip(RESIDUAL_QUANTILES, quantiles)}, lag1, float(rise_K))

    def abs_quantile_K(self, level: float) -> float:
        """The ``level`` quantile of |residual|, interpolated between the stored ones (K)."""
        levels = np.array(RESIDUAL_QUANTILES)
        values = np.array([self.abs_quantiles_K[f"{q:g}"] for q in RESIDUAL_QUANTILES])
        return float(np.interp(level, levels, values))

    def lead_error_K(self, level: float, lead_s: np.ndarray) -> np.ndarray | None:
        """The ``level`` quantile of a forecast's error after each of ``lead_s`` seconds from a reading (K),
        from the stored profile (rising from zero at lead 0, held beyond the longest lead seen); ``None``
        without one."""
        if not self.leads_s:
            return None
        levels = np.array(RESIDUAL_QUANTILES)
        table = np.array([self.lead_quantiles_K[f"{q:g}"] for q in RESIDUAL_QUANTILES])  # levels x leads
        at_level = np.array([np.interp(level, levels, table[:, k]) for k in range(table.shape[1])])
        return np.interp(np.asarray(lead_s, float), np.r_[0.0, self.leads_s], np.r_[0.0, at_level])

    def to_json(self) -> dict:
        out = {"samples": self.samples, "span_s": self.span_s, "mean_K": self.mean_K, "rmse_K": self.rmse_K,
               "abs_quantiles_K": dict(self.abs_quantiles_K), "lag1": self.lag1, "rise_K": self.rise_K}
        if self.leads_s:
            out.update(leads_s=list(self.leads_s), lead_quantiles_K={k: list(v) for k, v in
                                                                      self.lead_quantiles_K.items()})
        return out
