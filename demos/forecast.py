"""Demo ``forecast``: the identified model in use -- saved, asked how long a joint can hold a duty, and run
next to a robot as a monitor.

A plant richer than the model (a winding on a heavier housing, speed losses, copper's temperature coefficient,
a thermistor lagging 15 s) gives a calibration log.  The demo identifies two models on it and saves each to a
model file: Jorgensen et al.'s model as ``fit`` gives it, and the one ``diagnose --auto`` ends with.  Then, for
held duties run on the plant itself, each model answers "how long until the sensor reads this temperature?"
with a 90 % interval, and the demo counts how often the interval holds the truth.  Last, ``thermolimb
monitor``'s machinery follows a walking run of the same plant and writes its ROS 2 MCAP; its winding estimate
is drawn against the plant's true winding and the thermistor.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from thermolimb.demo_registry import DemoPage, demo_main, register_demo
from thermolimb.forecast import forecast
from thermolimb.logs.follow import CsvFollower, Run
from thermolimb.model import DEFAULT_MODEL
from thermolimb.model.reach import crossing_s
from thermolimb.model.saved import ModelFile
from thermolimb.monitor import Session
from thermolimb.monitor.recording import McapOutput
from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile
from thermolimb.plant.duties import held_duty
from thermolimb.plotting.forecast import plot_forecast
from thermolimb.plotting.monitor import plot_monitor
from thermolimb.workbench.diagnosis import auto_diagnose
from thermolimb.workbench.diagnosis.stability import Stability
from thermolimb.workbench.saving import saved_from_report
from thermolimb.workbench.validation import validate_model

NAME = "forecast"
SPEC = replace(X8_9, network=NETWORKS["second_order"])
RICHER = ("speed_losses", "winding_tempco", "sensor_lag")
HORIZONS_S = (60.0, 900.0)
LIMIT_C = 100.0


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for label, name in (("default", "Jorgensen et al.'s model"), ("auto", "the model diagnose --auto finds")):
        c = summary["coverage"][label]
        rows.append((f"{name}: 90 % intervals holding the true time", f"{c['covered']} of {c['cases']}",
                     f"median error of the time {100 * c['median_error']:.0f} %"))
    m = summary["monitor"]
    rows.append(("monitor: winding estimate against the plant's true winding", f"{m['rmse_K']:.2f} K RMSE",
                 f"the thermistor alone: {m['thermistor_rmse_K']:.2f} K; the truth within 2 sd "
                 f"{100 * m['true_within_2sd']:.0f} % of the time"))
    return rows


def _finding(summary: dict) -> str:
    auto, default = summary["coverage"]["auto"], summary["coverage"]["default"]
    return (f"In this run the model diagnose --auto finds holds the true time in {auto['covered']} of {auto['cases']} "
            f"of its 90 % intervals (median error {100 * auto['median_error']:.0f} %), Jorgensen et al.'s model in "
            f"{default['covered']} of {default['cases']} (median error {100 * default['median_error']:.0f} %).")


PAGE = DemoPage(
    about="The model the workbench finds, put to use. Two models identified on a calibration log of a plant richer "
          "than either (a heavier housing, speed losses, copper's tempco, a lagging thermistor) are saved to model "
          "files; each then says how long held duties take to reach a temperature, with a 90 % interval, checked "
          "against the plant itself; and the monitor follows a walking run, writing its ROS 2 MCAP. Look at the "
          "band plot (the interval's width is the honest part: it grows where the model is unsure) and at how "
          "far the thermistor trails the true winding while the estimate does not.",
    headline=_headline,
    finding=_finding,
    captions={"forecast_band.png": "A held duty from rest: the model's prediction and its 90 % band, the threshold "
                                   "(the plant's reading 900 s in) and the plant's own thermistor reading.",
              "monitor.png": "The monitor following a walking run: its winding estimate (with two standard "
                             "deviations), the plant's true winding and the thermistor it reads."})


@register_demo(NAME, "a saved model: how long until a joint reaches a temperature, with an interval; a monitor",
               page=PAGE)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    duration = 7200.0  # two hours: an hour of random holds at 1 Hz holds too few transients to tell the effects apart
    fx = PlantEffects.from_names(("sensor_noise", "quantisation") + RICHER)
    calibration = simulate_profile("random", duration, 1.0, ["knee"], [SPEC], fx, seed=0, quiet=quiet).log
    series = calibration.series("knee")
    calibration.write(out / "calibration.csv")
    stability = None if quick else Stability()
    _, steps = auto_diagnose([series], quiet=quiet, stability=stability)
    reports = {"default": validate_model([series], DEFAULT_MODEL), "auto": steps[-1].base}
    models = {}
    for label, report in reports.items():
        path = out / f"model_{label}.json"
        ModelFile({"knee": saved_from_report(report, [out / "calibration.csv"], LIMIT_C)}).save(path)
        models[label] = ModelFile.load(path)["knee"]
    rows = _duties(models, quick)
    coverage = {label: _coverage(rows, label) for label in models}
    band = held_duty(SPEC, PlantEffects.from_names(RICHER), 1.5 * SPEC.continuous_effort, 2.0, 1800.0)
    f = forecast(models["auto"], band.signals, band.start_C, float(band.sensor_C[900]), measured_C=band.sensor_C)
    plot_forecast(f, out / "forecast_band.png")
    return {"plant": {"network": "winding + heavier housing", "effects": list(RICHER), "calibration_s": duration},
            "models": {label: list(m.model.terms) for label, m in models.items()},
            "stability_check": stability is not None,
            "coverage": coverage, "cases": rows, "monitor": _monitor(models["auto"], out, quiet)}


def _duties(models: dict, quick: bool) -> list[dict]:
    loads = (1.0, 1.5) if quick else (0.8, 1.0, 1.2, 1.5)
    rows = []
    for load in loads:
        for speed in (0.0, 2.0):
            duty = held_duty(SPEC, PlantEffects.from_names(RICHER), load * SPEC.continuous_effort, speed, 1200.0)
            for horizon in HORIZONS_S:
                threshold = float(np.interp(horizon, duty.signals.time_s, duty.sensor_C))
                truth = crossing_s(duty.signals.time_s, duty.sensor_C, threshold)
                row = {"load": load, "speed_rad_s": speed, "horizon_s": horizon, "threshold_C": threshold,
                       "true_s": truth}
                for label, saved in models.items():
                    f = forecast(saved, duty.signals, duty.start_C, threshold)
                    low, high = f.interval_s
                    row[label] = {"predicted_s": f.time_to_threshold_s, "interval_s": [low, high],
                                  "covered": bool(low is not None and low <= truth and (high is None or truth <= high))}
                rows.append(row)
    return rows


def _coverage(rows: list[dict], label: str) -> dict:
    errors = [1.0 if r[label]["predicted_s"] is None else abs(r[label]["predicted_s"] - r["true_s"]) / r["true_s"]
              for r in rows]
    return {"cases": len(rows), "covered": sum(r[label]["covered"] for r in rows),
            "median_error": float(np.median(errors))}


def _monitor(saved, out: Path, quiet: bool) -> dict:
    fx = PlantEffects.from_names(("sensor_noise", "quantisation") + RICHER)
    walk = simulate_profile("walking", 1800.0, 1.0, ["knee"], [SPEC], fx, seed=7, quiet=quiet)
    walk.log.write(out / "walking.csv")
    session = Session(ModelFile({"knee": saved}), {"knee": LIMIT_C}, [McapOutput(out / "monitor.mcap", ["knee"])],
                      publish_every_s=1.0)
    estimates = []
    follower = CsvFollower(out / "walking.csv")
    pieces = follower.poll(final=True)["knee"]  # the first rows, then the rest: one run, read in two pieces
    whole = {c: np.concatenate([p.arrays[c] for p in pieces]) for c in pieces[0].arrays}
    for lo in range(0, len(whole["time"]), 60):  # the run as it would arrive, a minute at a time
        minute = {c: v[lo:lo + 60] for c, v in whole.items()}
        estimates += session.feed({"knee": [Run(minute, lo == 0)]})
    session.close()
    est_t = np.array([e.time_s for e in estimates])
    est = np.array([e.winding_C for e in estimates])
    std = np.array([e.winding_std_K for e in estimates])
    true = np.interp(est_t, walk.time_s, walk.true_winding_C[:, 0])
    measured = np.interp(est_t, walk.time_s, walk.measured_C[:, 0])
    plot_monitor(walk.time_s, walk.true_winding_C[:, 0], walk.measured_C[:, 0], est_t, est, std, out / "monitor.png")
    return {"publications": session.publications, "rmse_K": float(np.sqrt(np.mean((est - true) ** 2))),
            "true_within_2sd": float(np.mean(np.abs(est - true) <= 2 * std)),
            "thermistor_rmse_K": float(np.sqrt(np.mean((measured - true) ** 2))), "mcap": "monitor.mcap"}


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
