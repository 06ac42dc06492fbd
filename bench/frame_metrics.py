"""Errors of a moving picture as it is shown, frame by frame, against references that are noisy
themselves: PSNR, FLIP and temporal instability of the displayed sRGB values.

A displayed picture is what the viewer shows at its default tone (`wgputrace.view.present.Tone()`:
exposure 0, the `clip` curve, sRGB, 8 bits): `displayed`. A reference is the mean of two
independent half-references A and B; its own noise in the display, per pixel and channel, has a
variance of about E[(A - B)^2] / 4 (each half has twice the full reference's variance), so
`reference_noise` estimates it and the squared errors below subtract it (Var(test - reference) =
Var(test - truth) + Var(reference) for independent renders).
"""

from __future__ import annotations

import importlib.util
import math

import numpy as np

from wgputrace.image_io import srgb8, tonemap
from wgputrace.view.present import Tone

# The viewer's default tone, which every displayed picture here is shown with.
DISPLAY_TONE = Tone()
# The least mean squared error a display of 8-bit steps can resolve (uniform rounding error,
# (1/255)^2 / 12): a noise-corrected error below it is reported as this, PSNR ~59 dB.
DISPLAY_QUANTIZATION_MSE = (1.0 / 255.0) ** 2 / 12.0
# FLIP's viewing condition: its default, a 0.7 m distance from a 0.7 m wide 3840-pixel monitor.
FLIP_PIXELS_PER_DEGREE = 67.0
FLIP_INSTALL_HINT = 'pip install "wgputrace[bench]" (flip-evaluator, which has wheels for x86-64 Linux)'


def flip_missing() -> str | None:
    """Why FLIP cannot be measured here (flip-evaluator is not installed), or None."""
    return None if importlib.util.find_spec("flip_evaluator") else f"flip-evaluator is missing: {FLIP_INSTALL_HINT}"


def displayed(linear: np.ndarray) -> np.ndarray:
    """float64 (H, W, 3) in [0, 1]: linear radiance as the viewer shows it at DISPLAY_TONE, in 8-bit steps."""
    return srgb8(tonemap(linear, DISPLAY_TONE.operator, DISPLAY_TONE.ev)) / 255.0


def reference_noise(half_a: np.ndarray, half_b: np.ndarray) -> float:
    """The mean variance of the displayed full reference's noise, from its two displayed halves."""
    return float(np.mean((half_a - half_b) ** 2) / 4.0)


def corrected_mse(shown: np.ndarray, reference: np.ndarray, noise: float) -> float:
    """The mean squared error of `shown` against the truth: against `reference` less its `noise`,
    at least DISPLAY_QUANTIZATION_MSE."""
    return max(float(np.mean((shown - reference) ** 2)) - noise, DISPLAY_QUANTIZATION_MSE)


def psnr(shown: np.ndarray, reference: np.ndarray, noise: float) -> float:
    """10 log10(1 / corrected_mse) in dB: the displayed values' peak is 1."""
    return 10.0 * math.log10(1.0 / corrected_mse(shown, reference, noise))


def flip(shown: np.ndarray, reference: np.ndarray) -> float:
    """Mean LDR-FLIP (Andersson et al. 2020; NVIDIA's `flip-evaluator`) of two displayed pictures,
    0 (equal) to 1. The reference's own noise is not subtracted: FLIP has no such decomposition,
    so the reference's noise sets a floor under every mode's FLIP alike."""
    import flip_evaluator

    _, mean, _ = flip_evaluator.evaluate(
        np.ascontiguousarray(reference, np.float32),
        np.ascontiguousarray(shown, np.float32),
        "LDR",
        applyMagma=False,
        parameters={"ppd": FLIP_PIXELS_PER_DEGREE},
    )
    return float(mean)


def instability(
    shown: np.ndarray,
    previous_shown: np.ndarray,
    reference: np.ndarray,
    previous_reference: np.ndarray,
    noise: float,
    previous_noise: float,
) -> float:
    """The root mean square of the displayed picture's change from the previous frame beyond the
    reference's own change: sqrt(mean((dShown - dReference)^2) - noise - previous_noise), where the
    two frames' references are independent renders (their noise adds), and 0 where that is negative."""
    change = (shown - previous_shown) - (reference - previous_reference)
    return math.sqrt(max(float(np.mean(change**2)) - noise - previous_noise, 0.0))
