"""Glossy spheres reflecting a small lamp, seen in a glossy panel: the highlights the camera sees
in the panel are the lamp after two glossy bounces.

A path from the camera must sample the panel's narrow lobe towards a sphere and then the sphere's
towards the lamp (or connect to the small lamp from the sphere, where a narrow lobe makes light
sampling noisy); each glossy bounce narrows which directions carry the light. The lamp is above
the picture, so the camera sees it only in the glass-like reflections.
"""

from __future__ import annotations

from ..scene import Camera, Diffuse, Glossy, Scene, make_icosphere
from .stage import backdrop, floor, square_lamp

# The panel stands across the view, facing the camera; the spheres sit on the floor between the
# two, so the panel shows their backs, which face the lamp.
FLOOR_SIDE = 8.0
PANEL_Z = 2.0
PANEL_SIZE = (3.0, 2.0)
PANEL_ROUGHNESS = 0.05
SPHERE_Z = -0.3
SPHERE_RADIUS = 0.3
SPHERE_ROUGHNESS = (0.02, 0.08, 0.2)
SPHERE_SPACING = 0.8
LAMP_CENTRE = (0.0, 2.4, 1.0)
LAMP_SIZE = 0.1
LAMP_EMITTANCE = 800.0


def glossy_through_glossy() -> Scene:
    panel = Glossy("panel", color=(0.9, 0.9, 0.95), roughness=PANEL_ROUGHNESS)
    shapes = [
        floor(Diffuse("floor", color=(0.5, 0.5, 0.5)), FLOOR_SIDE),
        backdrop(panel, "panel", PANEL_Z, PANEL_SIZE),
        square_lamp(LAMP_CENTRE, LAMP_SIZE, LAMP_EMITTANCE),
    ]
    for index, roughness in enumerate(SPHERE_ROUGHNESS):
        x = (index - (len(SPHERE_ROUGHNESS) - 1) / 2) * SPHERE_SPACING
        metal = Glossy(f"sphere_{roughness:g}", color=(0.95, 0.75, 0.5), roughness=roughness)
        shapes.append(
            make_icosphere((x, SPHERE_RADIUS, SPHERE_Z), (0, 0, 0), SPHERE_RADIUS, 3, metal, f"sphere_{roughness:g}")
        )
    camera = Camera.looking_at((0.0, 1.0, -3.0), (0.0, 0.6, 0.0), vfov_degrees=40.0)
    return Scene(shapes, camera)
