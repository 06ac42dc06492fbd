"""
Environments and lights
=======================

Scenes lit by an environment map, a constant environment, or point, spot and directional lights
instead of emitting triangles.
"""

import wgputrace as wt

SETTINGS = {"spp": 16, "width": 128, "height": 96, "seed": 1}

# %%
# ``env_sun_spheres``: a sunny sky whose few sun texels carry most of the light, which the map's
# importance sampling must find.
wt.save_image("env_sun_spheres.png", wt.render(wt.load_scene("env_sun_spheres"), **SETTINGS))

# %%
# ``constant_env``: a constant, bluish sky: ambient light and soft contact shadows.
wt.save_image("constant_env.png", wt.render(wt.load_scene("constant_env"), **SETTINGS))

# %%
# ``env_one_texel``: a map lit by one texel, turned: its direction must come out right.
wt.save_image("env_one_texel.png", wt.render(wt.load_scene("env_one_texel"), **SETTINGS))

# %%
# ``point_spot_directional``: a warm point light, a cool spot light and a green directional light.
wt.save_image("point_spot_directional.png", wt.render(wt.load_scene("point_spot_directional"), **SETTINGS))
