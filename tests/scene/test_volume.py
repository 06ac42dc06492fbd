"""Absorption inside materials (`volume`): glTF's attenuation colour and distance as sigma_a, the
parameters' checks on Glass and Principled, their GPU records and their Mitsuba 3 medium."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wgputrace.render.scene_records import material_records
from wgputrace.scene import Diffuse, Glass, MaterialError, Principled
from wgputrace.scene.materials.volume import (
    ABSORPTION_MAX,
    MITSUBA_SIGMA_MIN_RELATIVE,
    absorption_coefficients,
    mitsuba_medium,
)


def test_sigma_a_is_minus_log_color_over_distance():
    sigma = absorption_coefficients((0.5, 0.25, 1.0), 2.0)
    np.testing.assert_allclose(sigma, [math.log(2) / 2, math.log(4) / 2, 0.0], rtol=1e-15)
    # after attenuation_distance, white light has attenuation_color
    np.testing.assert_allclose(np.exp(-np.array(sigma) * 2.0), [0.5, 0.25, 1.0], rtol=1e-15)


def test_a_zero_channel_absorbs_everything_but_stays_finite():
    sigma = absorption_coefficients((0.0, 0.5, 1.0), 1.0)
    assert sigma[0] == ABSORPTION_MAX and np.isfinite(np.float32(sigma[0]))
    assert np.float32(sigma[0]) * np.float32(0.0) == 0.0  # never inf x 0 = NaN on the GPU
    assert absorption_coefficients((0.0, 0.0, 0.0), 1e-30) == (ABSORPTION_MAX,) * 3


def test_an_infinite_distance_absorbs_nothing():
    assert absorption_coefficients((0.1, 0.5, 1.0), math.inf) == (0.0, 0.0, 0.0)
    assert Glass("clear").absorption() == (0.0, 0.0, 0.0)


def test_glass_and_transmitting_principled_absorb_opaque_principled_does_not():
    attenuation = {"attenuation_color": (0.5, 0.5, 0.5), "attenuation_distance": 1.0}
    expected = pytest.approx((math.log(2),) * 3)
    assert Glass("g", **attenuation).absorption() == expected
    assert Principled("p", spec_trans=0.5, **attenuation).absorption() == expected
    # no light goes inside a Principled without transmission; its back is not an inside
    assert Principled("p", spec_trans=0.0, **attenuation).absorption() == (0.0, 0.0, 0.0)
    assert Diffuse("d").absorption() == (0.0, 0.0, 0.0)


def test_records_carry_sigma_a_and_zero_elsewhere():
    glass = Glass("g", attenuation_color=(0.5, 1.0, 0.25), attenuation_distance=0.5)
    records = material_records([glass, Diffuse("d")])
    np.testing.assert_allclose(records["absorption"][0], [2 * math.log(2), 0.0, 2 * math.log(4)], rtol=1e-6)
    assert not records["absorption"][1].any()


@pytest.mark.parametrize("cls", [Glass, Principled])
@pytest.mark.parametrize(
    "parameter, value, message",
    [
        ("attenuation_distance", 0.0, r"attenuation_distance must be > 0 \(inf: no absorption\), got 0.0"),
        ("attenuation_distance", -2, r"attenuation_distance must be > 0 \(inf: no absorption\), got -2"),
        ("attenuation_distance", math.nan, r"attenuation_distance must be > 0 \(inf: no absorption\), got nan"),
        ("attenuation_distance", "far", r"attenuation_distance must be > 0 \(inf: no absorption\), got 'far'"),
        ("attenuation_color", (0.5, 1.5, 0.5), r"attenuation_color must be <= 1.0"),
        ("attenuation_color", (0.5, -0.5, 0.5), r"attenuation_color must be finite and >= 0"),
        ("attenuation_color", (0.5, 0.5), r"attenuation_color must be 3 numbers"),
    ],
)
def test_bad_values_are_one_line_errors_naming_material_parameter_and_value(cls, parameter, value, message):
    with pytest.raises(MaterialError, match=rf"^material 'amber': {message}") as caught:
        cls("amber", **{parameter: value})
    assert caught.value.parameter == parameter and "\n" not in str(caught.value)
    material = cls("amber", spec_trans=1.0) if cls is Principled else cls("amber")
    with pytest.raises(MaterialError):
        setattr(material, parameter, value)
    assert material.absorption() == (0.0, 0.0, 0.0)  # the refused edit changed nothing


def test_mitsuba_medium_absorbs_only_at_sigma_a():
    sigma = absorption_coefficients((0.5, 0.25, 1.0), 2.0)
    medium = mitsuba_medium(sigma)
    assert (medium["type"], medium["albedo"]) == ("homogeneous", 0.0)
    scaled = np.array(medium["sigma_t"]["value"]) * medium["scale"]
    np.testing.assert_allclose(scaled[:2], sigma[:2], rtol=1e-15)
    # Mitsuba's volpath cannot take a channel of exactly 0: a negligible one instead
    assert 0.0 < scaled[2] <= MITSUBA_SIGMA_MIN_RELATIVE * max(sigma)
    assert mitsuba_medium((0.0, 0.0, 0.0)) is None
