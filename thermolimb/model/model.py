"""The effort-based first-order thermal model of one actuator (Jorgensen et al., Eqs. 5, 6, 17).

    RC * dT/dt + T = T_offset + sum_k ( rise_k(t) + gain_k(t) * T )

With the default terms ``joule`` and ``effort_bias`` this is exactly Eq. 5:
``RC dT/dt + T = beta*R*F^2 - beta_bias*R*F + T_offset``.
"""

from __future__ import annotations

from dataclasses import InitVar, dataclass, field
from typing import Mapping

import numpy as np

from ..util.frozen import FrozenMapping
from .guard import instance
from .scan import first_order_scan
from .signals import Signals
from .terms import TERMS, Parameter, is_built_in, parse_model

TIME_CONSTANT = Parameter("RC_s", "s", 1e-3, np.inf, 100.0, "thermal time constant RC",
                          "temperature that changes: heating and cooling transients")
OFFSET = Parameter("T_offset_C", "degC", -100.0, 400.0, 25.0,
                   "temperature offset: ambient plus the constant bias heating, T_amb + P_bias*R",
                   "periods at low effort, so that heating can be told from the offset")
BASE_PARAMETERS = (TIME_CONSTANT, OFFSET)


def redefines_offset(terms) -> bool:
    """Whether a model of ``terms`` has a term after which T_offset is no ambient temperature."""
    return any(TERMS[t].redefines_offset for t in terms if t in TERMS)

# A term may not cancel the restoring -T of the model; closer than this to
# thermal runaway the gain is clipped (see ThermalModel.forcing).
_MIN_RESTORING = 1e-6
# fixed-point passes of a temperature-dependent heat through slow masses (see ThermalModel._coupled)
COUPLING_PASSES = 2
# ThermalModel.place_hidden's memo keeps the responses of this many parameter points, and at most this many
# bytes (a finite-difference Jacobian perturbs one parameter at a time: the ones that move only the rise reuse
# its point's)
MEMO_RESPONSES, MEMO_BYTES = 4, 32 << 20


def hidden_states(terms: tuple[str, ...]) -> tuple[str, ...]:
    """The states of a model its first reading does not give: the winding behind a lagging sensor, each slow
    mass.  A fit places them per run (:class:`~thermolimb.identification.FreeRunLeastSquares`)."""
    lagged = ("winding",) if any(TERMS[t].lags_output for t in terms) else ()
    return lagged + tuple(t for t in terms if TERMS[t].carries_state)


def model_parameters(terms: tuple[str, ...]) -> tuple[Parameter, ...]:
    """All parameters of a model in the order of the regression (Eq. 7): RC, each term's, T_offset."""
    return (TIME_CONSTANT,) + tuple(p for name in terms for p in TERMS[name].parameters) + (OFFSET,)


