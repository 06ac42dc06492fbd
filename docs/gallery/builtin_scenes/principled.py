"""
The Principled material
=======================

Mitsuba 3's ``principled`` BSDF, the material glTF files load as, over its parameters.
"""

import wgputrace as wt

SETTINGS = {"spp": 16, "width": 128, "height": 96, "seed": 1}

# %%
# ``principled_spheres``: metallic 0 to 1 and roughness 0.1 to 1.
wt.save_image("principled_spheres.png", wt.render(wt.load_scene("principled_spheres"), **SETTINGS))

# %%
# ``principled_transmission``: spheres that transmit (``spec_trans`` 0.5 and 1), rough and smooth.
wt.save_image("principled_transmission.png", wt.render(wt.load_scene("principled_transmission"), **SETTINGS))

# %%
# ``principled_clearcoat``: rough red spheres under a clearcoat from rough to glossy.
wt.save_image("principled_clearcoat.png", wt.render(wt.load_scene("principled_clearcoat"), **SETTINGS))

# %%
# ``principled_sheen``: cloth-like spheres with a white, half-tinted and tinted sheen at their rims.
wt.save_image("principled_sheen.png", wt.render(wt.load_scene("principled_sheen"), **SETTINGS))

# %%
# ``principled_anisotropic``: brushed metal quads whose texture coordinates (the tangent) run along x,
# the diagonal and y, blurring the room's checkers along them; anisotropic spheres below.
wt.save_image("principled_anisotropic.png", wt.render(wt.load_scene("principled_anisotropic"), **SETTINGS))
