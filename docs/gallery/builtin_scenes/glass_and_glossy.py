"""
Glass and glossy surfaces
=========================

Scenes of delta and near-delta lobes: grazing glass, a roughness sweep, a caustic and glossy
reflections seen in a glossy panel, and coloured glass that absorbs.
"""

import wgputrace as wt

SETTINGS = {"spp": 16, "width": 128, "height": 96, "seed": 1}

# %%
# ``glass_grazing``: glass seen at grazing angles, where Fresnel nears 1 and total internal
# reflection sets in.
wt.save_image("glass_grazing.png", wt.render(wt.load_scene("glass_grazing"), **SETTINGS))

# %%
# ``glossy_spheres``: GGX roughness from 0.01 (almost a mirror) upwards.
wt.save_image("glossy_spheres.png", wt.render(wt.load_scene("glossy_spheres"), **SETTINGS))

# %%
# ``caustic``: a glass sphere focusing a small lamp onto the floor, light that next-event
# estimation cannot see (the bdpt integrator's case).
wt.save_image("caustic.png", wt.render(wt.load_scene("caustic"), **SETTINGS))

# %%
# ``glossy_through_glossy``: glossy spheres reflecting a small lamp, seen in a glossy panel.
wt.save_image("glossy_through_glossy.png", wt.render(wt.load_scene("glossy_through_glossy"), **SETTINGS))

# %%
# ``absorbing_glass``: coloured glass that absorbs inside (KHR_materials_volume): a long smooth
# block, bluer where light crossed more of it, and a rough amber sphere.
wt.save_image("absorbing_glass.png", wt.render(wt.load_scene("absorbing_glass"), **SETTINGS))
