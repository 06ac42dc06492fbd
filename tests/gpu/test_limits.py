"""Limits checked before anything is allocated (`check_image_size`, `check_scene_size`): images and scenes just within
each of the device's limits pass and just beyond are refused, with a message naming the limit, the
value asked for and the largest allowed; the host-memory model holds what the code really holds;
the bound of 4-wide BVH records holds for trees built, lopsided ones too."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Emitter, Renderer, Scene, Shape, default_scene
from wgputrace.bvh import build_bvh
from wgputrace.bvh.wide import BUILD_MAX_DEPTH, collapse
from wgputrace.gpu.bindings import IMAGE_WORKGROUP
from wgputrace.gpu.device import DeviceLimitError
from wgputrace.gpu.layout import BVH_NODE, LIGHT, MATERIAL, TRIANGLE, WIDE_BVH_NODE
from wgputrace.gpu.texels import most_texel_records
from wgputrace.render import limits
from wgputrace.render.limits import (
    HOST_MEMORY,
    PIXEL_BUFFER_LIMITS,
    PIXEL_BUFFERS,
    SceneCounts,
    check_image_size,
    check_scene_counts,
    check_scene_size,
    host_bytes,
    host_steps,
    largest_square_image,
    scene_counts,
    wide_record_bound,
)
from wgputrace.render.rng_seed import pixel_rng_states
from wgputrace.render.scene_mirror import SceneMirror
from wgputrace.testing.memory import TRACEMALLOC_SLACK_BYTES, traced_peak

# Rows of the images probed against the per-pixel buffer limits: wide enough that the dispatch's
# workgroups never bind first, narrow enough that one more row is just above the limit.
PROBE_WIDTH = 2048
# Pixels of the images whose host memory is measured: large enough that bookkeeping is negligible.
MEASURED_PIXELS = 256 * 256
UNLIMITED = 2**62


def refused(context, width, height) -> str:
    with pytest.raises(DeviceLimitError) as error:
        check_image_size(context, width, height)
    message = str(error.value)
    assert "\n" not in message
    return message


def lift_all_but(context, monkeypatch, limit: str, limits_: tuple[str, ...]) -> None:
    """Make every one of `limits_` but `limit` unlimited for this test, so `limit` binds first."""
    for other in limits_:
        if other != limit:
            monkeypatch.setitem(context.device.limits, other, UNLIMITED)


@pytest.fixture
def no_host_check(monkeypatch):
    """Device limits alone: the host's memory unknown, so unchecked."""
    monkeypatch.setattr(limits, "available_host_memory", lambda: None)


def test_workgroups_per_dimension_just_within_and_beyond(gpu_context, no_host_check):
    workgroups = gpu_context.device.limits["max-compute-workgroups-per-dimension"]
    widest, tallest = (group * workgroups for group in IMAGE_WORKGROUP)
    check_image_size(gpu_context, widest, 1)
    check_image_size(gpu_context, 1, tallest)
    for width, height in ((widest + 1, 1), (1, tallest + 1)):
        message = refused(gpu_context, width, height)
        assert f"max-compute-workgroups-per-dimension = {workgroups + 1:,}" in message
        assert f"offers {workgroups:,}" in message


@pytest.mark.parametrize("limit", PIXEL_BUFFER_LIMITS)
def test_pixel_buffers_just_within_and_beyond(gpu_context, no_host_check, monkeypatch, limit):
    """Each limit on its own (the others lifted, the dispatch's too: on a GPU whose buffers may be
    larger than lavapipe's the probe's rows could outnumber its workgroups), probed where it binds."""
    lift_all_but(gpu_context, monkeypatch, limit, ("max-compute-workgroups-per-dimension", *PIXEL_BUFFER_LIMITS))
    allowed = gpu_context.device.limits[limit]
    label, record_bytes = max(PIXEL_BUFFERS.items(), key=lambda item: item[1])
    rows = allowed // record_bytes // PROBE_WIDTH
    check_image_size(gpu_context, PROBE_WIDTH, rows)
    message = refused(gpu_context, PROBE_WIDTH, rows + 1)
    assert f"buffer {label!r} needs {limit} = {PROBE_WIDTH * (rows + 1) * record_bytes:,}" in message
    assert f"offers {allowed:,}" in message


def test_host_memory_just_within_and_beyond(gpu_context, monkeypatch):
    width, height = 640, 480
    needed = host_bytes(gpu_context, width * height)
    monkeypatch.setattr(limits, "available_host_memory", lambda: needed)
    check_image_size(gpu_context, width, height)
    monkeypatch.setattr(limits, "available_host_memory", lambda: needed - 1)
    message = refused(gpu_context, width, height)
    assert f"{HOST_MEMORY} = {needed:,} but this host offers {needed - 1:,}" in message


