"""bench.instancing on a small field (the billion-triangle run is the benchmark's, not the suite's):
its mesh has the triangles asked for, and the result records memory and time for both kinds."""

from __future__ import annotations

import json

import pytest

from bench import instancing

pytestmark = pytest.mark.gpu


def test_torus_mesh_has_the_triangles_asked_for():
    assert instancing.torus_mesh(100_000).triangle_count == 100_000


def test_a_small_run_records_memory_and_time_of_instanced_and_unique(tmp_path):
    arguments = ["--instances", "4", "--unique", "4", "--mesh-triangles", "200", "--size", "16x16"]
    assert instancing.main([*arguments, "--spp", "1", "--repeats", "1", "--out", str(tmp_path)]) == 0
    (path,) = tmp_path.glob("instancing_*.json")
    result = json.loads(path.read_text())
    instanced, unique = result["runs"]
    assert (instanced["kind"], unique["kind"]) == ("instanced", "unique")
    assert instanced["triangles_drawn"] == unique["triangles_drawn"] == 4 * result["mesh_triangles"]
    # the mesh stored once against four times
    assert instanced["triangles_stored"] < unique["triangles_stored"]
    assert all(run["seconds_per_sample"] > 0 and run["gpu_scene_bytes"] > 0 for run in result["runs"])
    assert list(tmp_path.glob("instancing_*.png"))
