"""What the page generators share: pages written only when their text changed (so that Sphinx reads
again only what did), stale pages removed, docstrings as Markdown, and Markdown tables."""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from pathlib import Path


def write_page(path: Path, text: str) -> None:
    """Write `text` to `path` unless it holds that text already."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)


def remove_stale(folder: Path, pattern: str, keep: Iterable[Path]) -> None:
    """Remove the files of `folder` matching `pattern` that this build did not generate (a plugin or a
    result that is gone)."""
    kept = {path.resolve() for path in keep}
    for path in folder.glob(pattern):
        if path.resolve() not in kept:
            path.unlink()


def plain_text(docstring: str) -> str:
    """A docstring as Markdown that reads as written: `<adapter>` in "results_<adapter>.json" is a
    placeholder, not an HTML tag (code spans and indented code are left alone: Markdown shows their
    < as it is)."""
    return "\n".join(line if line.startswith("    ") else _escaped(line) for line in docstring.split("\n"))


def _escaped(line: str) -> str:
    parts = re.split(r"(`[^`]*`)", line)
    return "".join(part if part.startswith("`") else part.replace("<", "\\<") for part in parts)


def cell(value: object) -> str:
    """A value as a Markdown table cell: one line, its pipes escaped."""
    return " ".join(str(value).split()).replace("|", "\\|")


def markdown_table(header: Sequence[str], rows: Iterable[Sequence[object]]) -> str:
    lines = ["| " + " | ".join(cell(name) for name in header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(cell(value) for value in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"