@dataclass(frozen=True)
class ThermalModel:
    """A model structure (its terms) with parameter values, each finite and within its declared bounds.

    ``bounded=False`` lets an estimate of an unconstrained regression (the
    least squares of Jorgensen et al., Eq. 7) stand as it came out, a negative βR included:
    the fit's flags report it as implausible instead.
    """

    terms: tuple[str, ...]
    params: Mapping[str, float] = field(default_factory=dict)
    bounded: InitVar[bool] = True

    def __post_init__(self, bounded: bool):
        terms = parse_model(self.terms)
        object.__setattr__(self, "terms", terms)
        expected = [p.name for p in model_parameters(terms)]
        missing = [n for n in expected if n not in self.params]
        extra = [n for n in self.params if n not in expected]
        if missing or extra:
            raise ValueError(f"parameters of model {','.join(terms)}: missing {missing}, unexpected {extra}")
        values = {n: float(self.params[n]) for n in expected}
        bad = [n for n, v in values.items() if not np.isfinite(v)]
        if bad:
            raise ValueError(f"parameters of model {','.join(terms)} "
                             f"must be finite numbers; {', '.join(bad)} "
                             f"{'is' if len(bad) == 1 else 'are'} not "
                             f"({', '.join(str(values[n]) for n in bad)})")
        if not values["RC_s"] > 0:
            raise ValueError(f"RC_s must be positive, got {values['RC_s']}")
        for p in model_parameters(terms) if bounded else ():
            slack = 1e-9 * max(1.0, abs(values[p.name]))
            if not p.lower - slack <= values[p.name] <= p.upper + slack:
                raise ValueError(f"{p.name} = {values[p.name]:g} is outside "
                                 f"its bounds [{p.lower:g}, {p.upper:g}] "
                                 f"({p.description})")
        # read-only and picklable (a fitted model crosses process boundaries in fleets and users' pools)
        object.__setattr__(self, "params", FrozenMapping(values))

    @property
    def parameters(self) -> tuple[Parameter, ...]:
        return model_parameters(self.terms)

    @property
    def columns(self) -> tuple[str, ...]:
        """The log columns this model needs as inputs."""
        cols: list[str] = []
        for name in self.terms:
            cols += [c for c in TERMS[name].columns if c not in cols]
        return tuple(cols)

    @property
    def gap_fade_s(self) -> float:
        """How fast a forecast's gap to the reading it starts from fades (s): the first slow mass's time
        constant, else the winding's.  After a history the model has run over, what it misses of the last
        reading sits in its slow state (the winding has long settled on it), and fades as that state does."""
        return self.params.get("frame_tau_s", self.params["RC_s"])

    def with_params(self, values) -> "ThermalModel":
        """The same structure with new values (a mapping, or a vector in parameter order)."""
        if not isinstance(values, Mapping):
            values = dict(zip([p.name for p in self.parameters], np.asarray(values, dtype=float)))
        return ThermalModel(self.terms, values)

    def vector(self) -> np.ndarray:
        return np.array([self.params[p.name] for p in self.parameters])

    def forcing(self, s: Signals) -> tuple[np.ndarray, np.ndarray]:
        """``(u, lam)`` per sample: the model reads ``dT/dt = lam * (u - T)``.

        ``u`` is the instantaneous equilibrium temperature (degC) and ``lam``
        the instantaneous rate (1/s).  Where the terms' total gain would reach
        1 (thermal runaway) it is clipped to ``1 - 1e-6``.
        """
        u, lam, _, _ = self._forcing(s)
        return u, np.broadcast_to(lam, u.shape)

    def _forcing(self, s: Signals) -> tuple[np.ndarray, np.ndarray | float, np.ndarray, np.ndarray | float]:
        """``(u, lam, boundary, gain)``: ``boundary`` is the temperature heat finally flows to (offset plus
        boundary terms such as the ambient), which slow masses relax towards; ``gain`` the terms' total
        gain on T, clipped short of runaway.  ``lam`` and ``gain`` are one number when no term's gain varies
        (the usual case: a long log's free run then makes no array for them)."""
        offset = self.params["T_offset_C"]
        rise = np.zeros(s.n)
        gain = 0.0
        boundary = offset
        for term in self._terms():
            r, g = s.contribution(term, self.params)
            rise += r
            if np.ndim(g) or g != 0.0:
                gain = gain + g
            if term.boundary or term.heats_slow_mass:
                boundary = boundary + r
        restoring = np.maximum(1.0 - gain, _MIN_RESTORING)
        rise += offset
        u = rise / restoring if np.ndim(restoring) or restoring != 1.0 else rise
        lam = restoring / self.params["RC_s"]
        return u, lam, np.broadcast_to(boundary, u.shape), 1.0 - restoring

    def _terms(self):
        return [instance(name) for name in self.terms]

    def equilibrium_C(self, s: Signals) -> np.ndarray:
        """Steady-state temperature if each sample's inputs were held forever (Eq. 5 with dT/dt = 0)."""
        return self.forcing(s)[0]

    def simulate(self, s: Signals, initial_temperature_C: float, method: str = "exact",
                 initial_rate_K_per_s: float = 0.0, state: Mapping[str, float] | None = None,
                 keep: dict | None = None, offsets: Mapping[str, float] | None = None) -> np.ndarray:
        """Free-run temperatures at every sample time, from ``initial_temperature_C``, inputs only.

        ``initial_rate_K_per_s`` is how fast the measured temperature was
        moving at the start; terms with hidden states (a lagging sensor) use
        it to place the winding behind the first reading.

        ``method="exact"`` integrates each interval exactly for inputs held
        constant over it (zero-order hold, Eq. 6 applied interval by
        interval); ``method="euler"`` is forward Euler as Jorgensen et al. used.
        Terms with states of their own (a second mass, a lagging sensor) shape
        the equilibrium and the output around the winding's recursion.

        A run in pieces (a monitor following a log): ``keep``, a dict, receives the state the simulation
        ends in (the winding, each slow mass, the output; and the last sample's steady state ``steady_C`` and
        rate ``rate_per_s``, the forcing's, for a forecast); passed back as ``state`` for the next piece,
        whose first sample is this piece's last, the run carries on exactly as one simulation of the whole
        would (``initial_temperature_C`` and the rate are then unused).

        ``offsets`` (K, by :func:`hidden_states`' names) move the hidden states' starts from where the first
        reading puts them: where the data place them (a run that starts warm, or mid-transient).
        """
        if method not in ("exact", "euler"):
            raise ValueError(f"method must be 'exact' or 'euler', got {method!r}")
        if not np.isfinite(s.effort).all():
            k = int(np.flatnonzero(~np.isfinite(s.effort))[0])
            raise ValueError(f"the effort is {s.effort[k]} at sample {k} (t "
                             f"= {s.time_s[k]:g} s); a simulation needs a "
                             f"finite effort at every sample (drop or fill the missing ones)")
        terms = self._terms()
        if state is None:
            start = initial_temperature_C
            for term in terms:
                start = term.initial_winding(self.params, start, initial_rate_K_per_s)
            start += (offsets or {}).get("winding", 0.0)
            output_start = initial_temperature_C
        else:
            start, output_start = state["winding"], state["output"]
        u, lam, boundary, gain = self._forcing(s)
        shaped = self._shape(s, terms, u, start, boundary, state, offsets)
        winding = self._winding(s, shaped, lam, start, method)
        share = float(np.prod([term.winding_share(self.params) for term in terms]))
        if share < 1.0 and np.any(gain != 0.0):
            winding = self._coupled(s, terms, u, lam, boundary, gain, share, start, winding, method, state,
                                    offsets)
        out = winding
        for term in terms:
            out = term.shape_output(self.params, s, out, output_start)
        if keep is not None:
            keep.clear()
            keep.update({"winding": float(winding[-1]), "output": float(out[-1]),
                         "steady_C": float(u[-1]), "rate_per_s": float(np.broadcast_to(lam, u.shape)[-1])})
            keep.update(
                {t.name: t.state for t in terms if t.carries_state and getattr(t, "state", None) is not None}
            )
        return out

    def free_run(
        self,
        series,
        initial_rate_K_per_s: float | None = None,
        method: str = "exact",
        initial_temperature_C: float | None = None,
        offsets: Mapping[str, float] | None = None,
    ) -> np.ndarray:
        """The free run of a measured run (an :class:`~thermolimb.logs.ActuatorSeries`) from its first
        reading.

        The one way every fit, validation and diagnosis simulates a log: from
        the first measured temperature (unless ``initial_temperature_C``) and
        the measured trend over the first minute (unless
        ``initial_rate_K_per_s``), with the log's inputs alone; ``offsets``: the hidden states' starts
        where the data place them (:meth:`place_hidden`).
        """
        start = series.temperature_C[0] if initial_temperature_C is None else initial_temperature_C
        rate = series.rate_K_per_s() if initial_rate_K_per_s is None else initial_rate_K_per_s
        return self.simulate(series.signals, start, method=method, initial_rate_K_per_s=rate, offsets=offsets)

    @property
    def hidden_states(self) -> tuple[str, ...]:
        return hidden_states(self.terms)

    def place_hidden(self, series, rows: np.ndarray, rate: float | None = None, run: np.ndarray | None = None,
                     memo: dict | None = None) -> tuple[np.ndarray, dict[str, float]]:
        """The free run of ``series`` with its hidden states' starts placed where the readings at ``rows`` put
        them, and those offsets: the model is affine in its states, so each offset's response is one more free
        run, and the offsets are the least-squares fit of the residual at ``rows`` by those responses.
        ``run``: the free run without offsets, when the caller has it.  ``memo``, a dict the caller keeps for
        this series, holds the last responses: they depend only on the parameters that move more than the rise
        (a fit's finite differences in an effort coefficient or the offset reuse them)."""
        rate = series.rate_K_per_s() if rate is None else rate
        run = self.free_run(series, rate) if run is None else run
        names = self.hidden_states
        if not names or rows.size == 0:
            return run, {}
        key = self._response_key()
        responses = memo.pop(key, None) if memo is not None else None
        if responses is None:
            responses = np.column_stack([self.free_run(series, rate, offsets={h: 1.0}) - run for h in names])
        if memo is not None:  # most recent last; a few at most, and none of a long run's
            memo[key] = responses
            while len(memo) > min(MEMO_RESPONSES, MEMO_BYTES // responses.nbytes):
                memo.pop(next(iter(memo)))
        G = responses[rows]
        delta = np.linalg.lstsq(G, series.temperature_C[rows] - run[rows], rcond=1e-9)[0]
        return run + responses @ delta, dict(zip(names, map(float, delta)))

    def _response_key(self) -> tuple:
        """The terms and the values a hidden state's response depends on: all but the offset and the
        parameters of terms that move only the rise (``Term.rise_only``, the suite's own: the model is affine
        in them and in its states; a user's term may subclass one and add a gain), unless another term reads
        them (``Term.reads``: copper's coefficient makes the Joule heat's a gain on the winding's
        temperature)."""
        rise = {"T_offset_C"} | {
            p.name for t in map(TERMS.get, self.terms) if t.rise_only and is_built_in(t) for p in t.parameters
        } - {name for t in self.terms for name in TERMS[t].reads}
        return (self.terms, *(v for k, v in self.params.items() if k not in rise))

    def _winding(
        self, s: Signals, u: np.ndarray, lam: np.ndarray | float, start: float, method: str
    ) -> np.ndarray:
        if method == "exact":
            recursion = s.recursion(lam)
            return recursion.run((1.0 - recursion.a) * u[:-1], start)
        lam, dt = (lam[:-1], s.dt_s) if np.ndim(lam) else (lam, s.interval_s)
        a = 1.0 - lam * dt
        b = lam * dt * u[:-1]
        if np.all(a >= 0.0):
            return first_order_scan(a, b, start)
        a = np.broadcast_to(a, b.shape)
        winding = np.empty(s.n)
        winding[0] = start
        for k in range(s.n - 1):
            winding[k + 1] = a[k] * winding[k] + b[k]
        return winding

    def _coupled(
        self, s, terms, u, lam, boundary, gain, share, start, winding, method, state=None, offsets=None
    ):
        """Slow masses with a temperature-dependent heat (copper resistance, neighbours, airflow).

        The first pass fed the masses the heat of a winding already at its
        equilibrium, which overstates the feedback while it is still warming.
        Here the masses get the heat at the simulated winding temperature
        (a fixed point, ``COUPLING_PASSES`` passes), while the winding keeps
        its own share ``share`` of the gain implicit, so that strong
        couplings stay stable.
        """
        # T_offset + rises - boundary: the heat's rise with no feedback
        heat_at_rest = u * (1.0 - gain) - boundary
        rc = self.params["RC_s"]
        for _ in range(COUPLING_PASSES):
            heat = heat_at_rest + gain * winding
            frames = (
                self._shape(s, terms, boundary + heat, start, boundary, state, offsets)
                - boundary
                - share * heat
            )
            restoring = np.maximum(1.0 - share * gain, _MIN_RESTORING)
            target = (boundary + frames + share * heat_at_rest) / restoring
            winding = self._winding(s, target, restoring / rc, start, method)
        return winding

    def _shape(
        self,
        s: Signals,
        terms,
        u: np.ndarray,
        initial_C: float,
        boundary: np.ndarray,
        state: Mapping[str, float] | None = None,
        offsets: Mapping[str, float] | None = None,
    ) -> np.ndarray:
        for term in terms:
            if state is not None and term.carries_state:
                u = term.shape_equilibrium(self.params, s, u, initial_C, boundary, state=state.get(term.name))
            elif offsets and term.carries_state and term.name in offsets:
                u = term.shape_equilibrium(self.params, s, u, initial_C, boundary, offset=offsets[term.name])
            else:
                u = term.shape_equilibrium(self.params, s, u, initial_C, boundary)
        return u

    def _shaped_forcing(self, s: Signals, terms, initial_C: float) -> tuple[np.ndarray, np.ndarray]:
        u, lam, boundary, _ = self._forcing(s)
        return self._shape(s, terms, u, initial_C, boundary), np.broadcast_to(lam, u.shape)

    def one_step(self, s: Signals, measured_C: np.ndarray) -> np.ndarray:
        """Prediction of each sample from the measured temperature one sample before (exact).

        Hidden states (a second mass) are taken from the free run; a sensor lag is ignored.
        """
        u, lam = self._shaped_forcing(s, self._terms(), measured_C[0])
        a = np.exp(-lam[:-1] * s.dt_s)
        out = np.empty(s.n)
        out[0] = measured_C[0]
        out[1:] = a * measured_C[:-1] + (1.0 - a) * u[:-1]
        return out
