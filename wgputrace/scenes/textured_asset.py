"""A textured asset: a panel carrying every texture the Principled material reads (base colour with
a marked corner, metallic-roughness, a normal map of bumps, emissive marks), per-vertex normals and
texture coordinates, on a grey floor that its marks light, lit by a point light beside the camera.
Generated here (nothing to license), 8-bit as a glTF file holds them (`textured_asset_glb` writes
the same model as a .glb). Against Mitsuba's reference (MATERIAL_CASES) two choices keep the
comparison about textures: the panel faces +z with u along +x, so Mitsuba's `normalmap` (dP/du)
and our MikkTSpace tangents give the same frame; and the light is within 25 degrees of the panel's
normal while the bumps tilt at most 15, so our terminator term, which Mitsuba lacks, changes no
pixel by more than a tenth of a percent of its direct light.
"""

from __future__ import annotations

import numpy as np

from ..scene import Camera, Diffuse, PointLight, Principled, Scene, Shape, Texture

PANEL_LEFT, PANEL_RIGHT = -0.8, 0.8
PANEL_BOTTOM, PANEL_TOP = -0.5, 0.9
FLOOR_Y = PANEL_BOTTOM
FLOOR_HALF_WIDTH = 1.4
FLOOR_DEPTH = 1.6
BASE_TEXELS = 16
MARK_TEXELS = 2
NORMAL_TEXELS = 32
BUMP_CELLS = 4
BUMP_MAX_TILT_DEGREES = 15.0
EMISSIVE_TEXELS = 16
EMISSION = (1.0, 0.55, 0.25)
EMISSION_STRENGTH = 6.0
LIGHT_POSITION = (0.4, 0.9, 3.0)
LIGHT_INTENSITY = 5.0


def base_color_texture() -> Texture:
    """sRGB tiles of two stone colours, mortar lines between them, the top-left block red."""
    rows, columns = np.indices((BASE_TEXELS, BASE_TEXELS))
    tiles = ((rows // 4) + (columns // 4)) % 2 == 0
    pixels = np.where(tiles[..., None], (205, 190, 160), (120, 135, 150)).astype(np.uint8)
    pixels[(rows % 4 == 3) | (columns % 4 == 3)] = (60, 55, 50)
    pixels[:MARK_TEXELS, :MARK_TEXELS] = (220, 30, 20)
    return Texture(pixels, name="asset_base_color")


def metallic_roughness_texture() -> Texture:
    """Linear 8-bit: the left half a rough dielectric (roughness 0.8), the right half a smoother
    metal (0.35)."""
    texels = np.zeros((8, 8, 3), np.uint8)
    texels[:, :4, 1], texels[:, 4:, 1] = 204, 89
    texels[:, 4:, 2] = 255
    return Texture(texels, srgb=False, name="asset_metallic_roughness")


def normal_texture() -> Texture:
    """Linear 8-bit tangent-space normals of round bumps, BUMP_CELLS to a side: each a dome whose edge
    tilts BUMP_MAX_TILT_DEGREES (x along u, y up the image: glTF's convention)."""
    centres = (np.arange(NORMAL_TEXELS) + 0.5) / NORMAL_TEXELS * BUMP_CELLS % 1.0 * 2.0 - 1.0
    down, right = np.meshgrid(centres, centres, indexing="ij")
    inside = (right**2 + down**2) < 1.0
    # a dome's slope grows with the distance from its centre: tan(tilt) at its rim
    slope = np.tan(np.radians(BUMP_MAX_TILT_DEGREES)) * inside
    vectors = np.stack([slope * right, -slope * down, np.ones_like(right)], axis=-1)
    vectors /= np.linalg.norm(vectors, axis=-1, keepdims=True)
    texels = np.round(127.5 * (vectors + 1.0)).astype(np.uint8)
    return Texture(texels, srgb=False, name="asset_normals")


def emission_texture() -> Texture:
    """sRGB black with three small glowing marks along the panel's bottom edge."""
    pixels = np.zeros((EMISSIVE_TEXELS, EMISSIVE_TEXELS, 3), np.uint8)
    for column in (2, 7, 12):
        pixels[12:15, column : column + 2] = (255, 255, 255)
    return Texture(pixels, name="asset_emission")


def panel() -> Shape:
    """The panel in the plane z = 0 facing +z (the camera), uv (0, 0) at its top-left corner."""
    corners = np.array(
        [
            (PANEL_LEFT, PANEL_TOP, 0),
            (PANEL_RIGHT, PANEL_TOP, 0),
            (PANEL_RIGHT, PANEL_BOTTOM, 0),
            (PANEL_LEFT, PANEL_BOTTOM, 0),
        ],
        np.float32,
    )
    uv = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], np.float32)
    faces = np.array([[0, 2, 1], [0, 3, 2]])
    material = Principled(
        "asset_panel",
        (1.0, 1.0, 1.0),
        metallic=1.0,
        roughness=1.0,
        base_color_texture=base_color_texture(),
        metallic_roughness_texture=metallic_roughness_texture(),
        normal_texture=normal_texture(),
        normal_scale=0.9,
        emission=EMISSION,
        emission_texture=emission_texture(),
        emission_strength=EMISSION_STRENGTH,
    )
    normals = np.broadcast_to(np.float32([0, 0, 1]), (2, 3, 3))
    return Shape("panel", corners[faces], material, normals=normals, uvs=uv[faces])


def floor() -> Shape:
    """A grey Lambertian floor in front of the panel, facing up (glTF's metallic 0, roughness 1)."""
    w, y = FLOOR_HALF_WIDTH, FLOOR_Y
    corners = np.array([(-w, y, 0), (w, y, 0), (w, y, FLOOR_DEPTH), (-w, y, FLOOR_DEPTH)], np.float32)
    faces = np.array([[0, 2, 1], [0, 3, 2]])
    return Shape("floor", corners[faces], Diffuse("asset_floor", (0.6, 0.6, 0.6)))


def textured_asset() -> Scene:
    scene = Scene([panel(), floor()], Camera.looking_at((0.0, 0.35, 3.2), (0.0, 0.1, 0.0), vfov_degrees=40.0))
    scene.add_light(PointLight(LIGHT_POSITION, LIGHT_INTENSITY, name="key"))
    return scene
