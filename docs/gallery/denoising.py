"""
Denoising
=========

With ``guides=True`` the renderer also accumulates the albedo and normal of each path's first
vertex, and `Renderer.image` hands the mean to Intel Open Image Denoise guided by them. Needs the
``denoise`` extra: ``pip install "wgputrace[denoise]"``.
"""

import wgputrace as wt

scene = wt.default_scene()
renderer = wt.Renderer(scene, 160, 160, seed=1, guides=True)
renderer.render(spp=4)
wt.save_image("noisy.png", renderer.image())
wt.save_image("denoised.png", renderer.image(denoised=True))

# %%
# The same, by hand: `wgputrace.denoise` takes any linear float32 image and optional guides.
clean = wt.denoise(renderer.image(), **renderer.guides())
