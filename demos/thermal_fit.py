"""Demo ``thermal-fit``: Jorgensen et al.'s Fig. 5 on the thermal plant.

Identify the effort-based model of a knee actuator (core and driver) from a log
of random holds and motions, then predict a long experiment of repeated
double-support squats (one every 4.5 min) from 25 degC using effort only, with
no temperature updates, and compare with what the plant's sensors measured.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thermolimb.demo_registry import DemoPage, demo_main, kelvin, register_demo
from thermolimb.identification.metrics import fit_metrics
from thermolimb.identification.regression import lowpass, lowpass_derivative
from thermolimb.model import DEFAULT_MODEL
from thermolimb.plant import X8_16, EffortBias, PlantEffects, Quantisation, SensorNoise, simulate_profile
from thermolimb.plotting.fits import plt, save
from thermolimb.workbench.validation import make_estimator

NAME = "thermal-fit"
DT_S = 0.5
AMBIENT_C = 25.0
METHODS = ("jorgensen_gd", "least_squares", "output_error")
METHOD_WORDS = {"jorgensen_gd": "Jorgensen et al.'s gradient descent", "least_squares": "least squares",
                "output_error": "output error"}
CHANNELS = ("knee", "knee/driver")


def _effects() -> PlantEffects:
    # A series-elastic actuator with a real sensor: effort bias, 0.05 K noise, 0.1 degC steps.
    return PlantEffects(effort_bias=EffortBias(), sensor_noise=SensorNoise(), quantisation=Quantisation())


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for channel, methods in summary["channels"].items():
        oe, gd = methods["output_error"]["prediction"], methods["jorgensen_gd"]["prediction"]
        rows.append((f"{channel}: prediction RMSE, output error", kelvin(oe["rmse_K"]),
                     f"Jorgensen et al.'s gradient descent {kelvin(gd['rmse_K'])}; largest error "
                     f"{kelvin(oe['max_abs_K'])} against {kelvin(gd['max_abs_K'])}"))
    return rows


def _finding(summary: dict) -> str:
    oe, gd = (summary["channels"]["knee"][m]["prediction"] for m in ("output_error", "jorgensen_gd"))
    return (f"In this run the output-error model predicts the knee's winding over the squats, from effort alone, to "
            f"{kelvin(oe['rmse_K'])} RMSE, against {kelvin(gd['rmse_K'])} for Jorgensen et al.'s gradient descent.")


PAGE = DemoPage(
    about="Jorgensen et al.'s Fig. 5 on the thermal plant: a knee actuator's model is identified from a log of random "
          "holds and motions, then predicts a long experiment of squats (one every 4.5 minutes) from effort alone, "
          "never corrected by a measurement. Look at how closely the free-run prediction follows the measured "
          "winding and driver temperatures over the whole experiment, and how the three identification methods "
          "compare.",
    headline=_headline,
    finding=_finding,
    captions={"fig5_prediction.png": "Measured temperature during the squats (black) and each method's free-run "
                                     "prediction from effort alone, winding above and driver below.",
              "methods.png": "Prediction error of each identification method on both channels."})


@register_demo(NAME, "Jorgensen et al.'s Fig. 5: identify from plant data, predict a long squat experiment from effort only",
               page=PAGE)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    identification_s = 3600.0 if quick else 3 * 3600.0
    experiment_s = 1.5 * 3600.0 if quick else 4 * 3600.0
    ident = simulate_profile("random", identification_s, DT_S, ["knee"], [X8_16], _effects(), seed=1,
                             ambient_C=AMBIENT_C, include_drivers=True, quiet=quiet).log
    squat = simulate_profile("squat", experiment_s, DT_S, ["knee"], [X8_16], _effects(), seed=2,
                             ambient_C=AMBIENT_C, include_drivers=True, quiet=quiet).log
    summary = {"identification_s": identification_s, "experiment_s": experiment_s, "dt_s": DT_S,
               "plant": "HEBI X8-16, 3-node network, effort bias 2 N m, noise 0.05 K, 0.1 degC steps",
               "channels": {}}
    predictions = {}
    for channel in CHANNELS:
        train, test = ident.series(channel), squat.series(channel)
        per_method = {}
        for method in METHODS:
            est = make_estimator(method, DEFAULT_MODEL).fit(train)
            predicted = est.simulate(test, initial_temperature_C=AMBIENT_C)
            per_method[method] = {"params": est.params_, "prediction": fit_metrics(test.temperature_C, predicted)}
            predictions[channel, method] = predicted
        summary["channels"][channel] = per_method
    _plot_fig5(squat, predictions, out / "fig5_prediction.png")
    _plot_methods(summary, out / "methods.png")
    return summary


def _plot_fig5(log, predictions, path):
    fig, axes = plt.subplots(3, 2, figsize=(11, 8), sharex=True)
    for col, channel in enumerate(CHANNELS):
        ser = log.series(channel)
        t_min = ser.time_s / 60.0
        measured, measured_rate = lowpass_derivative(ser.temperature_C, 0.015, DT_S)
        ax = axes[0, col]
        ax.plot(t_min, ser.temperature_C, color="0.3", lw=1, label="measured")
        for method, style in zip(METHODS, (":", "--", "-")):
            pred = predictions[channel, method]
            ax.plot(t_min, pred, ls=style, lw=1.2, label=f"predicted, {METHOD_WORDS[method]}")
            axes[1, col].plot(t_min, np.gradient(lowpass(pred, 0.015, DT_S), DT_S) * 60.0, ls=style, lw=1)
        ax.set_title(f"{channel}: predicted from 25 °C using effort only")
        ax.set_ylabel("temperature (°C)")
        axes[1, col].plot(t_min, measured_rate * 60.0, color="0.3", lw=1)
        axes[1, col].set_ylabel("rate (K/min, 0.015 Hz low-pass)")
        axes[2, col].plot(t_min, ser.signals.effort, color="0.6", lw=0.5, label="raw")
        axes[2, col].plot(t_min, lowpass(ser.signals.effort, 1.0, DT_S), color="k", lw=0.8, label="1 Hz low-pass")
        axes[2, col].set_ylabel("effort (N m)")
        axes[2, col].set_xlabel("time (min)")
    # one legend for the figure, under it: the curves fill every panel
    handles = axes[0, 0].get_legend_handles_labels()[0] + axes[2, 0].get_legend_handles_labels()[0]
    labels = axes[0, 0].get_legend_handles_labels()[1] + ["effort, raw", "effort, 1 Hz low-pass"]
    fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=3, fontsize=8, frameon=False)
    fig.tight_layout()
    save(fig, path)


def _plot_methods(summary, path):
    fig, ax = plt.subplots(figsize=(7, 3.5))
    width = 0.25
    for i, method in enumerate(METHODS):
        rmse = [summary["channels"][c][method]["prediction"]["rmse_K"] for c in CHANNELS]
        ax.bar(np.arange(len(CHANNELS)) + (i - 1) * width, rmse, width, label=METHOD_WORDS[method])
    ax.set_xticks(np.arange(len(CHANNELS)), CHANNELS)
    ax.set_ylabel("prediction RMSE (K)")
    ax.set_title("squat experiment predicted from effort only: error by identification method")
    ax.legend(fontsize=8)
    save(fig, path)


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
