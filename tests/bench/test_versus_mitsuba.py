"""bench.versus_mitsuba's time-to-equal-RMSE arithmetic on synthetic curves (no Mitsuba needed)."""

from __future__ import annotations

import numpy as np
import pytest

from bench.error_curves import checkpoints
from bench.versus_mitsuba import MITSUBA, OURS, time_to_equal_rmse

# Exact power laws: only floating-point rounding separates the fit from the truth.
RTOL = 1e-9


def curve(seconds_per_spp: float, rmse_at_one_spp: float, max_spp: int = 256) -> dict:
    """An unbiased renderer: time grows with spp, RMSE falls as spp^-1/2."""
    spp = np.array(checkpoints(max_spp), dtype=np.float64)
    return {
        "spp": spp.tolist(),
        "seconds": (seconds_per_spp * spp).tolist(),
        "rmse": (rmse_at_one_spp / np.sqrt(spp)).tolist(),
    }


@pytest.mark.parametrize(("ours", "theirs"), [((2.0, 0.5), (0.25, 0.7)), ((0.1, 1.0), (0.4, 0.6))])
def test_ratio_of_times_to_a_common_rmse(ours, theirs):
    result = time_to_equal_rmse(curve(*ours), curve(*theirs))
    # time to reach RMSE L is seconds_per_spp * (rmse_at_one_spp / L)^2, so the ratio holds at any L
    expected = (ours[0] * ours[1] ** 2) / (theirs[0] * theirs[1] ** 2)
    assert result["ratio"] == pytest.approx(expected, rel=RTOL)
    # the common level is the larger final RMSE: both curves reach it inside their measured range
    final = max(ours[1], theirs[1]) / np.sqrt(256)
    assert result["rmse"] == pytest.approx(final, rel=RTOL)
    for name, (seconds_per_spp, rmse_at_one_spp) in ((OURS, ours), (MITSUBA, theirs)):
        assert result["seconds"][name] == pytest.approx(seconds_per_spp * (rmse_at_one_spp / final) ** 2, rel=RTOL)
        assert result["fitted_slope_rmse_vs_seconds"][name] == pytest.approx(-0.5, rel=RTOL)
