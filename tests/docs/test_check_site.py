"""scripts/check_site.py's link checker finds what is broken in a built site, and nothing else: a
site of three pages made here (no Sphinx, no browser)."""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
from PIL import Image

CHECK_SITE = Path(__file__).resolve().parents[2] / "scripts" / "check_site.py"


def test_check_site_reports_each_broken_link_and_image(tmp_path):
    broken_links = runpy.run_path(str(CHECK_SITE))["broken_links"]
    (tmp_path / "guide").mkdir()
    Image.fromarray(np.full((4, 4, 3), 128, np.uint8)).save(tmp_path / "picture.png")
    (tmp_path / "not_a_picture.png").write_text("text")
    (tmp_path / "index.html").write_text(
        '<a href="guide/page.html#usage">ok</a> <a href="guide/">ok, a folder</a> <a href="https://example.com">external</a>'
        '<a href="#top">ok</a> <img src="picture.png"> <a id="top"></a>'
        '<a href="missing.html">missing</a> <a href="guide/page.html#nowhere">no anchor</a> <img src="not_a_picture.png">'
    )
    (tmp_path / "guide" / "page.html").write_text('<h1 id="usage">Usage</h1><a href="../index.html#top">back</a>')
    (tmp_path / "guide" / "index.html").write_text('<img src="../gone.png">')

    problems = broken_links(tmp_path)

    # an image's line ends with PIL's words on it, in parentheses
    assert sorted(problem.split(" (")[0] for problem in problems) == sorted(
        [
            "index.html: missing.html: no such file",
            "index.html: guide/page.html#nowhere: no anchor #nowhere",
            "index.html: not_a_picture.png: not an image",
            "guide/index.html: ../gone.png: no such file",
        ]
    )
