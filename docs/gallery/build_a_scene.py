"""
Build a scene
=============

Shapes from trac0r's generators (`make_plane`, `make_box`, `make_icosphere`), each with a
material, seen by a `Camera`. Every material kind has a page under the plugins reference.
"""

import wgputrace as wt

white = wt.Diffuse("white", color=(0.74, 0.74, 0.73))
lamp = wt.Emitter("lamp", color=(1, 0.93, 0.85), emittance=15)
scene = wt.Scene(
    [
        wt.make_plane((0, 0, 0), (0, 0, 0), (2, 2), white, "floor"),
        wt.make_box((0, 0.25, 0), (0, 0.6, 0), (0.5, 0.5, 0.5), wt.Glossy("metal", roughness=0.2)),
        wt.make_icosphere((0, 2, 0), (0, 0, 0), 0.3, 2, lamp, "lamp"),
    ],
    wt.Camera.looking_at((0, 1, -3), (0, 0.3, 0), vfov_degrees=45),
)
wt.save_image("scene.png", wt.render(scene, spp=16, width=200, height=150, seed=1))
