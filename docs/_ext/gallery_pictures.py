"""The gallery's image scraper: a gallery script shows a picture by saving it, as a user's script
would (`wgputrace.save_image("cornell.png", image)`); after each code block sphinx-gallery runs,
the PNGs the block saved beside the script move into the gallery's images, shown in the order
they were saved, each named by its file."""

from __future__ import annotations

import shutil
from pathlib import Path

from sphinx_gallery.scrapers import figure_rst


def saved_pictures(block, block_vars: dict, gallery_conf: dict) -> str:
    """reST showing the PNGs the block saved in the script's folder (its working directory while it
    runs), moved out of the source tree into the gallery's image paths."""
    folder = Path(block_vars["src_file"]).parent
    saved = sorted(folder.glob("*.png"), key=lambda path: path.stat().st_mtime_ns)
    shown = []
    for picture, target in zip(saved, block_vars["image_path_iterator"], strict=False):
        shutil.move(picture, target)
        shown.append(figure_rst([target], gallery_conf["src_dir"], fig_titles=picture.stem))
    return "".join(shown)
