"""
Cameras and tone curves
=======================

Scenes made for the camera kinds other than the pinhole, and a sunlit scene bright enough to need
a tone curve: see :doc:`/guide/cameras_and_tonemapping`.
"""

import wgputrace as wt

SETTINGS = {"spp": 16, "width": 144, "height": 96, "seed": 1}

# %%
# ``depth_of_field``: a thin lens focused on the green sphere; the near red sphere and the far
# blue one and the striped wall are blurred.
wt.save_image("depth_of_field.png", wt.render(wt.load_scene("depth_of_field"), **SETTINGS), tonemap="agx")

# %%
# ``orthographic_boxes``: an orthographic camera: parallel rays, boxes of one size at any distance
# drawn the same size.
wt.save_image("orthographic_boxes.png", wt.render(wt.load_scene("orthographic_boxes"), **SETTINGS))

# %%
# ``sunlit_spheres``: a sun whose lit sides reach many times white, through AgX one stop down.
wt.save_image(
    "sunlit_spheres.png",
    wt.render(wt.load_scene("sunlit_spheres"), **SETTINGS),
    exposure=-1.0,
    tonemap="agx",
)
