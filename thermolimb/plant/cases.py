"""Plant logs that hide one physical effect, for proving the diagnosis (tests, benchmarks, docs).

Each case is an effect's :class:`~thermolimb.effects.Hidden`: the plant's hidden physics, how the plant is set
up for it, and the model term that names it.  The logs are richer than the model: on the default three-node X8
network, the model (one thermal mass) is wrong from the start, and a search has to find the slow masses as
well as the hidden effect.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..effects import EFFECTS, Hidden, PlantEffects
from .network import NETWORKS, X8_9, X8_16
from .run import simulate_profile

SENSOR = PlantEffects.realistic_sensor().names
# the three actuators of every plant log the suite's demos, tests and benchmarks make (names, then datasheets)
CASE_NAMES = ("knee", "hip", "ankle")
CASE_SPECS = (X8_9, X8_16, X8_9)


@dataclass(frozen=True)
class HiddenCase:
    """One hidden effect: the term that names it (and what else names the same physics), and how its log is
    made."""

    term: str
    hidden: Hidden

    @property
    def name(self) -> str:
        return self.hidden.case

    @property
    def effect(self) -> str | None:
        return self.hidden.effect

    def found_in(self, model) -> bool:
        """Whether ``model`` (term names) holds a term that names this case's effect."""
        return any(t in model for t in (self.term, *self.hidden.also))

    def log(self, seed: int, network: str = "x8", duration_s: float = 2 * 3600.0, dt_s: float = 1.0,
            profile: str = "random"):
        fx = PlantEffects.from_names(list(SENSOR) + ([self.effect] if self.effect else []))
        return simulate_profile(profile, duration_s, dt_s, list(CASE_NAMES), list(CASE_SPECS), fx, seed=seed,
                                network=NETWORKS[network], load_scale=self.hidden.load_scale,
                                **self.hidden.options).log


# in the catalog's order
HIDDEN_CASES = {e.hidden.case: HiddenCase(e.name, e.hidden) for e in EFFECTS.values() if e.hidden is not None}
