"""bench.restir_frames end to end at a tiny setting: the street walk and the Cornell box through a
few frames of every mode, finite measures, the targets as ratios of the modes' mean FLIP."""

from __future__ import annotations

import json
import math

import pytest

from bench import restir_frames

pytestmark = pytest.mark.gpu


def test_a_few_tiny_frames_of_every_mode_file_the_targets(tmp_path, capsys):
    modes = ["nee", "mis", "restir", "restir-t20"]
    arguments = ["--scenes", "street", "cornell", "--modes", *modes, "--frames", "2", "--size", "24x16"]
    arguments += ["--reference-spp", "2", "--out", str(tmp_path), "--cache", str(tmp_path / "cache")]
    assert restir_frames.main(arguments) == 0
    (path,) = tmp_path.glob("restir_frames_*.json")
    result = json.loads(path.read_text())
    summaries = {scene: entry["summary"] for scene, entry in result["scenes"].items()}
    for scene in ("street", "cornell"):
        for mode in modes:
            frames = result["scenes"][scene]["modes"][mode]["frames"]
            assert [frame["frame"] for frame in frames] == [0, 1]
            assert all(0.0 <= frame["flip"] <= 1.0 and math.isfinite(frame["psnr"]) for frame in frames)
    street = summaries["street"]["nee"]["mean_flip"] / summaries["street"]["restir"]["mean_flip"]
    assert result["measured"]["street_restir_flip_ratio_over_nee"] == pytest.approx(street)
    assert result["met"]["street_restir_flip_ratio_over_nee"] == (street >= 2.0)
    assert len(list(tmp_path.glob("restir_frames*.png"))) == 2
    assert "street_restir_flip_ratio_over_nee" in capsys.readouterr().out
