"""Residual analysis in the manner of a system-identification toolbox.

For a model's free-run residual ``e = measured - simulated``:

* its autocorrelation with the white-noise band ``+-1.96 / sqrt(n)``;
* its cross-correlation at +- lags with candidate inputs (effort, effort^2,
  |velocity|, current, ambient, the neighbours' temperatures), each with
  Bartlett's band ``1.96 sqrt(sum_j rho_xx(j) rho_ee(j) / n)``, which stays
  valid when both the residual and the input are coloured (a thermal
  residual always is);
* where the fit is worst: RMSE while heating, cooling, moving fast, and hot.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...logs import ActuatorSeries

Z95 = 1.96


@dataclass(frozen=True)
class Correlation:
    """A correlation function with its 95 % band."""

    lags_s: np.ndarray
    values: np.ndarray
    band: float

    @property
    def peak(self) -> tuple[float, float]:
        """``(lag_s, value)`` of the largest absolute correlation."""
        k = int(np.argmax(np.abs(self.values)))
        return float(self.lags_s[k]), float(self.values[k])

    @property
    def significant(self) -> bool:
        return bool(np.max(np.abs(self.values)) > self.band)


@dataclass(frozen=True)
class ResidualAnalysis:
    time_s: np.ndarray
    residual_K: np.ndarray
    autocorrelation: Correlation
    cross: dict[str, Correlation]
    phase_rmse_K: dict[str, float]

    @property
    def structured(self) -> bool:
        """Whether the residual is not white: autocorrelation outside its band, or a significant
        cross-correlation."""
        return self.autocorrelation.significant or any(c.significant for c in self.cross.values())

    def to_json(self) -> dict:
        return {
            "rmse_K": float(np.sqrt(np.mean(self.residual_K**2))),
            "autocorrelation_significant": self.autocorrelation.significant,
            "cross_correlation": {
                name: {
                    "peak_lag_s": c.peak[0],
                    "peak": c.peak[1],
                    "band": c.band,
                    "significant": c.significant,
                }
                for name, c in self.cross.items()
            },
            "phase_rmse_K": self.phase_rmse_K,
        }


def _normalised(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, float) - np.mean(x)
    sd = np.std(x)
    return x / sd if sd > 0 else x


def _size(n: int, max_lag: int) -> int:
    from scipy import fft

    return fft.next_fast_len(n + min(max_lag, n - 1), real=True)


def spectrum(x: np.ndarray, max_lag: int) -> np.ndarray:
    """The FFT of the standardised ``x`` over the length :func:`cross_correlation` takes for ``max_lag``."""
    from scipy import fft

    return fft.rfft(_normalised(x), _size(np.shape(x)[0], max_lag))


def cross_correlation(x: np.ndarray, y: np.ndarray, max_lag: int,
                      spectra: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``r_xy(k) = mean(x_t y_{t+k})`` of the standardised series for ``k`` in ``[-max_lag, max_lag]``.

    By FFT over ``n + max_lag`` points (enough that the lags asked for do not wrap around), not the full
    correlation's ``2n``: half the memory and time on a long log.  ``spectra``: the two series'
    :func:`spectrum`, where the caller has them (one FFT per series, not two per pair: the same numbers, bit
    for bit)."""
    from scipy import fft

    n = np.shape(x)[0]
    lag, size = min(max_lag, n - 1), _size(n, max_lag)
    X, Y = spectra if spectra is not None else (spectrum(x, max_lag), spectrum(y, max_lag))
    product = np.conjugate(X)
    product *= Y
    circular = fft.irfft(product, size)  # index k: lag k; index size - k: lag -k
    del product
    lags = np.arange(-max_lag, max_lag + 1)
    r = np.where(np.abs(lags) <= lag, circular[lags % size], 0.0) / n
    return lags, r


