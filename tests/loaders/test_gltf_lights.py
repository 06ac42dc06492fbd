"""glTF KHR_lights_punctual: each light type with its units and fields, placed by node transforms
(a node's world translation and -z), a light placed twice, glTF's defaults, `range` ignored, and
errors that name the file, the light's JSON path and the field; and a directional light rendered,
lighting the side its node's -z faces."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from wgputrace import SceneLoadError, load_scene, render
from wgputrace.scene import DirectionalLight, PointLight, SpotLight
from wgputrace.testing.gltf_files import BOX, BOX_INDICES, LIGHTS, gltf_document, light_node, with_lights, write_glb

GREY = 0.8  # the loader's albedo for a primitive without a material
RENDER_SIZE = 8
# 90 degrees about +x: the node's -z turns to +y (x, y, z, w as glTF writes quaternions)
QUARTER_TURN_ABOUT_X = [math.sin(math.pi / 4), 0.0, 0.0, math.cos(math.pi / 4)]


def lit_box(tmp_path, lights: list[dict], nodes: list[dict], name: str = "lit.glb"):
    document, blob = gltf_document([(BOX, BOX_INDICES, None)])
    return write_glb(tmp_path / name, with_lights(document, copy.deepcopy(lights), nodes), blob)


def test_each_type_with_its_fields_and_node_transform(tmp_path):
    nodes = [
        light_node(0, translation=[1, 2, 3]),
        light_node(1, translation=[0, -4, 0], rotation=QUARTER_TURN_ABOUT_X),
        light_node(2, rotation=QUARTER_TURN_ABOUT_X),
    ]
    point, spot, directional = load_scene(lit_box(tmp_path, LIGHTS, nodes)).lights
    assert isinstance(point, PointLight) and isinstance(spot, SpotLight) and isinstance(directional, DirectionalLight)
    np.testing.assert_allclose(point.position, [1, 2, 3])
    assert point.intensity == 40 and point.color == pytest.approx((1, 0.9, 0.8))  # candela 1:1, range ignored
    np.testing.assert_allclose(spot.position, [0, -4, 0], atol=1e-12)
    np.testing.assert_allclose(spot.direction, [0, 1, 0], atol=1e-12)  # the node's -z, turned
    assert spot.intensity == 200
    assert spot.beam_width_degrees == pytest.approx(math.degrees(0.3))
    assert spot.cutoff_angle_degrees == pytest.approx(math.degrees(0.6))
    np.testing.assert_allclose(directional.direction, [0, 1, 0], atol=1e-12)
    assert directional.irradiance == 3 and directional.color == pytest.approx((1, 1, 0.9))  # lux 1:1


def test_a_light_placed_by_two_nodes_one_through_a_scaled_parent(tmp_path):
    document, blob = gltf_document([(BOX, BOX_INDICES, None)])
    parent = {"translation": [0, 0, -2], "rotation": QUARTER_TURN_ABOUT_X, "scale": [3, 3, 3], "children": [3]}
    with_lights(document, [LIGHTS[1]], [light_node(0, translation=[5, 0, 0]), parent])
    document["nodes"].append(light_node(0, translation=[1, 0, 0]))  # node 3, the parent's child
    first, second = load_scene(write_glb(tmp_path / "twice.glb", document, blob)).lights
    assert first is not second
    np.testing.assert_allclose(first.position, [5, 0, 0])
    np.testing.assert_allclose(first.direction, [0, 0, -1])
    np.testing.assert_allclose(second.position, [3, 0, -2], atol=1e-12)
    np.testing.assert_allclose(second.direction, [0, 1, 0], atol=1e-12)  # normalised: the scale of 3 is not in it
    assert second.intensity == first.intensity == 200  # nor in the intensity


def test_glTF_defaults(tmp_path):
    lights = [{"type": "spot", "spot": {"innerConeAngle": 0.1}}, {"type": "point"}]
    spot, point = load_scene(lit_box(tmp_path, lights, [light_node(0), light_node(1)])).lights
    assert spot.cutoff_angle_degrees == pytest.approx(45)  # glTF's pi/4
    np.testing.assert_allclose(spot.direction, [0, 0, -1])  # an unturned node's -z
    assert point.intensity == 1 and point.color == (1, 1, 1) and point.name == "light1"


def test_equal_cones_are_a_hard_edge(tmp_path):
    lights = [{"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.5}}]
    (spot,) = load_scene(lit_box(tmp_path, lights, [light_node(0)])).lights
    assert spot.beam_width_degrees == spot.cutoff_angle_degrees == pytest.approx(math.degrees(0.5))


@pytest.mark.parametrize(
    "light, node, message",
    [
        ({"type": "area"}, light_node(0), r"lights\[0\].type: must be 'point', 'spot' or 'directional', got 'area'"),
        ({}, light_node(0), r"lights\[0\]: 'type' is missing"),
        ({"type": "point", "intensity": "bright"}, light_node(0), r"lights\[0\].intensity: must be float"),
        ({"type": "point", "intensity": -1}, light_node(0), r"lights\[0\] \(placed by nodes\[1\]\): .*intensity"),
        ({"type": "point", "color": [1, 1]}, light_node(0), r"lights\[0\].color: must be 3 numbers"),
        ({"type": "point", "color": [1, -1, 1]}, light_node(0), r"lights\[0\] \(placed by nodes\[1\]\): .*color"),
        (
            {"type": "spot", "spot": {"innerConeAngle": 0.7, "outerConeAngle": 0.6}},
            light_node(0),
            r"bad.glb: extensions.KHR_lights_punctual.lights\[0\].spot: needs 0 <= innerConeAngle <= outerConeAngle <= pi/2, got innerConeAngle 0.7",
        ),
        ({"type": "spot", "spot": {"outerConeAngle": 2}}, light_node(0), r"lights\[0\].spot: needs 0 <="),
        ({"type": "spot", "spot": []}, light_node(0), r"lights\[0\].spot: must be dict"),
        ({"type": "point"}, light_node(3), r"nodes\[1\].extensions.KHR_lights_punctual.light: .*index 3 out of range"),
        ({"type": "point"}, {"extensions": {"KHR_lights_punctual": {}}}, r"KHR_lights_punctual: 'light' is missing"),
        ({"type": "directional"}, light_node(0, scale=[0, 0, 0]), r"lights\[0\] \(placed by nodes\[1\]\): .*direction"),
    ],
)
def test_errors_name_file_light_and_field(tmp_path, light, node, message):
    path = lit_box(tmp_path, [light], [node], "bad.glb")
    with pytest.raises(SceneLoadError, match=message) as caught:
        load_scene(path)
    assert caught.value.path == path and str(caught.value).startswith(f"{path}: ")
    assert str(caught.value).count(str(path)) == 1  # named once, however deep the error arose


@pytest.mark.gpu
@pytest.mark.parametrize("half_turn, expected", [(False, GREY / math.pi), (True, 0.0)])
def test_a_directional_light_shines_along_its_node_minus_z(tmp_path, half_turn, expected):
    # A grey square facing +z, seen from +z (the loader's framing), under a directional light of
    # irradiance 1 travelling along its node's -z: the square's radiance is albedo x E / pi, with no
    # noise (one delta light, nothing to bounce off); turned half about y, the light comes from
    # behind and the front is black.
    square = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    document, blob = gltf_document([(square, np.array([[0, 1, 2], [0, 2, 3]]), None)])
    node = light_node(0, rotation=[0, 1, 0, 0]) if half_turn else light_node(0)
    with_lights(document, [{"type": "directional", "intensity": 1}], [node])
    scene = load_scene(write_glb(tmp_path / "sunlit.glb", document, blob))
    image = render(scene, spp=1, width=RENDER_SIZE, height=RENDER_SIZE)
    centre = image[RENDER_SIZE // 2, RENDER_SIZE // 2]
    np.testing.assert_allclose(centre, [expected] * 3, rtol=1e-5)
