"""Check the built site: every link between its pages and every image they show resolves (pure
Python, over the HTML files), and, where Debian's chromium is installed, a real browser opens the
index and one gallery page, says whether each image loaded, and renders both to PNG.

    .venv/bin/python -m sphinx -W --keep-going -b html docs docs/_build/html
    .venv/bin/python scripts/check_site.py                 # docs/_build/html; PNGs in docs/_build/screenshots
    .venv/bin/python scripts/check_site.py --no-browser    # the links and images only

Links to other sites are not followed (the build and this check stay offline). Exit status 0 when
everything resolves, 1 with one line per broken link or image otherwise. Not run in CI: chromium
is a 100 MB install (`apt-get install chromium`).
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

from PIL import Image

# the pages the browser opens, relative to the site's root
BROWSER_PAGES = ("index.html", "auto_gallery/library.html")
# a page's images get this long to load in the browser's virtual time
LOAD_MILLISECONDS = 10_000
WINDOW = "1280,1800"
# chromium prints the page's DOM; this attribute of <body> counts the images that did not load
BROKEN_ATTRIBUTE = "data-broken-images"
COUNT_BROKEN = f"""<script>
window.addEventListener("load", () => {{
  const broken = [...document.images].filter((image) => !image.complete || image.naturalWidth === 0);
  document.body.setAttribute("{BROKEN_ATTRIBUTE}", broken.map((image) => image.getAttribute("src")).join(" ") || "none");
}});
</script>"""


class PageLinks(HTMLParser):
    """The links (a href, link href), images (img src) and anchors (id, name) of one HTML page."""

    def __init__(self) -> None:
        super().__init__()
        self.links: list[str] = []
        self.images: list[str] = []
        self.anchors: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        values = dict(attrs)
        self.anchors.update(value for key in ("id", "name") if (value := values.get(key)))
        if tag in ("a", "link") and values.get("href"):
            self.links.append(values["href"])
        if tag == "img" and values.get("src"):
            self.images.append(values["src"])


def _local(url: str) -> bool:
    parts = urlsplit(url)
    return not parts.scheme and not parts.netloc


def broken_links(site: Path) -> list[str]:
    """One line per link or image of the site that does not resolve to a file (and anchor) in it,
    or an image file that does not open as one."""
    pages = {}
    for path in site.rglob("*.html"):
        parser = PageLinks()
        parser.feed(path.read_text(errors="replace"))
        pages[path.resolve()] = parser
    problems = []
    for page, parser in pages.items():
        where = page.relative_to(site.resolve())
        for url in filter(_local, parser.links + parser.images):
            parts = urlsplit(url)
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.is_file():
                problems.append(f"{where}: {url}: no such file")
            elif parts.fragment and target in pages and unquote(parts.fragment) not in pages[target].anchors:
                problems.append(f"{where}: {url}: no anchor #{parts.fragment}")
        for url in filter(_local, parser.images):
            target = (page.parent / unquote(urlsplit(url).path)).resolve()
            if target.is_file() and target.suffix != ".svg":
                try:
                    with Image.open(target) as image:
                        image.verify()
                except Exception as error:
                    problems.append(f"{where}: {url}: not an image ({error})")
    return problems


def chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


def _run_chromium(browser: str, url: str, *arguments: str) -> str:
    command = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", *arguments, url]
    done = subprocess.run(command, capture_output=True, text=True, timeout=120, check=True)
    return done.stdout


def browse(site: Path, page: str, screenshots: Path, browser: str) -> list[str]:
    """Open `page` in chromium: the images that did not load (one line each), and its picture as PNG."""
    source = (site / page).resolve()
    # a copy beside the page (its relative links resolve alike) that reports its broken images
    with tempfile.NamedTemporaryFile("w", suffix=".html", dir=source.parent, delete=False) as copy:
        copy.write(source.read_text().replace("</body>", f"{COUNT_BROKEN}</body>"))
    try:
        dom = _run_chromium(
            browser, Path(copy.name).as_uri(), f"--virtual-time-budget={LOAD_MILLISECONDS}", "--dump-dom"
        )
    finally:
        Path(copy.name).unlink()
    screenshot = screenshots / (page.replace("/", "_").removesuffix(".html") + ".png")
    screenshot.parent.mkdir(parents=True, exist_ok=True)
    _run_chromium(
        browser,
        source.as_uri(),
        f"--virtual-time-budget={LOAD_MILLISECONDS}",
        f"--window-size={WINDOW}",
        f"--screenshot={screenshot}",
    )
    problems = []
    marker = f'{BROKEN_ATTRIBUTE}="'
    if marker not in dom:
        problems.append(f"{page}: the browser did not finish loading it")
    else:
        broken = dom.split(marker, 1)[1].split('"', 1)[0]
        problems += [f"{page}: {src}: did not load in the browser" for src in broken.split() if broken != "none"]
    with Image.open(screenshot) as picture:
        if picture.convert("L").getextrema()[0] == picture.convert("L").getextrema()[1]:
            problems.append(f"{page}: its screenshot {screenshot} is blank")
    print(f"{page}: rendered to {screenshot}")
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("site", nargs="?", type=Path, default=Path("docs/_build/html"), help="the built site")
    parser.add_argument("--screenshots", type=Path, default=Path("docs/_build/screenshots"), help="where the PNGs go")
    parser.add_argument("--no-browser", action="store_true", help="check links and images only")
    args = parser.parse_args(argv)
    if not (args.site / "index.html").is_file():
        print(f"check_site: no site at {args.site}: build it first", file=sys.stderr)
        return 2
    problems = broken_links(args.site)
    browser = None if args.no_browser else chromium()
    if browser is None and not args.no_browser:
        print("check_site: chromium is not installed (apt-get install chromium): links and images only")
    for page in BROWSER_PAGES if browser else ():
        problems += browse(args.site, page, args.screenshots, browser)
    for problem in problems:
        print(problem)
    pages = sum(1 for _ in args.site.rglob("*.html"))
    print(f"check_site: {pages} pages, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
