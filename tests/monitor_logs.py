"""A saved model and a log to follow, as the monitor's tests need them (written through the command line)."""

from __future__ import annotations

from pathlib import Path

from thermolimb.cli.main import main


def model_and_run(folder: Path, calibration_s: float, run_s: float) -> tuple[Path, Path]:
    """A first-order model fitted on a random-duty plant log of ``calibration_s`` (limit 60 degC), saved; and a
    squat log of ``run_s`` to follow."""
    cal, run, model = folder / "cal.csv", folder / "run.csv", folder / "model.json"
    assert main(["simulate", "--profile", "random", "--duration", f"{calibration_s:g}", "--dt", "1", "--network",
                 "first_order", "--seed", "4", "--out", str(cal), "--quiet"]) == 0
    assert main(["simulate", "--profile", "squat", "--duration", f"{run_s:g}", "--dt", "1", "--network", "first_order",
                 "--seed", "5", "--out", str(run), "--quiet"]) == 0
    assert main(["fit", str(cal), "--save", str(model), "--limit-C", "60", "--quiet"]) == 0
    return model, run