def test_the_largest_square_named_fits_and_one_more_pixel_a_side_does_not(gpu_context, monkeypatch):
    # a host short of memory makes the host the binding limit, whatever the adapter
    monkeypatch.setattr(limits, "available_host_memory", lambda: host_bytes(gpu_context, 1000 * 1000))
    side = largest_square_image(gpu_context)
    check_image_size(gpu_context, side, side)
    message = refused(gpu_context, side + 1, side + 1)
    assert message.endswith(f"the largest square image it can render is {side:,}x{side:,}")
    assert side == 1000


def test_issue_size_is_refused_before_numpy_allocates(gpu_context):
    """The issue's 100000x100000 died in numpy asking for 74.5 GiB; now the check refuses it first."""
    message = refused(gpu_context, 100_000, 100_000)
    side = largest_square_image(gpu_context)
    assert f"the largest square image it can render is {side:,}x{side:,}" in message


def test_host_memory_is_read_from_meminfo():
    available = limits.available_host_memory()
    try:
        with open("/proc/meminfo") as meminfo:
            total = next(int(line.split()[1]) * 1024 for line in meminfo if line.startswith("MemTotal:"))
    except OSError:
        assert available is None
        return
    assert 0 < available <= total


def test_seeding_peak_is_within_the_model():
    peak = traced_peak(lambda: pixel_rng_states(1, MEASURED_PIXELS))
    assert peak <= host_steps(MEASURED_PIXELS)["seeding"] + TRACEMALLOC_SLACK_BYTES


def test_image_read_back_peak_is_within_the_model(gpu_context):
    """tracemalloc sees what Python and numpy hold during image(), not wgpu's staging memory: the
    model without one staging copy of the accumulation must still cover the measured peak."""
    lamp = Emitter("lamp", color=(1, 1, 1), emittance=1)
    triangle = np.array([[[0, 0, 1], [1, 0, 1], [0, 1, 1]]], np.float32)
    side = int(np.sqrt(MEASURED_PIXELS))
    renderer = Renderer(Scene([Shape("lamp", triangle, lamp)]), side, side)
    renderer.image()  # the first read-back also sets up wgpu-py's own state, a quarter of a MB
    peak = traced_peak(renderer.image)
    staging = side * side * PIXEL_BUFFERS["accumulation"]
    assert peak <= max(host_steps(side * side).values()) - staging + TRACEMALLOC_SLACK_BYTES


def counts(**changed: int) -> SceneCounts:
    one_of_each = {"triangles": 1, "shapes": 1, "materials": 1, "emissive_triangles": 0}
    return SceneCounts(**{**one_of_each, **changed})


def scene_refused(context, scene_counts_: SceneCounts, acceleration: str = "bvh") -> str:
    with pytest.raises(DeviceLimitError) as error:
        check_scene_counts(context, scene_counts_, acceleration)
    return str(error.value)


def test_triangles_just_within_and_beyond(gpu_context):
    most = most_texel_records(gpu_context, TRIANGLE.dtype)
    check_scene_counts(gpu_context, counts(triangles=most))
    message = scene_refused(gpu_context, counts(triangles=most + 1))
    assert "texture 'triangles'" in message and "max-texture-dimension-2d" in message
    assert f"offers {gpu_context.device.limits['max-texture-dimension-2d']:,} ({most:,} records at most)" in message
    # the BVH's records fit wherever the triangles do, so its texture never refuses a scene first
    assert wide_record_bound(most) <= most_texel_records(gpu_context, WIDE_BVH_NODE.dtype)


# (SceneCounts field, buffer label, record) kept in storage buffers; the flat list's boxes count shapes
STORAGE_RECORDS = [
    ("materials", "materials", MATERIAL, "bvh"),
    ("emissive_triangles", "lights", LIGHT, "bvh"),
    ("shapes", "bvh nodes", BVH_NODE, "flat"),
]


