"""
Hard geometry and hard light paths
==================================

Degenerate triangles, rays along the axes, a coarse smooth sphere's shadow terminator, and a room
lit only through a door ajar.
"""

import wgputrace as wt

SETTINGS = {"spp": 16, "width": 128, "height": 96, "seed": 1}

# %%
# ``slivers``: needle-thin and degenerate triangles.
wt.save_image("slivers.png", wt.render(wt.load_scene("slivers"), **SETTINGS))

# %%
# ``axis_boxes``: a camera looking exactly along +z at axis-aligned boxes (rays parallel to slabs).
wt.save_image("axis_boxes.png", wt.render(wt.load_scene("axis_boxes"), **SETTINGS))

# %%
# ``smooth_sphere``: a coarse sphere with interpolated normals above its flat twin.
wt.save_image("smooth_sphere.png", wt.render(wt.load_scene("smooth_sphere"), **SETTINGS))

# %%
# ``door_ajar``: Veach's door ajar, a room lit only through the gap of a door.
wt.save_image("door_ajar.png", wt.render(wt.load_scene("door_ajar"), **SETTINGS))
