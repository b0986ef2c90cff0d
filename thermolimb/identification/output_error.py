"""Output-error identification: minimise the free-run simulation error.

The regression methods fit the *equation*; what a controller needs is the
*simulation* (temperature predicted from effort alone, minutes ahead).  This
estimator starts from least squares and refines every parameter by
``scipy.optimize.least_squares`` (trust-region reflective, within each
parameter's bounds) on the residual ``simulate(inputs) - measured`` of every
series, each simulated from its own first measured temperature.

A long log is compared at every ``k``-th sample (``stride_``) and simulated on
blocks of ``k`` samples while its time constants allow (``blocks_``, see
:mod:`~thermolimb.identification.thinning`).
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from ..model.guard import instance
from ..model.model import ThermalModel, hidden_states, model_parameters
from ..model.terms import DEFAULT_MODEL, TERMS
from ..util.errors import IdentifiabilityError
from .base import ThermalEstimator
from .bounds import fit_bounds
from .least_squares import LeastSquares
from .metrics import ar1_variance_factor, scaled_inverse
from .regression import collinear_partners, independent_fractions
from .thinning import blocks_allowed, fit_rows, fit_stride, on_blocks

# Output error refuses only near-exact degeneracy; a poorly determined parameter shows in its standard error.
DEGENERATE_FRACTION = 1e-5


class FreeRunLeastSquares(ThermalEstimator):
    """Free-run (simulation) error minimisation, started from least squares.

    Parameters
    ----------
    model
        Terms of the model.
    initial
        Starting values by parameter name; missing ones come from
        :class:`LeastSquares` on the linear terms, then from each parameter's
        ``typical`` value.
    cutoff_hz
        Filter of the least-squares start.
    max_nfev
        Limit on evaluations per parameter (scipy's ``max_nfev`` is this times
        the number of parameters; scipy does not count the simulations of its
        finite-difference Jacobians, one per parameter and iteration).
    max_iterations
        Instead of ``max_nfev``: at most this many evaluations in all, each
        trust-region iteration one evaluation and one Jacobian (a short fit that
        screens starting points).
    fixed
        Values held, not fitted (an offset tied to the logged ambient when the
        log cannot identify it); their standard error is 0.

    A model with hidden states (a slow mass, the winding behind a lagging
    sensor) has their starts placed in each run where its readings put them,
    not tied to its first reading (``offsets_``, K per run and state): the
    output is affine in them, so they are fitted by least squares inside
    every evaluation (variable projection), at one more free run per state.
    """

    method = "output_error"

    def __init__(
        self,
        model=DEFAULT_MODEL,
        initial: Mapping[str, float] | None = None,
        cutoff_hz: float | None = 0.015,
        max_nfev: int = 30,
        fixed: Mapping[str, float] | None = None,
        max_iterations: int | None = None,
        max_samples: int | None = None,
    ):
        super().__init__(model)
        self.initial = initial
        self.cutoff_hz = cutoff_hz
        self.max_nfev = max_nfev
        self.fixed = fixed
        self.max_iterations = max_iterations
        # compared per evaluation (None: thinning's); fewer for a fit ranking starts
        self.max_samples = max_samples

    def _start(self, series, terms, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
        params = model_parameters(terms)
        start = {p.name: p.typical for p in params}
        given = {**(self.initial or {}), **(self.fixed or {})}
        if any(p.name not in given for p in params):
            first = series[0]
            linear = tuple(
                n for n in terms if instance(n).features(first.signals, first.temperature_C) is not None
            )
            if any(TERMS[n].is_heat_source for n in linear):
                try:
                    start.update(LeastSquares(model=linear, cutoff_hz=self.cutoff_hz).fit(series).params_)
                except IdentifiabilityError as exc:
                    if len(linear) == len(terms) and exc.parameter != "RC_s" and not self.fixed:
                        # a regressor the data cannot separate: the regression's message is the most specific
                        raise
                    # a non-positive RC from the filtered regression, or nonlinear terms that may make the
                    # model identifiable: output error starts from typical values and judges for itself
        if "RC_s" not in given and start["RC_s"] == model_parameters(terms)[0].typical:
            start["RC_s"] = _time_constant_guess(series)
        start.update(given)
        x0 = np.array([start[p.name] for p in params], dtype=float)
        span = np.where(np.isfinite(upper - lower), upper - lower, np.abs(x0) + 1.0)
        return np.clip(x0, lower + 1e-9 * span, upper - 1e-9 * span)

    def _fit(self, series, terms):
        params = model_parameters(terms)
        names = [p.name for p in params]
        lower, upper = fit_bounds(params, terms, series)
        x_all = self._start(series, terms, lower, upper)
        unknown = [k for k in self.fixed or {} if k not in names]
        if unknown:
            raise ValueError(f"fixed names {', '.join(unknown)}, not a parameter of model {','.join(terms)}")
        free = np.array([p.name not in (self.fixed or {}) for p in params])
        params = [p for p, f in zip(params, free) if f]
        self.stride_ = k = fit_stride(series, self.max_samples)
        rows = [fit_rows(s, k) for s in series]
        measured = np.concatenate([s.temperature_C[r] for s, r in zip(series, rows)])
        rates = [s.rate_K_per_s() for s in series]

        hidden = bool(hidden_states(terms))

        def model_at(x):
            return ThermalModel(terms, dict(zip(names, _with(x_all, free, x))))

        def residual_on(shown, shown_rows):
            memos = [{} for _ in shown]

            def residual(x):
                model = model_at(x)
                # each run's free run, its hidden states (a slow mass, the winding behind a lagging sensor)
                # placed where the run's readings put them (variable projection: they are linear in the
                # output)
                runs = [model.place_hidden(s, r, rate, memo=m)[0] if hidden else model.free_run(s, rate)
                        for s, rate, r, m in zip(shown, rates, shown_rows, memos)]
                return np.concatenate([run[r] for run, r in zip(runs, shown_rows)]) - measured
            return residual

        from scipy.optimize import least_squares  # scipy.optimize takes ~0.4 s to import: only when fitting

        x0 = x_all[free]
        scale = np.array([max(abs(v), abs(p.typical) * 1e-3, 1e-9) for v, p in zip(x0, params)])
        budget = self.max_iterations or self.max_nfev * len(params)
        # a long log is simulated on blocks of k samples, and again at its full rate if the fit ends where its
        # time constants are not long against them (thinning.BLOCK_TIME_CONSTANTS); a short fit, which only
        # ranks starting points, keeps its blocks
        blocks = k > 1
        shown, shown_rows = (
            zip(*(on_blocks(s, r, k) for s, r in zip(series, rows))) if blocks else (series, rows)
        )
        result = least_squares(residual_on(shown, shown_rows), x0, bounds=(lower[free], upper[free]),
                               x_scale=scale, method="trf", max_nfev=budget)
        if blocks and not self.max_iterations and not blocks_allowed(model_at(result.x), shown):
            blocks = False
            result = least_squares(residual_on(series, rows), result.x, bounds=(lower[free], upper[free]),
                                   x_scale=scale, method="trf", max_nfev=budget)
        self.blocks_ = k if blocks else 1  # the samples per block of the simulation the fit ended on
        self.optimizer_result_ = result
        self.jacobian_ = result.jac  # d simulated temperature / d free parameters, every stride_-th sample
        r = result.fun
        J = result.jac
        fractions = independent_fractions(J)
        weak = int(np.argmin(fractions))
        if fractions[weak] < DEGENERATE_FRACTION:
            p = params[weak]
            raise IdentifiabilityError(
                f"cannot identify {p.name} ({p.description}) for "
                f"actuator {series[0].actuator}: changing it changes "
                "the simulated temperature almost exactly as other "
                f"parameters do ({fractions[weak]:.1e} independent); "
                f"a log needs {p.excitation}",
                parameter=p.name, partners=tuple(params[k].name for k in collinear_partners(J, weak)),
            )
        dof = max(r.size - len(params), 1)
        sigma2 = float(r @ r) / dof * ar1_variance_factor(r)
        cov = np.zeros((len(names), len(names)))
        cov[np.ix_(free, free)] = sigma2 * scaled_inverse(J.T @ J)
        values = _with(x_all, free, result.x)
        final = model_at(result.x)
        self.offsets_ = [
            final.place_hidden(s, r, rate)[1] if hidden else {} for s, rate, r in zip(series, rates, rows)
        ]
        return values, cov


def _with(values: np.ndarray, free: np.ndarray, x: np.ndarray) -> np.ndarray:
    out = values.copy()
    out[free] = x
    return out


def _time_constant_guess(series) -> float:
    """A tenth of the longest series' duration: a neutral start for RC when least squares has none."""
    return max(float(s.time_s[-1] - s.time_s[0]) for s in series) / 10.0
