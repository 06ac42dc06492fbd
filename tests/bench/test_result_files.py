"""bench.result_files: every result file carries the same metadata and the picture's settings."""

from __future__ import annotations

import json

import pytest

from bench.provenance import Run
from bench.result_files import SETTINGS_KEYS, write_result

SETTINGS = {"scene": "cornell", "width": 8, "height": 4, "spp": 2, "max_depth": 9}
METADATA_KEYS = ("benchmark", "git_revision", "adapter", "environment", "load_average_at_write")


@pytest.mark.gpu  # the adapter's description comes from the device
def test_a_result_carries_metadata_and_settings(gpu_context, tmp_path):
    plotted = {}

    def plot(path, result):
        plotted.update(result)
        path.write_bytes(b"png")

    paths = write_result("example", {**SETTINGS, "value": 1.5}, out=tmp_path, plot=plot, run=Run())
    written = json.loads(paths["json"].read_text())
    assert all(key in written for key in METADATA_KEYS)
    assert written["benchmark"] == "example" and written["value"] == 1.5
    assert {key: written[key] for key in SETTINGS_KEYS} == SETTINGS
    assert written["adapter"]["adapter"] and written["environment"]["wgpu"]
    # what lavapipe's speed depends on: the driver's version and the processor
    assert written["environment"]["driver"] == written["adapter"]["description"] and written["environment"]["cpu"]
    assert written["wall_seconds"] >= 0 and len(written["load_average_before_after"]) == 2
    # the command as typed in the checkout: no folder of this machine
    assert not any(word.startswith("/") for word in written["environment"]["command"].split())
    # the file is named by benchmark and adapter, and the chart sees what the file holds
    assert paths["json"].name.startswith("example_") and paths["png"].with_suffix(".json") == paths["json"]
    assert plotted == written


@pytest.mark.gpu
def test_a_result_without_its_settings_is_refused(gpu_context, tmp_path):
    with pytest.raises(ValueError, match="lacks spp, max_depth"):
        write_result("example", {"scene": "cornell", "width": 8, "height": 4}, out=tmp_path)
    assert not list(tmp_path.iterdir())
