"""
Render, accumulate, save
========================

`wgputrace.render` renders a scene from scratch; a `wgputrace.Renderer` keeps the device and the
scene's buffers, and each `Renderer.render` adds samples to the mean: 8 + 8 samples give exactly
the image of 16.
"""

import wgputrace as wt

scene = wt.default_scene()  # the trac0r Cornell box
image = wt.render(scene, spp=16, width=160, height=160, seed=1, max_depth=9)
# image: numpy float32 (H, W, 3), linear radiance, row 0 = top of the picture
wt.save_image("render.png", image)

# %%
# Progressively: the renderer keeps accumulating until asked for the mean.
renderer = wt.Renderer(scene, width=160, height=160, seed=1)
renderer.render(spp=8)
renderer.render(spp=8)
mean = renderer.image()  # the mean of all 16 samples per pixel so far
print(renderer.samples_per_pixel, "samples per pixel;", renderer.nonfinite_samples, "non-finite samples dropped")
wt.save_image("accumulated.png", mean)  # .png (sRGB, 8 bit), .exr or .npy by the extension
