"""
Textures, alpha, normal maps and vertex colours
===============================================

The Principled material's textures, its alpha modes and normal maps, and vertex colours, made in
Python (no files).
"""

import wgputrace as wt

SETTINGS = {"spp": 16, "width": 128, "height": 96, "seed": 1}

# %%
# ``textured_quads``: a checkerboard repeating past [0, 1], a mirrored and transformed
# metallic-roughness texture.
wt.save_image("textured_quads.png", wt.render(wt.load_scene("textured_quads"), **SETTINGS))

# %%
# ``textured_asset``: a panel with every texture Principled reads, its emissive marks lighting the floor.
wt.save_image("textured_asset.png", wt.render(wt.load_scene("textured_asset"), **SETTINGS))

# %%
# ``alpha_cutout``: a MASK quad cut into stripes, casting cut-out shadows.
wt.save_image("alpha_cutout.png", wt.render(wt.load_scene("alpha_cutout"), **SETTINGS))

# %%
# ``alpha_blend``: the same quad under BLEND: stochastic transparency.
wt.save_image("alpha_blend.png", wt.render(wt.load_scene("alpha_blend"), **SETTINGS))

# %%
# ``normal_mapped_plane``: a normal-mapped square under a light grazing it.
wt.save_image("normal_mapped_plane.png", wt.render(wt.load_scene("normal_mapped_plane"), **SETTINGS))

# %%
# ``vertex_colored_triangles``: vertex colours multiplying a diffuse and a glossy colour, per vertex
# (the backdrop, the triangle) and per corner (the quad's hard diagonal).
wt.save_image("vertex_colored_triangles.png", wt.render(wt.load_scene("vertex_colored_triangles"), **SETTINGS))
