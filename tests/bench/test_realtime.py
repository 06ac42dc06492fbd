"""bench.realtime: its measures against closed forms, the sample budget's arithmetic, the targets'
ratios, and a few frames at a tiny size through every mode (finite measures, the result written)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from bench import frame_metrics, realtime
from bench.realtime_modes import MODES, SampleBudget

SHAPE = (6, 8, 3)


def test_displayed_is_the_viewers_clip_and_srgb_in_8_bit_steps():
    linear = np.array([[[0.0, 1.0, 0.5], [2.0, -1.0, 0.0031308]]])
    # 0.5 -> 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 188 / 255; 0.0031308 * 12.92 = 0.0404 -> 10 / 255
    expected = np.array([[[0, 255, 188], [255, 0, 10]]]) / 255.0
    np.testing.assert_array_equal(frame_metrics.displayed(linear), expected)


def test_reference_noise_is_the_full_references_variance():
    # halves t + d and t - d: their mean is t, each half's noise d
    truth, deviation = np.full(SHAPE, 0.5), np.full(SHAPE, 0.1)
    noise = frame_metrics.reference_noise(truth + deviation, truth - deviation)
    assert noise == pytest.approx(0.01)


def test_psnr_of_a_known_error_with_and_without_the_references_noise():
    reference = np.full(SHAPE, 0.5)
    assert frame_metrics.psnr(reference + 0.1, reference, 0.0) == pytest.approx(20.0)
    # an error of sqrt(0.01 + 0.03) of which the reference's noise is 0.03: the picture's own is 0.1
    assert frame_metrics.psnr(reference + 0.2, reference, 0.03) == pytest.approx(20.0)


def test_psnr_of_an_exact_picture_is_the_displays_resolution():
    reference = np.full(SHAPE, 0.25)
    expected = 10.0 * math.log10(1.0 / frame_metrics.DISPLAY_QUANTIZATION_MSE)
    assert frame_metrics.psnr(reference, reference, 0.0) == pytest.approx(expected)
    assert frame_metrics.psnr(reference + 0.01, reference, 0.001) == pytest.approx(expected)


def test_instability_of_identical_frames_is_zero():
    frame = np.random.default_rng(1).random(SHAPE)
    reference = np.random.default_rng(2).random(SHAPE)
    assert frame_metrics.instability(frame, frame, reference, reference, 0.0, 0.0) == 0.0


def test_instability_follows_the_reference_and_subtracts_its_noise():
    rng = np.random.default_rng(3)
    previous, change = rng.random(SHAPE) * 0.5, rng.random(SHAPE) * 0.3
    reference = rng.random(SHAPE)
    # the picture changes as the reference does: no instability
    assert frame_metrics.instability(
        previous + change, previous, reference + change, reference, 0.0, 0.0
    ) == pytest.approx(0.0, abs=1e-12)
    # a flicker of 0.1 over a still reference, whose two frames' noise adds 0.002 + 0.002
    flicker = frame_metrics.instability(previous + 0.1, previous, reference, reference, 0.0, 0.0)
    assert flicker == pytest.approx(0.1)
    noisy = np.sqrt(0.1**2 + 0.004)
    assert frame_metrics.instability(previous + noisy, previous, reference, reference, 0.002, 0.002) == pytest.approx(
        0.1
    )


def test_flip_is_zero_for_equal_pictures_and_grows_with_the_error():
    pytest.importorskip("flip_evaluator")
    reference = np.random.default_rng(4).random((32, 32, 3))
    assert frame_metrics.flip(reference, reference) == 0.0
    small = frame_metrics.flip(np.clip(reference + 0.05, 0, 1), reference)
    large = frame_metrics.flip(np.clip(reference + 0.3, 0, 1), reference)
    assert 0.0 < small < large <= 1.0


def test_sample_budget_fits_the_samples_in_what_is_left_of_the_budget():
    budget = SampleBudget(0.05)
    assert budget.spp() == 1  # nothing measured yet
    budget.measured(spp=2, trace_seconds=0.02, frame_seconds=0.03)  # 10 ms a sample, 10 ms fixed
    assert budget.spp() == 4
    budget = SampleBudget(0.05)
    budget.measured(spp=1, trace_seconds=0.2, frame_seconds=0.3)
    assert budget.spp() == 1  # over the budget, still one sample


def test_targets_are_ratios_to_the_preview_and_need_the_budget():
    def means(flip, psnr, instability, over):
        return {
            "mean_flip": flip,
            "mean_psnr": psnr,
            "mean_instability": instability,
            "median_seconds_over_budget": over,
        }

    summaries = {
        "preview": means(0.4, 15.0, 0.2, 0.9),
        "temporal": means(0.1, 22.0, 0.05, 0.8),
        "temporal+svgf": means(0.1, 22.0, 0.05, 1.5),
        "temporal+svgf+oidn": means(0.3, 16.0, 0.15, 0.5),
    }
    targets = realtime.targets(summaries)
    assert set(targets) == {"temporal", "temporal+svgf", "temporal+svgf+oidn"}
    assert targets["temporal"]["flip_ratio"] == pytest.approx(4.0)
    assert targets["temporal"]["psnr_gain_db"] == pytest.approx(7.0)
    assert targets["temporal"]["instability_ratio"] == pytest.approx(4.0)
    assert targets["temporal"]["passed"]
    # as good, but over the budget
    assert all(targets["temporal+svgf"]["met"].values()) and not targets["temporal+svgf"]["passed"]
    assert not any(targets["temporal+svgf+oidn"]["met"].values())


@pytest.mark.gpu
def test_a_few_tiny_frames_through_every_mode_write_finite_measures(tmp_path):
    pytest.importorskip("flip_evaluator")
    from wgputrace.denoise import denoiser_available

    modes = [name for name in MODES if denoiser_available() or "oidn" not in name]
    arguments = ["--size", "24x16", "--frames", "3", "--reference-spp", "2", "--budgets", "1", "2"]
    arguments += ["--sweep-frames", "2", "--scenes", "moving", "--modes", *modes]
    assert realtime.main([*arguments, "--out", str(tmp_path), "--cache", str(tmp_path / "cache")]) == 0
    (path,) = tmp_path.glob("realtime_24x16_*.json")
    result = json.loads(path.read_text())
    first, second = result["scenes"]["moving"]["runs"]
    assert len(second["modes"]["preview"]["frames"]) == 2
    for name in modes:
        frames = first["modes"][name]["frames"]
        assert [frame["frame"] for frame in frames] == [0, 1, 2]
        assert frames[0]["instability"] is None
        for frame in frames:
            assert math.isfinite(frame["psnr"]) and 0.0 <= frame["flip"] <= 1.0 and frame["spp"] >= 1
            assert frame["seconds"] > 0
        assert all(math.isfinite(frame["instability"]) for frame in frames[1:])
    # a fixed factor traces one pixel of each of its blocks
    assert all(frame["traced"] == [6, 4] for frame in first["modes"]["upsampled4"]["frames"])
    # two-sample references' halves differ: their noise sets a FLIP floor above 0
    assert 0.0 < first["reference_halves_flip"] <= 1.0
    assert set(result["scenes"]["moving"]["targets"]) == set(modes) - {"preview"}
    assert result["scenes"]["moving"]["references_rendered"] == 3
    assert len(list((tmp_path / "cache").glob("moving_*.npz"))) == 3
    assert len(list(tmp_path.glob("realtime_24x16_*.png"))) == 2
