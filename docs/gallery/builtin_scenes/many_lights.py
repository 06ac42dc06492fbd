"""
Many lights
===========

A street at night lit by 1,065 windows and 24 lamps: the light sampler chooses a light by power, so
almost every sample lands on a window far away; the ``restir`` integrator resamples candidates by
what they add to the point and finds the near lamp.
"""

import wgputrace as wt

SETTINGS = {"spp": 16, "width": 160, "height": 120, "seed": 1}

# %%
# ``night_street`` under ``mis``, the default: 16 samples per pixel.
street = wt.render(wt.load_scene("night_street"), **SETTINGS)
wt.save_image("night_street_mis.png", street, exposure="auto")

# %%
# The same 16 samples per pixel under ``restir``: each first vertex weighs 16 light candidates and
# traces one shadow ray.
street = wt.render(wt.load_scene("night_street"), integrator="restir", **SETTINGS)
wt.save_image("night_street_restir.png", street, exposure="auto")
