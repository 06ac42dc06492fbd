"""Small scenes with closed-form images, shared by the render tests."""

from __future__ import annotations

from wgputrace import Camera, Diffuse, Emitter, Glass, Scene, make_box, make_icosphere

ENCLOSURE_RADIANCE = (0.8, 1.6, 2.4)


def inside_emitter(*inner_shapes) -> Scene:
    """The camera and `inner_shapes` inside a closed box that emits ENCLOSURE_RADIANCE everywhere."""
    light = Emitter("enclosure", color=ENCLOSURE_RADIANCE, emittance=1.0)
    enclosure = make_box((0, 0, 0), (0.1, 0.2, 0.3), (6, 6, 6), light, "enclosure")
    camera = Camera(position=(0, 0, -2), forward=(0, 0, 1), up=(0, 1, 0), vfov_degrees=40.0)
    return Scene([enclosure, *inner_shapes], camera)


def diffuse_sphere_in_emitter(albedo) -> Scene:
    return inside_emitter(make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 2, Diffuse("ball", color=albedo), "ball"))


def glass_sphere_in_emitter(ior: float = 1.5) -> Scene:
    return inside_emitter(make_icosphere((0, 0, 0), (0, 0, 0), 1.0, 2, Glass("ball", color=(1, 1, 1), ior=ior), "ball"))
