"""Every generated file a kernel variant gets, by name, and the function of the variant that writes
it. A hook that a variant does not switch on compiles to nothing (empty functions the compiler
inlines away, constant conditions it folds), so a scene pays only for the features it uses."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from ..gpu.texels import GENERATED_TEXEL_LOADERS, TEXEL_STRUCTS, texel_loaders
from .absorption import GENERATED_ABSORPTION, absorption_hook
from .alpha import GENERATED_ALPHA, alpha_hook
from .camera import GENERATED_CAMERA, camera_hook
from .emission import GENERATED_EMISSION, emission_hook
from .instancing import GENERATED_INSTANCING, instancing_hook
from .light_dispatch import GENERATED_ESCAPED_LIGHT, GENERATED_LIGHTS, escaped_light_hook, lights_hook
from .material_dispatch import GENERATED_MATERIALS, materials_hook
from .path_guides import GENERATED_PATH_GUIDES, path_guides_hook
from .principled_lobes import GENERATED_PRINCIPLED_LOBES, principled_lobes_hook
from .ray_count import GENERATED_RAY_COUNT, ray_count_hook
from .regeneration import GENERATED_REGENERATION, regeneration_hook
from .sampler import GENERATED_SAMPLER, sampler_hook
from .shading_normals import GENERATED_SHADING_NORMALS, shading_normals_hook
from .structs import GENERATED_STRUCTS, structs_hook
from .textures import GENERATED_TEXTURES, textures_hook
from .traversal import GENERATED_ACCELERATION, GENERATED_TRAVERSAL_STACK, acceleration_hook, traversal_stack_hook
from .vertex_colors import GENERATED_VERTEX_COLORS, vertex_colors_hook

if TYPE_CHECKING:
    from .variant import KernelVariant


def _texel_loaders_hook(variant: KernelVariant) -> str:
    return texel_loaders(TEXEL_STRUCTS)


HOOKS: dict[str, Callable[[KernelVariant], str]] = {
    GENERATED_STRUCTS: structs_hook,
    GENERATED_TEXEL_LOADERS: _texel_loaders_hook,
    GENERATED_ACCELERATION: acceleration_hook,
    GENERATED_INSTANCING: instancing_hook,
    GENERATED_CAMERA: camera_hook,
    GENERATED_TRAVERSAL_STACK: traversal_stack_hook,
    GENERATED_MATERIALS: materials_hook,
    GENERATED_PRINCIPLED_LOBES: principled_lobes_hook,
    GENERATED_LIGHTS: lights_hook,
    GENERATED_ESCAPED_LIGHT: escaped_light_hook,
    GENERATED_SHADING_NORMALS: shading_normals_hook,
    GENERATED_TEXTURES: textures_hook,
    GENERATED_VERTEX_COLORS: vertex_colors_hook,
    GENERATED_ALPHA: alpha_hook,
    GENERATED_ABSORPTION: absorption_hook,
    GENERATED_EMISSION: emission_hook,
    GENERATED_PATH_GUIDES: path_guides_hook,
    GENERATED_RAY_COUNT: ray_count_hook,
    GENERATED_SAMPLER: sampler_hook,
    GENERATED_REGENERATION: regeneration_hook,
}
