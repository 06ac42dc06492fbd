"""
Edit a scene between renders
============================

Every assignment is checked where it happens and marks what it touches; the next render uploads
only the records that changed (`Renderer.upload_stats` says which) and restarts accumulation only
if some uploaded byte changed.
"""

import numpy as np

import wgputrace as wt

scene = wt.load_scene("cornell")
renderer = wt.Renderer(scene, 160, 160, seed=1)
renderer.render(8)
wt.save_image("before.png", renderer.image())

# %%
# Move a box (a BVH refit), recolour a wall (one material record), move the camera (the frame
# uniform) and add a glass ball (a rebuild, and a new pipeline).
scene.shape("box2").transform = wt.model_matrix((0.1, 0, 0), (0, 0.3, 0), 1.0)
next(m for m in scene.materials if m.name == "red").color = (0.2, 0.6, 0.9)
scene.camera = wt.Camera.looking_at((0, 0.4, -1.5), (0, 0.3, 0), vfov_degrees=50)
scene.add(wt.make_icosphere((0, 0.5, 0), (0, 0, 0), 0.1, 2, wt.Glass("ball")))
renderer.render(8)
print({buffer: count.bytes for buffer, count in renderer.upload_stats.items()})
wt.save_image("after.png", renderer.image())

# %%
# A fresh renderer of the edited scene with the same seed makes the same picture, bit for bit.
fresh = wt.Renderer(scene, 160, 160, seed=1)
fresh.render(8)
print("the same picture:", np.array_equal(fresh.image(), renderer.image()))
