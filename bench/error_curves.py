"""Error against a reference, and how it falls with samples and time: per-image MSEs with the
reference's variance taken out, the checkpoints a progressive render is read at, and power laws
fitted to the curves."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

# relative MSE = mean((ours - reference)^2 / (reference^2 + this)): dark pixels do not dominate
RELATIVE_MSE_EPSILON = 1e-2
# Power laws are fitted from this many samples per pixel on: the first few checkpoints are
# dominated by the odd first sample and by what a single image happens to hit.
FIT_MIN_SPP = 4


def errors(image: np.ndarray, reference_mean: np.ndarray, reference_variance: np.ndarray) -> dict:
    """Our MSE and relative MSE with the reference's own variance taken out, and the raw MSE.

    Ours and the reference are independent, so E[(ours - reference)^2] = our MSE + the reference's
    variance: subtracted, what remains is our error alone."""
    squared = (image.astype(np.float64) - reference_mean) ** 2
    mse = float(np.mean(squared - reference_variance))
    relative = float(np.mean((squared - reference_variance) / (reference_mean**2 + RELATIVE_MSE_EPSILON)))
    return {"rmse": float(np.sqrt(max(mse, 0.0))), "relative_mse": relative, "raw_mse": float(np.mean(squared))}


def checkpoints(max_spp: int) -> list[int]:
    """1, 2, 4, ... max_spp: where a progressive render is read back."""
    return [1 << k for k in range(max_spp.bit_length()) if 1 << k <= max_spp]


def fit_slope(x: Sequence[float], y: Sequence[float]) -> float:
    """Least-squares slope of log y against log x (positive values only)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    keep = (x > 0) & (y > 0)
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def curves(rows: list[dict]) -> dict:
    """Per scene and integrator ("scene/integrator"): per checkpoint the MSEs averaged over runs,
    the median time, and the slopes of the log-log curves from FIT_MIN_SPP on."""
    result = {}
    for key in dict.fromkeys((row["scene"], row["integrator"]) for row in rows):
        mine = [row for row in rows if (row["scene"], row["integrator"]) == key]
        spp = sorted({row["spp"] for row in mine})
        at = {s: [row for row in mine if row["spp"] == s] for s in spp}
        rmse = [float(np.sqrt(max(np.mean([r["rmse"] ** 2 for r in at[s]]), 0.0))) for s in spp]
        relative = [float(np.mean([r["relative_mse"] for r in at[s]])) for s in spp]
        seconds = [float(np.median([r["seconds"] for r in at[s]])) for s in spp]
        fit = [i for i, s in enumerate(spp) if s >= FIT_MIN_SPP]

        def pick(values, indices=fit):
            return [values[i] for i in indices]

        result[f"{key[0]}/{key[1]}"] = {
            "scene": key[0],
            "integrator": key[1],
            "spp": spp,
            "seconds": seconds,
            "rmse": rmse,
            "relative_mse": relative,
            "slope_rmse_vs_spp": fit_slope(pick(spp), pick(rmse)),
            "slope_rmse_vs_seconds": fit_slope(pick(seconds), pick(rmse)),
            "slope_relative_mse_vs_spp": fit_slope(pick(spp), pick(relative)),
            # efficiency: 1 / (relative MSE x seconds) at the last checkpoint
            "efficiency": 1.0 / (relative[-1] * seconds[-1]) if relative[-1] > 0 else None,
        }
    return result


def fit_power_law(curve: dict, metric: str) -> tuple[float, float]:
    """Slope and intercept of log `metric` against log seconds over the checkpoints from FIT_MIN_SPP on."""
    keep = [i for i, spp in enumerate(curve["spp"]) if spp >= FIT_MIN_SPP]
    log_seconds = np.log([curve["seconds"][i] for i in keep])
    log_error = np.log([max(curve[metric][i], np.finfo(float).tiny) for i in keep])
    slope, intercept = np.polyfit(log_seconds, log_error, 1)
    return float(slope), float(intercept)


def error_at(slope: float, intercept: float, seconds: float) -> float:
    """The power law log error = intercept + slope log seconds at `seconds`."""
    return float(np.exp(intercept + slope * np.log(seconds)))


def seconds_to_reach(slope: float, intercept: float, error: float) -> float:
    """Where the power law log error = intercept + slope log seconds reaches `error`."""
    return float(np.exp((np.log(error) - intercept) / slope))
