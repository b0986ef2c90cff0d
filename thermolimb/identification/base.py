"""The estimator contract shared by every identification method (scikit-learn style).

``fit(data)`` returns ``self``; learned values end in ``_`` (``model_``,
``params_``, ``stderr_``, ``covariance_``); ``simulate`` runs the fitted model
free from a measured start; ``predict`` is the one-step-ahead prediction from
the previous measured temperature; ``score`` is the free-run fit percentage.
"""

from __future__ import annotations

import inspect
from typing import Sequence

import numpy as np

from ..logs import MIN_SAMPLES, ActuatorSeries, LogError
from ..model.model import ThermalModel, model_parameters
from ..model.terms import DEFAULT_MODEL, TERMS, parse_model
from ..util.errors import IdentifiabilityError, ModelSpecError
from ..util.memory import release_freed
from .metrics import fit_percent

MIN_FIT_SAMPLES = MIN_SAMPLES // 2  # the fewest a training part may hold (ActuatorSeries.split_index)


class ThermalEstimator:
    """Base class: subclasses implement ``_fit(series, terms) -> (values, covariance)``."""

    method: str = ""
    constrained: bool = True  # whether estimates stay within the parameters' bounds (output error's do)

    def __init__(self, model: str | Sequence[str] = DEFAULT_MODEL):
        self.model = model

    # scikit-learn's parameter protocol, from the __init__ signature
    def get_params(self, deep: bool = True) -> dict:
        names = [p for p in inspect.signature(type(self).__init__).parameters if p != "self"]
        return {n: getattr(self, n) for n in names}

    def set_params(self, **params) -> "ThermalEstimator":
        valid = self.get_params()
        for key, value in params.items():
            if key not in valid:
                raise ValueError(f"{type(self).__name__} has no parameter {key!r}; it has {', '.join(valid)}")
            setattr(self, key, value)
        return self

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.get_params().items())
        return f"{type(self).__name__}({args})"

    # ----------------------------------------------------------------- fitting
    def fit(self, data: ActuatorSeries | Sequence[ActuatorSeries]) -> "ThermalEstimator":
        """Identify the model from one series or several series of the same actuator (jointly)."""
        series = [data] if isinstance(data, ActuatorSeries) else list(data)
        if not series:
            raise ValueError("fit needs at least one series")
        short = [s for s in series if s.n < MIN_FIT_SAMPLES]
        if short:
            raise LogError(f"actuator {short[0].actuator}{short[0].run_label} "
                           f"has {short[0].n} sample(s); fitting "
                           f"needs at least {MIN_FIT_SAMPLES} per series")
        terms = parse_model(self.model)
        for ser in series:
            for name in terms:
                for column in TERMS[name].columns:
                    try:
                        ser.signals.channel(column)
                    except KeyError:
                        raise ModelSpecError(
                            f"model term '{name}' needs the log column '{column}', which actuator "
                            f"{ser.actuator}'s log does not have"
                        ) from None
        values, covariance = self._fit(series, terms)
        release_freed()  # the simulations' per-sample arrays, before the caller's next ones
        names = [p.name for p in model_parameters(terms)]
        if not values[0] > 0:
            raise IdentifiabilityError(
                f"{self.method} gives RC_s = {values[0]:.3g} s for "
                f"actuator {series[0].actuator}: this log does not "
                f"determine the time constant of model {','.join(terms)}; a log needs "
                f"{model_parameters(terms)[0].excitation}",
                parameter="RC_s",
            )
        # an unconstrained regression's estimate stands as it came out; the flags judge it
        self.model_ = ThermalModel(terms, dict(zip(names, values)), bounded=self.constrained)
        self.params_ = dict(self.model_.params)
        self.covariance_ = covariance
        self.stderr_ = dict(zip(names, np.sqrt(np.clip(np.diag(covariance), 0.0, None))))
        self.n_samples_ = int(sum(s.n for s in series))
        return self

    def _fit(self, series: list[ActuatorSeries], terms: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError  # abstract

    def _check_fitted(self):
        if not hasattr(self, "model_"):
            raise RuntimeError(f"{type(self).__name__} is not fitted yet; call fit(series) first")

    # ------------------------------------------------------------------ using
    def simulate(self, series: ActuatorSeries, initial_temperature_C: float | None = None,
                 method: str = "exact", initial_rate_K_per_s: float | None = None) -> np.ndarray:
        """Free-run temperatures from the inputs alone, starting at the first measured temperature.

        The starting trend (for hidden states) is the measured slope over the
        first minute unless given.
        """
        self._check_fitted()
        return self.model_.free_run(series, initial_rate_K_per_s, method, initial_temperature_C)

    def predict(self, series: ActuatorSeries) -> np.ndarray:
        """One-step-ahead predictions from the previous measured temperature."""
        self._check_fitted()
        return self.model_.one_step(series.signals, series.temperature_C)

    def score(self, series: ActuatorSeries) -> float:
        """Free-run fit percentage, 100 (1 - ||y - y_sim|| / ||y - mean y||)."""
        return fit_percent(series.temperature_C, self.simulate(series))