def bartlett_band(x: np.ndarray, e: np.ndarray, max_lag: int, ree: np.ndarray | None = None,
                  spectrum_x: np.ndarray | None = None) -> float:
    """95 % band of a cross-correlation between two coloured series (Bartlett's formula); ``ree``: ``e``'s own
    correlation over the same lags, when the caller has it (one per residual, not one per input);
    ``spectrum_x``: ``x``'s :func:`spectrum`, likewise."""
    _, rxx = cross_correlation(x, x, max_lag, None if spectrum_x is None else (spectrum_x, spectrum_x))
    if ree is None:
        _, ree = cross_correlation(e, e, max_lag)
    variance = max(float(np.sum(rxx * ree)), 1.0) / x.size
    return Z95 * float(np.sqrt(variance))


def candidate_inputs(series: ActuatorSeries) -> dict[str, np.ndarray]:
    """The inputs a residual is checked against, by name (only those the log has)."""
    s = series.signals
    inputs = {"effort": s.effort, "effort^2": s.effort**2}
    if s.velocity is not None:
        inputs["|velocity|"] = np.abs(s.velocity)
    if s.current_A is not None:
        inputs["current^2"] = s.current_A**2
    if s.power_W is not None:
        inputs["power"] = s.power_W
    if s.ambient_C is not None and np.ptp(s.ambient_C) > 0:
        inputs["ambient"] = s.ambient_C
    if s.housing_C is not None:
        inputs["housing temperature"] = s.housing_C
    if s.neighbor_temperature_C is not None:
        for name, column in zip(s.neighbor_names, s.neighbor_temperature_C.T):
            inputs[f"temperature of {name}"] = column
    for name, column in s.extra.items():
        inputs[name if name not in inputs else f"extra.{name}"] = column
    return {k: v for k, v in inputs.items() if np.ptp(v) > 0}


def analyse_residuals(
    series: ActuatorSeries, simulated_C: np.ndarray, max_lag_s: float = 600.0
) -> ResidualAnalysis:
    """Analyse ``measured - simulated`` of one series (uniformly sampled or nearly so)."""
    e = series.temperature_C - simulated_C
    dt = series.median_dt_s
    max_lag = max(int(min(max_lag_s / dt, series.n // 4)), 1)
    E = spectrum(e, max_lag)  # each series' FFT once: 5 where there were 18 on a log of four inputs
    lags, acf = cross_correlation(e, e, max_lag, (E, E))
    keep = lags >= 0
    auto = Correlation(lags[keep] * dt, acf[keep], Z95 / np.sqrt(e.size))
    cross = {}
    for name, x in candidate_inputs(series).items():
        X = spectrum(x, max_lag)
        lags, r = cross_correlation(x, e, max_lag, (X, E))
        cross[name] = Correlation(lags * dt, r, bartlett_band(x, e, max_lag, acf, X))
    return ResidualAnalysis(series.time_s, e, auto, cross, phase_rmse(series, e))


def phase_rmse(series: ActuatorSeries, residual: np.ndarray) -> dict[str, float]:
    """RMSE while heating, cooling, moving fast and hot (top quartiles of rate, speed and temperature)."""
    T = series.temperature_C
    # a one-minute moving average, never longer than a tenth of the log
    window = int(np.clip(60.0 / series.median_dt_s, 1, max(series.n // 10, 1)))
    smooth = np.convolve(T, np.ones(window) / window, mode="same")
    rate = np.gradient(smooth, series.time_s)
    phases = {
        "heating": rate > np.quantile(rate, 0.75),
        "cooling": rate < np.quantile(rate, 0.25),
        "hot": T > np.quantile(T, 0.75),
        "cool": T < np.quantile(T, 0.25),
    }
    v = series.signals.velocity
    if v is not None and np.ptp(v) > 0:
        speed = np.abs(v)
        phases["fast motion"] = speed > np.quantile(speed, 0.75)
        phases["still"] = speed <= np.quantile(speed, 0.25)
    return {name: float(np.sqrt(np.mean(residual[m] ** 2))) for name, m in phases.items() if m.any()}
