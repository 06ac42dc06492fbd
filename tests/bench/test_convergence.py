"""bench.convergence's read-off on synthetic curves (no renderer, no Mitsuba): the fixed RMSE,
each strategy's time to reach it, efficiencies and the issue's ratios; and its pixel regions."""

from __future__ import annotations

import numpy as np
import pytest

from bench.convergence import BASELINE, MITSUBA, Strategy, away_from_lamp, gains, read_off, scene_spp
from bench.error_curves import checkpoints
from wgputrace import load_scene
from wgputrace.testing.references import load_reference

# Exact power laws: only floating-point rounding separates the fit from the truth.
RTOL = 1e-9
MAX_SPP = 256


def curve(scene: str, strategy: Strategy, seconds_per_spp: float, rmse_at_one_spp: float) -> dict:
    """An unbiased estimator: time grows with spp, RMSE falls as spp^-1/2."""
    spp = np.array(checkpoints(MAX_SPP), dtype=np.float64)
    return {
        "scene": scene,
        "integrator": strategy.label,
        "spp": spp.tolist(),
        "seconds": (seconds_per_spp * spp).tolist(),
        "rmse": (rmse_at_one_spp / np.sqrt(spp)).tolist(),
    }


# (seconds per spp, RMSE at 1 spp): efficiency 1 / (MSE x s) is 1 / (seconds_per_spp x rmse_1^2)
CURVES = {
    BASELINE: (1.0, 0.5),
    Strategy(BASELINE.integrator, "sobol" if BASELINE.sampler == "independent" else "independent"): (1.0, 0.25),
    Strategy("bdpt", BASELINE.sampler): (4.0, 0.05),
    Strategy(MITSUBA, "independent"): (0.125, 0.8),
    Strategy(MITSUBA, "multijitter"): (0.125, 0.6),
}


def efficiency(strategy: Strategy) -> float:
    seconds_per_spp, rmse = CURVES[strategy]
    return 1.0 / (seconds_per_spp * rmse**2)


def table() -> dict:
    made = [curve("scene", strategy, *parameters) for strategy, parameters in CURVES.items()]
    return read_off({f"scene/{c['integrator']}": c for c in made})


def test_every_strategy_reaches_the_fixed_rmse_read_off_its_curve():
    entry = table()["scene"]
    # what ours as shipped reaches at its last checkpoint
    level = CURVES[BASELINE][1] / np.sqrt(MAX_SPP)
    assert entry["fixed_rmse"] == pytest.approx(level, rel=RTOL)
    for strategy, (seconds_per_spp, rmse) in CURVES.items():
        row = entry["strategies"][strategy.label]
        # RMSE L is reached after (rmse / L)^2 samples per pixel
        spp = (rmse / level) ** 2
        assert row["seconds_to_fixed_rmse"] == pytest.approx(seconds_per_spp * spp, rel=RTOL)
        # read inside the fitted checkpoints (4 to MAX_SPP spp), or carried on past them
        assert row["extrapolated"] == (not 4 <= spp <= MAX_SPP)
        assert row["efficiency"] == pytest.approx(efficiency(strategy), rel=RTOL)
        assert row[f"efficiency_over_{BASELINE.label}"] == pytest.approx(
            efficiency(strategy) / efficiency(BASELINE), rel=RTOL
        )
        assert row["fitted_slope_rmse_vs_seconds"] == pytest.approx(-0.5, rel=RTOL)


def test_a_curve_that_does_not_fall_has_no_time_to_reach():
    flat = curve("scene", BASELINE, 1.0, 0.5) | {"rmse": [0.5] * len(checkpoints(MAX_SPP))}
    falling = curve("scene", Strategy("bdpt", BASELINE.sampler), 1.0, 0.5)
    entry = read_off({"a": flat, "b": falling})["scene"]
    assert entry["strategies"][BASELINE.label]["seconds_to_fixed_rmse"] is None
    assert entry["strategies"][falling["integrator"]][f"time_over_{BASELINE.label}"] is None


def test_without_ours_as_shipped_the_fixed_rmse_is_the_largest_final_one():
    others = {s: parameters for s, parameters in CURVES.items() if s != BASELINE}
    entry = read_off({s.label: curve("scene", s, *parameters) for s, parameters in others.items()})["scene"]
    assert entry["fixed_rmse"] == pytest.approx(max(rmse for _, rmse in others.values()) / np.sqrt(MAX_SPP), rel=RTOL)


def test_gains_are_the_issues_ratios():
    ratios = gains(table())["scene"]
    other = next(s for s in CURVES if s.integrator == BASELINE.integrator and s != BASELINE)
    sobol, independent = (other, BASELINE) if other.sampler == "sobol" else (BASELINE, other)
    assert ratios["sampler_efficiency_over_independent"][sobol.label] == pytest.approx(
        efficiency(sobol) / efficiency(independent), rel=RTOL
    )
    bdpt = Strategy("bdpt", BASELINE.sampler)
    assert ratios["bdpt_efficiency_over_mis"][BASELINE.sampler] == pytest.approx(
        efficiency(bdpt) / efficiency(Strategy("mis", BASELINE.sampler)), rel=RTOL
    )
    # time to a common RMSE scales as 1 / efficiency
    for sampler in ("independent", "multijitter"):
        assert ratios["ours_time_over_mitsuba"][sampler] == pytest.approx(
            efficiency(Strategy(MITSUBA, sampler)) / efficiency(BASELINE), rel=RTOL
        )


@pytest.mark.parametrize(
    ("max_spp", "size", "expected"), [(256, 128, 256), (256, 256, 64), (64, 256, 16), (256, 96, 256)]
)
def test_larger_images_stop_at_as_many_paths(max_spp, size, expected):
    assert scene_spp(max_spp, size, size) == expected


def test_away_from_lamp_leaves_out_the_lamp_pixels_and_little_else():
    mask = away_from_lamp(load_scene("tiny_light"), 128, 128)
    brightest = load_reference("tiny_light").estimate.mean.max(axis=-1)
    # the lamp's pixels are over a hundred times brighter than any other
    assert np.count_nonzero(~mask) <= 16
    assert brightest[~mask].max() > 100 * brightest[mask].max()
