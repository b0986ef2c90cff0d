"""A user's own term, held to its contract: whatever goes wrong inside it is one sentence naming the term.

Terms the suite ships (the catalog, and the terms it generates) are trusted; a term registered from a user's
file is wrapped by :func:`instance` so that each of its methods, when it raises, returns ``None``, NaN or inf,
an array of the wrong length, or calls ``sys.exit``, raises :class:`TermError` naming the term, the method and
what it returned -- which ``fit`` and ``compare`` report in one sentence and ``diagnose`` uses to set the term
aside and go on.
"""

from __future__ import annotations

import numpy as np

from ..util.errors import TermError
from .terms import TERMS, Term, is_built_in


def is_users(cls: type[Term]) -> bool:
    return not is_built_in(cls) and not getattr(cls, "generated", False)


def instance(name: str) -> Term:
    """A term of ``name``: the class itself when the suite ships it, a guarded one when a user wrote it."""
    cls = TERMS[name]
    return Guarded(cls()) if is_users(cls) else cls()


def _describe(value) -> str:
    if value is None:
        return "None"
    arr = np.asarray(value)
    if arr.dtype == object:
        return f"a {type(value).__name__}"
    if arr.ndim == 0:
        return repr(float(arr)) if np.issubdtype(arr.dtype, np.number) else repr(value)
    bad = int(np.size(arr) - np.count_nonzero(np.isfinite(arr))) if np.issubdtype(arr.dtype, np.number) else 0
    return f"an array of shape {arr.shape}" + (f" with {bad} values not finite (NaN or inf)" if bad else "")


class Guarded:
    """A user's term instance whose every method is checked (see the module docstring)."""

    def __init__(self, term: Term):
        self._term = term
        self.name = term.name

    def __getattr__(self, attr):
        return getattr(self._term, attr)

    def _call(self, method: str, *args):
        try:
            return getattr(self._term, method)(*args)
        except SystemExit as exc:
            raise TermError(
                f"term {self.name!r} called sys.exit({exc.code!r}) "
                f"in {method}; a term must return "
                f"its values, not end the program",
                self.name,
            ) from None
        # a user's code: whatever it raises is reported as what it is
        except Exception as exc:  # noqa: BLE001
            hint = ""
            if isinstance(exc, KeyError):
                hint = (
                    f" (a log column it reads and does not declare? it declares columns "
                    f"{', '.join(self._term.columns)})"
                )
            raise TermError(
                f"term {self.name!r} failed in {method}: {type(exc).__name__}: {exc}{hint}", self.name
            ) from None

    def _check_array(self, method: str, what: str, value, n: int):
        if value is None:
            raise TermError(f"term {self.name!r}: {method} returned None "
                            f"for its {what}; expected a number or an "
                            f"array of {n} samples", self.name)
        arr = np.asarray(value,
                         dtype=object if not np.isscalar(value) and not hasattr(value, "dtype") else None)
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise TermError(f"term {self.name!r}: {method} returned "
                            f"{_describe(value)} for its {what}; expected "
                            f"numbers", self.name) from None
        if arr.ndim > 1 or (arr.ndim == 1 and arr.shape[0] != n):
            raise TermError(f"term {self.name!r}: {method} returned "
                            f"{_describe(arr)} for its {what}; expected a "
                            f"number or an array of {n} samples", self.name)
        if not np.all(np.isfinite(arr)):
            raise TermError(f"term {self.name!r}: {method} returned "
                            f"{_describe(arr)} for its {what}; every value "
                            f"must be finite", self.name)
        return value

    def contribution(self, p, s):
        out = self._call("contribution", p, s)
        if not isinstance(out, tuple) or len(out) != 2:
            raise TermError(f"term {self.name!r}: contribution returned {_describe(out)}; expected a pair "
                            f"(rise_K, gain)", self.name)
        return (self._check_array("contribution", "rise", out[0], s.n),
                self._check_array("contribution", "gain", out[1], s.n))

    def shape_equilibrium(self, p, s, equilibrium_C, initial_C, boundary_C, **state):
        out = self._call("shape_equilibrium", p, s, equilibrium_C, initial_C, boundary_C)
        return self._check_array("shape_equilibrium", "equilibrium", out, s.n)

    def shape_output(self, p, s, winding_C, measured_initial_C):
        return self._check_array("shape_output", "output", self._call("shape_output", p, s, winding_C,
                                                                      measured_initial_C), s.n)

    def initial_winding(self, p, measured_C, rate_K_per_s):
        return float(
            self._check_array(
                "initial_winding", "start", self._call("initial_winding", p, measured_C, rate_K_per_s), 1
            )
        )

    def winding_share(self, p):
        return float(self._check_array("winding_share", "share", self._call("winding_share", p), 1))

    def features(self, s, temperature_C):
        out = self._call("features", s, temperature_C)
        if out is None:
            return None
        arr = np.asarray(out, dtype=float)
        if arr.ndim != 2 or arr.shape[0] != s.n or not np.all(np.isfinite(arr)):
            raise TermError(f"term {self.name!r}: features returned "
                            f"{_describe(out)}; expected a finite array of "
                            f"shape ({s.n}, {len(self._term.parameters)})", self.name)
        return out

    def implausible(self, p):
        return self._call("implausible", p)
