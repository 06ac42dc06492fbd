"""The built-in scenes, by name (wgputrace.load_scene and the command line take these names): the
default Cornell box and the test scenes, each chosen to hit a known failure of path tracers (see
each family's module)."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

from ..scene import Scene
from .absorbing_glass import absorbing_glass
from .alpha_cutout import alpha_blend, alpha_cutout
from .anisotropic import principled_anisotropic
from .axis_aligned import axis_boxes
from .camera_views import depth_of_field, orthographic_boxes
from .caustic import caustic
from .cornell import cornell, scaled_cornell, tiny_light
from .door_ajar import door_ajar
from .environment_lit import constant_env, env_one_texel, env_sun_spheres
from .glass import glass_grazing
from .glossy import glossy_spheres
from .glossy_through_glossy import glossy_through_glossy
from .instanced import instanced_cornell
from .many_lights import night_street
from .normal_mapped import normal_mapped_plane
from .principled import principled_clearcoat, principled_sheen, principled_spheres, principled_transmission
from .punctual import point_spot_directional
from .slivers import slivers
from .smooth_sphere import smooth_sphere
from .sunlit import sunlit_spheres
from .textured import textured_quads
from .textured_asset import textured_asset
from .vertex_colored import vertex_colored_triangles

BUILTIN_SCENES: dict[str, Callable[[], Scene]] = {
    "cornell": cornell,
    "tiny_light": tiny_light,
    "cornell_1e-4": partial(scaled_cornell, 1e-4),
    "cornell_1e4": partial(scaled_cornell, 1e4),
    "glass_grazing": glass_grazing,
    "glossy_spheres": glossy_spheres,
    "principled_spheres": principled_spheres,
    "principled_transmission": principled_transmission,
    "principled_clearcoat": principled_clearcoat,
    "principled_sheen": principled_sheen,
    "slivers": slivers,
    "axis_boxes": axis_boxes,
    "env_sun_spheres": env_sun_spheres,
    "constant_env": constant_env,
    "env_one_texel": env_one_texel,
    "point_spot_directional": point_spot_directional,
    "textured_quads": textured_quads,
    "textured_asset": textured_asset,
    "alpha_cutout": alpha_cutout,
    "smooth_sphere": smooth_sphere,
    "alpha_blend": alpha_blend,
    "normal_mapped_plane": normal_mapped_plane,
    "door_ajar": door_ajar,
    "caustic": caustic,
    "glossy_through_glossy": glossy_through_glossy,
    # cameras and tone mapping (issue 28)
    "depth_of_field": depth_of_field,
    "orthographic_boxes": orthographic_boxes,
    "sunlit_spheres": sunlit_spheres,
    # instances (issue 25)
    "instanced_cornell": instanced_cornell,
    # vertex colours (issue 25)
    "vertex_colored_triangles": vertex_colored_triangles,
    # KHR_materials_volume (issue 25)
    "absorbing_glass": absorbing_glass,
    # KHR_materials_anisotropy (issue 25)
    "principled_anisotropic": principled_anisotropic,
    # ReSTIR's many lights (issue 27)
    "night_street": night_street,
}
DEFAULT_SCENE = "cornell"


def default_scene() -> Scene:
    """The trac0r Cornell box (listing 16 of the thesis)."""
    return BUILTIN_SCENES[DEFAULT_SCENE]()


def scene_by_name(name: str) -> Scene:
    try:
        return BUILTIN_SCENES[name]()
    except KeyError:
        raise ValueError(f"unknown scene {name!r}; built-in scenes: {', '.join(sorted(BUILTIN_SCENES))}") from None
