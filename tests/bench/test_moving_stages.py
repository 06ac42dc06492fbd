"""bench.moving_stages: a few tiny frames at full resolution and upsampled, every stage of each
timed, the stages within the frame, and the timing wrappers gone after the run."""

from __future__ import annotations

import json

import pytest

from bench import moving_stages
from wgputrace.render.svgf_filter import VarianceGuidedFilter

pytestmark = pytest.mark.gpu


def test_every_stage_of_a_few_tiny_frames_is_timed(tmp_path):
    filter_method = VarianceGuidedFilter.filter
    argv = ["--scenes", "cornell", "--factors", "1", "4", "--size", "16x12", "--frames", "3", "--warm-up", "1"]
    assert moving_stages.main([*argv, "--out", str(tmp_path)]) == 0
    assert VarianceGuidedFilter.filter is filter_method, "the timing wrappers are removed after the run"
    (path,) = tmp_path.glob("moving_stages_*.json")
    factors = json.loads(path.read_text())["scenes"]["cornell"]
    expected = {"1": set(moving_stages.STAGES) - {"antialiasing"}, "4": set(moving_stages.STAGES)}
    for factor, stages in expected.items():
        medians = factors[factor]["median_ms"]
        assert set(medians) == stages | {"frame"}
        assert all(medians[stage] > 0.0 for stage in stages)
        # the stages run one after another within the frame
        assert sum(medians[stage] for stage in stages) <= medians["frame"] * 1.05
