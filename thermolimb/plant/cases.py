"""Plant logs that hide one physical effect, for proving the diagnosis (tests, benchmarks, docs).

Each case names the plant's hidden physics, how the plant is set up for it,
and the model term that names it.  The logs are richer than the model: on the
default three-node X8 network, the model (one thermal mass) is wrong from the
start, and a search has to find the slow masses as well as the hidden effect.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .effects import PlantEffects
from .network import NETWORKS, X8_9, X8_16
from .run import simulate_profile

SENSOR = ("sensor_noise", "quantisation")
# the three actuators of every plant log the suite's demos, tests and benchmarks make (names, then datasheets)
CASE_NAMES = ("knee", "hip", "ankle")
CASE_SPECS = (X8_9, X8_16, X8_9)


@dataclass(frozen=True)
class HiddenCase:
    """One hidden effect: the plant effect switched on (or none), the plant's options, the term that names it
    (and ``also``: terms that name the same physics acting elsewhere in the model, e.g. airflow on the housing)."""

    name: str
    term: str
    effect: str | None = None
    load_scale: float = 1.0
    options: dict = field(default_factory=dict)
    also: tuple[str, ...] = ()

    def found_in(self, model) -> bool:
        """Whether ``model`` (term names) holds a term that names this case's effect."""
        return any(t in model for t in (self.term, *self.also))

    def log(self, seed: int, network: str = "x8", duration_s: float = 2 * 3600.0, dt_s: float = 1.0,
            profile: str = "random"):
        fx = PlantEffects.from_names(list(SENSOR) + ([self.effect] if self.effect else []))
        return simulate_profile(profile, duration_s, dt_s, list(CASE_NAMES), list(CASE_SPECS), fx, seed=seed,
                                network=NETWORKS[network], load_scale=self.load_scale, **self.options).log


HIDDEN_CASES = {case.name: case for case in (
    HiddenCase("effort_bias", "effort_bias", "effort_bias"),  # in the default start: found means kept
    HiddenCase("winding_tempco", "winding_tempco", "winding_tempco", load_scale=1.8),  # visible only when hot
    HiddenCase("speed_losses", "speed_losses", "speed_losses"),
    HiddenCase("field_weakening", "current_heating", "field_weakening"),
    HiddenCase("neighbor_coupling", "neighbor_coupling", "neighbor_coupling"),
    HiddenCase("ambient_variation", "ambient_variation", "ambient_variation"),
    # the plant's airflow cools its outer node; on the X8 the model may place it on the housing mass
    HiddenCase("motion_cooling", "motion_cooling", "motion_cooling", also=("housing_motion_cooling",)),
    HiddenCase("sensor_lag", "sensor_lag", "sensor_lag"),
    HiddenCase("slow_masses", "second_node"),  # nothing switched on: the X8's own housing and body
    HiddenCase("housing_sensor", "housing_boundary", options={"housing_sensor": True}),
)}
