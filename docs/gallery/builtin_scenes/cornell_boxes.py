"""
Cornell boxes
=============

The default scene and its variations: the same box with a tiny lamp, and scaled by 1e-4 and 1e4
(the picture must not change with the scale: ray offsets and epsilons are relative).
"""

import wgputrace as wt

SETTINGS = {"spp": 16, "width": 112, "height": 112, "seed": 1}

# %%
# ``cornell``: the trac0r Cornell box, listing 16 of the thesis (`wgputrace.scenes.cornell`).
wt.save_image("cornell.png", wt.render(wt.load_scene("cornell"), **SETTINGS))

# %%
# ``tiny_light``: a lamp of 1e-4 the area and the same power, which only light sampling finds.
wt.save_image("tiny_light.png", wt.render(wt.load_scene("tiny_light"), **SETTINGS))

# %%
# ``cornell_1e-4``: every vertex and the camera scaled by 1e-4.
wt.save_image("cornell_1e-4.png", wt.render(wt.load_scene("cornell_1e-4"), **SETTINGS))

# %%
# ``cornell_1e4``: scaled by 1e4.
wt.save_image("cornell_1e4.png", wt.render(wt.load_scene("cornell_1e4"), **SETTINGS))

# %%
# ``instanced_cornell``: the box's walls and lamp with spheres and crates placed as instances of
# two meshes, each stored once (`Scene.add_instance`, traversed through a two-level BVH).
wt.save_image("instanced_cornell.png", wt.render(wt.load_scene("instanced_cornell"), **SETTINGS))
