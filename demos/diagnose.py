"""Demo ``diagnose``: the model-versus-measurement story on a log with hidden effects.

The plant hides two effects the seed's model lacks -- speed losses and heat
conducted from the neighbouring actuators.  The diagnosis of the hip fits
the base model, shows where and why it fails (residual analysis), ranks the
catalog's effects, and with ``--auto`` adds them one at a time: the
waterfall shows the validation error falling to the sensor noise.
"""

from __future__ import annotations

from pathlib import Path

from thermolimb.demo_registry import demo_main, register_demo
from thermolimb.diagnosis import auto_diagnose
from thermolimb.diagnosis.plots import plot_diagnosis
from thermolimb.plant import NETWORKS, X8_9, X8_16, PlantEffects, simulate_profile

NAME = "diagnose"
HIDDEN = ("speed_losses", "neighbor_coupling")


@register_demo(NAME, "a log with hidden effects: residual analysis, ranked candidates, the waterfall")
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    dt_s = 1.0 if quick else 0.1
    effects = PlantEffects.from_names(["sensor_noise", "quantisation", *HIDDEN])
    log = simulate_profile("random", 2 * 3600.0, dt_s, ["knee", "hip", "ankle"], [X8_9, X8_16, X8_9], effects,
                           seed=4, network=NETWORKS["first_order"], quiet=quiet).log
    first, steps = auto_diagnose([log.series("hip")], quiet=quiet)
    plot_diagnosis(first, out, "hip")
    return {
        "hidden_effects": list(HIDDEN),
        "log": {"duration_s": 7200.0, "dt_s": dt_s, "actuators": list(log.actuators),
                "plant": "first-order X8 network, noise 0.05 K, 0.1 degC steps"},
        "diagnosis": first.to_json(),
        "found": sorted({t for s in steps[1:] for t in s.model} - set(first.model)),
    }


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
