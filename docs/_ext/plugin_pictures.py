"""The small pictures of the plugin pages, rendered when the site builds: a material on a sphere
before a striped backdrop under a lamp, a light alone on a sphere and a box, an environment map
around a sphere, and an integrator on the caustic scene, all at equal samples per pixel."""

from __future__ import annotations

from dataclasses import MISSING, fields
from pathlib import Path

import numpy as np

import wgputrace as wt
from wgputrace.scene import Material
from wgputrace.scene.lights import Light
from wgputrace.scenes import scene_by_name
from wgputrace.scenes.stage import floor, square_lamp

WIDTH, HEIGHT, SPP = 128, 96, 16
# Values for the light parameters that have no default, by name: a light above and in front of
# the sphere, shining down onto it. A light kind with another required parameter needs one here.
LIGHT_EXAMPLE = {
    "position": (-0.6, 1.8, -0.9),
    "direction": (0.35, -1.0, 0.5),
    "intensity": 4.0,
    "irradiance": 2.0,
}
# what the integrator pages compare on: the scene whose light reaches the floor only through glass
INTEGRATOR_SCENE = "caustic"
STRIPES, STRIPE_WIDTH, BACKDROP_Z = 12, 0.5, 1.5


def _camera() -> wt.Camera:
    return wt.Camera.looking_at((0.0, 1.0, -2.8), (0.0, 0.5, 0.0), vfov_degrees=38.0)


def _striped_backdrop() -> list[wt.Shape]:
    """Vertical stripes, light and dark, standing behind the sphere: what glass bends and metal mirrors."""
    shades = (wt.Diffuse("light stripe", color=0.8), wt.Diffuse("dark stripe", color=0.1))
    left = -STRIPES * STRIPE_WIDTH / 2
    return [
        wt.make_plane(
            (left + (i + 0.5) * STRIPE_WIDTH, 1.5, BACKDROP_Z),
            (-np.pi / 2, 0, 0),
            (STRIPE_WIDTH, 3.0),
            shades[i % 2],
            f"stripe {i}",
        )
        for i in range(STRIPES)
    ]


def material_scene(material: Material) -> wt.Scene:
    sphere = wt.make_icosphere((0.0, 0.5, 0.0), (0, 0, 0), 0.5, 3, material, "sphere", smooth=True)
    shapes = [floor(wt.Diffuse("floor", color=0.5), 8.0), *_striped_backdrop(), sphere]
    shapes.append(square_lamp((0.0, 2.6, -1.0), 1.0, 6.0))
    return wt.Scene(shapes, _camera())


def light_scene(light: Light) -> wt.Scene:
    white = wt.Diffuse("white", color=0.75)
    shapes = [
        floor(white, 8.0),
        wt.make_plane((0.0, 1.5, BACKDROP_Z), (-np.pi / 2, 0, 0), (6.0, 3.0), white, "wall"),
        wt.make_icosphere((-0.35, 0.4, 0.0), (0, 0, 0), 0.4, 3, wt.Diffuse("clay", color=(0.7, 0.4, 0.3)), smooth=True),
        wt.make_box((0.55, 0.25, 0.3), (0, 0.5, 0), (0.5, 0.5, 0.5), white),
    ]
    scene = wt.Scene(shapes, _camera())
    scene.add_light(light)
    return scene


def example_arguments(cls: type[Light]) -> dict[str, object]:
    """LIGHT_EXAMPLE's values for the parameters of `cls` that have no default."""
    required = [f.name for f in fields(cls) if f.default is MISSING and f.default_factory is MISSING]
    unknown = [name for name in required if name not in LIGHT_EXAMPLE]
    if unknown:
        raise KeyError(f"{cls.__name__} needs {', '.join(unknown)}: give an example value in LIGHT_EXAMPLE")
    return {name: LIGHT_EXAMPLE[name] for name in required}


def example_environment() -> wt.Environment:
    """A small sky: blue above, a bright horizon, a dark ground and a sun high on the right."""
    rows, columns = 32, 64
    v = (np.arange(rows) + 0.5) / rows
    sky = np.where(v[:, None] < 0.5, 1.0 - v[:, None], 0.15)
    texels = np.stack([0.5 * sky + 0.2, 0.7 * sky + 0.2, 1.2 * sky + 0.1], axis=-1) * np.ones((rows, columns, 1))
    texels[6:8, 40:42] = 200.0
    return wt.Environment(texels=texels.astype(np.float32))


def environment_scene(environment: wt.Environment) -> wt.Scene:
    shapes = [
        floor(wt.Diffuse("floor", color=0.5), 40.0),
        wt.make_icosphere((0.0, 0.5, 0.0), (0, 0, 0), 0.5, 3, wt.Glossy("metal", roughness=0.05), smooth=True),
    ]
    return wt.Scene(shapes, _camera(), environment=environment)


def integrator_scene() -> wt.Scene:
    return scene_by_name(INTEGRATOR_SCENE)


def render_picture(path: Path, scene: wt.Scene, integrator: str = "mis") -> None:
    image = wt.render(scene, spp=SPP, width=WIDTH, height=HEIGHT, seed=1, integrator=integrator)
    wt.save_image(path, image)
