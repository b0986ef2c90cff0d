"""Identification on one million samples: direct least squares against Jorgensen et al.'s gradient descent.

Both solve the *same* regression (Jorgensen et al.'s rows: effort low-passed at 1 Hz,
temperature at 0.015 Hz, y = T - T_amb); the gradient descent runs until its
loss is within 1e-6 (relative) of the least-squares optimum.  Then the time of
``thermolimb fit`` (output error, the default) on a one-million-sample log,
with its peak memory, in a child process.

    python benchmarks/identification.py [--samples 1000000] [--json]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from thermolimb.identification import (
    FreeRunLeastSquares,
    JorgensenGradientDescent,
    LeastSquares,
    build_regression,
)
from thermolimb.identification.jorgensen_gd import zscore_gradient_descent
from thermolimb.identification.least_squares import solve_least_squares
from thermolimb.logs import log_from_arrays
from thermolimb.model import DEFAULT_MODEL, Signals, ThermalModel
from thermolimb.plant.profiles import random_holds

TRUE = {"RC_s": 80.0, "betaR_K_per_effort2": 0.2, "beta_biasR_K_per_effort": 0.8, "T_offset_C": 25.8}
DT_S = 0.1


def make_log(samples: int, seed: int = 0):
    """A first-order actuator (the model's own structure) with 0.05 K noise and 0.1 degC steps."""
    rng = np.random.default_rng(seed)
    profile = random_holds((samples - 1) * DT_S, DT_S, 1, rng)
    effort = 8.0 * profile.load[:, 0]
    model = ThermalModel(DEFAULT_MODEL, TRUE)
    temperature = model.simulate(Signals(profile.time_s, effort), 25.0)
    measured = np.round((temperature + rng.normal(0, 0.05, temperature.size)) / 0.1) * 0.1
    return log_from_arrays(profile.time_s, ("knee",), effort[:, None], measured[:, None],
                           velocity=profile.velocity_rad_s, ambient_C=np.full(profile.time_s.size, 25.0))


def timed(func, repeat=1):
    best, out = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - start)
    return best, out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    args = parser.parse_args(argv)

    log = make_log(args.samples)
    series = log.series("knee")
    print(f"{series.n} samples ({series.time_s[-1] / 3600:.1f} h at {1 / DT_S:.0f} Hz)")

    t_ls, ls = timed(lambda: LeastSquares(filtering="jorgensen").fit(series), repeat=3)
    target = ls.loss_ * (1 + 1e-6)
    t_gd, gd = timed(lambda: JorgensenGradientDescent(target_loss=target, tol=0.0, max_iter=1_000_000).fit(series))
    agreement = max(abs(gd.params_[k] - ls.params_[k]) / abs(ls.params_[k]) for k in ls.params_)
    # The solvers alone, on the same prebuilt rows (filtering and differentiation excluded).
    rows = build_regression([series], DEFAULT_MODEL, 0.015, consistent=False,
                            effort_cutoff_hz=1.0, subtract_ambient_C=25.0)
    t_solve_ls, (_, loss_ls, _) = timed(lambda: solve_least_squares(rows.X, rows.y), repeat=5)
    descents = {}
    for rate in (1.0, 0.2, 0.01):
        t_rate, (_, _, iters) = timed(lambda: zscore_gradient_descent(
            rows.X, rows.y, rate, 1_000_000, 0.0, loss_ls * (1 + 1e-6)))
        descents[rate] = (t_rate, iters)
    t_lsc, lsc = timed(lambda: LeastSquares().fit(series), repeat=3)
    t_oe, oe = timed(lambda: FreeRunLeastSquares().fit(series))

    print(f"least squares (paper's rows)  {t_ls * 1e3:9.1f} ms   loss {ls.loss_:.6g} K^2")
    print(f"Jorgensen et al. gradient descent{t_gd * 1e3:9.1f} ms   loss {gd.loss_:.6g} K^2 after {gd.n_iter_} iterations")
    print(f"  speed-up of least squares   {t_gd / t_ls:9.1f} x   (target: >= 100 x)")
    print(f"  largest parameter difference {agreement:.2e} (relative)")
    print("solvers alone on the same rows (to the same loss, within 1e-6):")
    print(f"  least squares (normal equations) {t_solve_ls * 1e3:8.2f} ms")
    for rate, (t_rate, iters) in descents.items():
        print(f"  gradient descent, alpha = {rate:<5} {t_rate * 1e3:8.1f} ms  {iters:6d} iterations"
              f"  ratio {t_rate / t_solve_ls:8.1f} x")
    print(f"least squares (consistent)    {t_lsc * 1e3:9.1f} ms")
    print(f"output error                  {t_oe * 1e3:9.1f} ms   {oe.optimizer_result_.nfev} function evaluations")
    for name, value in TRUE.items():
        print(f"  {name:26s} true {value:9.4g}  paper {gd.params_[name]:9.4g}  consistent LS {lsc.params_[name]:9.4g}"
              f"  output error {oe.params_[name]:9.4g}")

    with tempfile.TemporaryDirectory() as tmp:
        path = log.write(Path(tmp) / "million.parquet")
        exe = Path(sys.executable).parent / "thermolimb"
        start = time.perf_counter()
        subprocess.run([str(exe), "fit", str(path), "--json", "--quiet"], check=True, capture_output=True)
        t_cli = time.perf_counter() - start
        peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
    print(f"thermolimb fit on {series.n} samples: {t_cli:.2f} s wall, peak memory {peak_mb:.0f} MB "
          f"(target: a few seconds, < 1024 MB)")

    record = {"samples": series.n, "least_squares_s": t_ls, "jorgensen_gd_s": t_gd, "speedup": t_gd / t_ls,
              "jorgensen_gd_iterations": gd.n_iter_, "max_param_rel_diff": agreement, "output_error_s": t_oe,
              "solve_only_speedup": {str(rate): t / t_solve_ls for rate, (t, _) in descents.items()},
              "cli_fit_s": t_cli, "cli_peak_MB": peak_mb}
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
