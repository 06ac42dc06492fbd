"""
Environment and lights
======================

Besides triangles with an `Emitter` material, a scene holds an environment (a constant, or an
equirectangular map: `Environment.from_file` reads .exr and .hdr) and any number of lights.
"""

import numpy as np

import wgputrace as wt

scene = wt.Scene(
    [
        wt.make_plane((0, 0, 0), (0, 0, 0), (6, 6), wt.Diffuse("floor", color=0.6), "floor"),
        wt.make_icosphere((-0.45, 0.4, 0), (0, 0, 0), 0.4, 3, wt.Diffuse("clay", color=(0.7, 0.4, 0.3)), smooth=True),
        wt.make_icosphere((0.45, 0.4, 0), (0, 0, 0), 0.4, 3, wt.Glossy("metal", roughness=0.1), smooth=True),
    ],
    wt.Camera.looking_at((0, 1.2, -3), (0, 0.4, 0), vfov_degrees=35),
)

# %%
# A sky made in numpy: a map's row 0 looks straight up, its centre column along +z (Mitsuba's `envmap`).
rows, columns = 64, 128
v = (np.arange(rows)[:, None, None] + 0.5) / rows
sky = np.where(v < 0.5, (0.35, 0.5, 0.9) * (1.2 - v), (0.1, 0.09, 0.08)) * np.ones((1, columns, 1))
scene.environment = wt.Environment(texels=sky.astype(np.float32), intensity=1.0, rotation_degrees=90.0)
wt.save_image("sky.png", wt.render(scene, spp=8, width=200, height=130, seed=1))

# %%
# A sun (a distant disc: soft shadows) and a warm point light.
scene.add_light(wt.Sun(direction=(0.5, -1, 0.5), irradiance=3.0))
scene.add_light(wt.PointLight(position=(0, 2, -0.5), intensity=2.0, color=(1, 0.9, 0.8)))
wt.save_image("sun_and_point.png", wt.render(scene, spp=8, width=200, height=130, seed=1))