@pytest.mark.parametrize("limit", PIXEL_BUFFER_LIMITS)
@pytest.mark.parametrize(
    ("field", "label", "record", "acceleration"), STORAGE_RECORDS, ids=[r[1] for r in STORAGE_RECORDS]
)
def test_storage_records_just_within_and_beyond(gpu_context, monkeypatch, limit, field, label, record, acceleration):
    lift_all_but(gpu_context, monkeypatch, limit, PIXEL_BUFFER_LIMITS)
    most = gpu_context.device.limits[limit] // record.size
    check_scene_counts(gpu_context, counts(**{field: most}), acceleration)
    message = scene_refused(gpu_context, counts(**{field: most + 1}), acceleration)
    assert f"buffer {label!r} ({most + 1:,} records of {record.size} B) needs {limit}" in message
    assert f"({most:,} records at most)" in message


def test_scene_counts_bound_the_records_the_renderer_builds(gpu_context):
    scene = default_scene()
    scene_counts_ = scene_counts(scene)
    mirror = SceneMirror(scene, "bvh")
    assert scene_counts_.triangles == len(mirror.triangles)
    assert scene_counts_.materials == len(mirror.materials)
    assert scene_counts_.emissive_triangles >= mirror.lights.count > 0
    assert len(mirror.nodes) <= wide_record_bound(scene_counts_.triangles)
    check_scene_size(gpu_context, scene)


def lopsided(count: int) -> np.ndarray:
    """Triangles at x = 2^k, each a hundredth of its distance across: every split peels one off,
    the deepest and narrowest tree."""
    corners = np.array([[1, 0, 0], [1.01, 0, 0], [1, 0.01, 0]])
    return (2.0 ** np.arange(count)[:, None, None] * corners).astype(np.float32)


def clusters_of_five(rng, count: int) -> np.ndarray:
    """Clusters of five nearly coincident triangles: nodes of five split into leaves of 1 and 4."""
    centres = np.repeat(rng.uniform(-100, 100, (count // 5 + 1, 3)), 5, axis=0)[:count]
    corners = np.array([[0, 0, 0], [0.01, 0, 0], [0, 0.01, 0]])
    return (centres[:, None, :] + rng.uniform(0, 1e-3, (count, 1, 3)) + corners).astype(np.float32)


@pytest.mark.parametrize("count", [1, 4, 5, 6, 9, 13, 100, 1000])
def test_wide_record_bound_holds_for_built_trees(rng, count):
    soups = {
        "random": rng.uniform(-1, 1, (count, 3, 3)).astype(np.float32),
        "lopsided": lopsided(min(count, 100)),
        "clusters": clusters_of_five(rng, count),
    }
    for name, vertices in soups.items():
        records = collapse(build_bvh(vertices, max_depth=BUILD_MAX_DEPTH)).record_count
        assert records <= wide_record_bound(len(vertices)), name


def test_flat_list_nodes_count_shapes():
    grey = Diffuse("grey")
    shapes = [Shape(f"s{k}", np.eye(3, dtype=np.float32)[None] + k, grey) for k in range(3)]
    scene = Scene(shapes)
    assert scene_counts(scene).shapes == len(SceneMirror(scene, "flat").nodes)


def test_a_map_larger_than_the_adapter_holds_is_downscaled_with_a_warning(gpu_context, monkeypatch):
    from wgputrace import Environment
    from wgputrace.scene.lights.environment import EnvironmentWarning

    side = 64
    monkeypatch.setitem(gpu_context.device.limits, "max-texture-dimension-2d", side)
    scene = default_scene()
    texels = np.random.default_rng(3).uniform(0.0, 2.0, (40, 200, 3)).astype(np.float32)
    scene.environment = Environment(texels=texels)
    with pytest.warns(EnvironmentWarning, match="200x40 map downscaled"):
        renderer = Renderer(scene, 8, 8)
    width, height = scene.environment.size
    assert width <= side and height <= side
    assert scene.environment.texels.mean() == pytest.approx(texels.mean(), rel=0.05)
    renderer.render(1)
    assert np.isfinite(renderer.image()).all()
    # a map assigned later is fitted at the next update too
    scene.environment = Environment(texels=texels)
    with pytest.warns(EnvironmentWarning):
        renderer.render(1)
    assert scene.environment.size[0] <= side


def test_smooth_shapes_need_the_shading_group(gpu_context, monkeypatch):
    from wgputrace import make_icosphere

    scene = Scene([make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 1, Emitter("lamp"), "ball", smooth=True)])
    check_scene_size(gpu_context, scene)
    monkeypatch.setitem(gpu_context.device.limits, "max-bind-groups", 5)
    with pytest.raises(DeviceLimitError, match="the shading group .* needs max-bind-groups = 6"):
        check_scene_size(gpu_context, scene)
    flat = Scene([make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 1, Emitter("lamp"), "ball")])
    check_scene_size(gpu_context, flat)
