"""Sphinx configuration of the wgputrace site: pages in Markdown (myst-parser), the API reference from
docstrings (autodoc, Google-style sections through napoleon), a gallery that runs its scripts
(sphinx-gallery) and the pages generated from the code by the local extensions in docs/_ext.

Build from the checkout's root (the local extensions import as `docs._ext`), offline:
`.venv/bin/python -m sphinx -W --keep-going -b html docs docs/_build/html`.
"""

import wgputrace

project = "wgputrace"
author = "the wgputrace authors"
copyright = "the wgputrace authors"
release = wgputrace.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
    "docs._ext.api_reference",
    "docs._ext.plugin_pages",
    "docs._ext.cli_reference",
    "docs._ext.benchmark_pages",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "gallery/**"]
# `name` in a docstring links to that symbol where Sphinx finds it, and reads as code where not
default_role = "py:obj"

# "--env" stays two hyphens and quotes stay straight: options and code are quoted verbatim
smartquotes = False
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence", "deflist"]

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_description_target = "documented_params"
autodoc_preserve_defaults = True
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_rtype = False

sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_gallery",
    # every script runs at build time, not only those named plot_*
    "filename_pattern": r".*\.py",
    "image_scrapers": ("docs._ext.gallery_pictures.saved_pictures",),
    # the gallery shows no matplotlib figures: nothing to reset between scripts
    "reset_modules": (),
    "download_all_examples": False,
    "remove_config_comments": True,
    "min_reported_time": 1,
    # no page of computation times (its table loads scripts from CDNs)
    "write_computation_times": False,
    "show_memory": False,
    "show_signature": False,
    # a script's last expression (save_image's path) is not output worth showing
    "capture_repr": (),
}

html_theme = "furo"
html_title = f"wgputrace {release}"
html_static_path = []
# the site opens from disk or any static host; no search index fetched from elsewhere
html_copy_source = False
