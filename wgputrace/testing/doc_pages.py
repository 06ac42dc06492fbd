"""The documentation's pages as the tests run them: a MyST Markdown page cut into prose and fenced
code blocks, each block with the test comment written above it, and a page turned into a Jupyter
notebook (prose as Markdown cells, Python blocks as code cells), so the notebook cannot drift from
the page it is made from.

A comment line `% test: WORD [rest]` (MyST hides `%` lines) just above a block's fence says how the
tests treat it: `skip why` shows it only; `parse` parses a `wgputrace` command line without running
it (a window would open); `needs module` runs it where `module` imports; `status N` expects that
exit status of a shell command; `slow` runs it only with the slow tests, on its own (it may not
rely on the blocks before it). Without a comment, `python` and `sh` blocks run."""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

# A fence and its info string: a language ("python"), or a MyST directive ("{toctree}").
FENCE = re.compile(r"^(?P<fence>`{3,}|~{3,})(?P<language>\S*)\s*$")
TEST_COMMENT = re.compile(r"^%\s*test:\s*(?P<word>\w+)\s*(?P<rest>.*?)\s*$")
RUNNABLE = ("python", "sh")
NOTEBOOK_FORMAT = (4, 5)


@dataclass(frozen=True)
class Block:
    """A fenced code block: its language, code, first line on the page (1-based) and test comment."""

    language: str
    code: str
    line: int
    test: str = ""
    test_argument: str = ""

    @property
    def runs(self) -> bool:
        return self.language in RUNNABLE and self.test in ("", "needs", "status", "slow")


@dataclass(frozen=True)
class Prose:
    """Markdown between code blocks, test comments left out."""

    text: str


def parts(path: Path) -> list[Block | Prose]:
    """The page at `path` in order: its prose and its code blocks."""
    result: list[Block | Prose] = []
    prose: list[str] = []

    def end_prose() -> None:
        text = "\n".join(prose).strip("\n")
        if text.strip():
            result.append(Prose(text))
        prose.clear()

    comment: re.Match | None = None
    lines = path.read_text().splitlines()
    number = 0
    while number < len(lines):
        line = lines[number]
        number += 1
        fence = FENCE.match(line)
        if fence is None:
            comment = TEST_COMMENT.match(line)
            if comment is None:
                prose.append(line)
            continue
        start = number
        code: list[str] = []
        while number < len(lines) and lines[number].strip() != fence["fence"]:
            code.append(lines[number])
            number += 1
        if number == len(lines):
            raise ValueError(f"{path}:{start}: the code block opened here is not closed")
        number += 1
        end_prose()
        test, argument = (comment["word"], comment["rest"]) if comment else ("", "")
        result.append(Block(fence["language"], "\n".join(code) + "\n", start + 1, test, argument))
        comment = None
    end_prose()
    return result


def code_blocks(path: Path) -> list[Block]:
    return [part for part in parts(path) if isinstance(part, Block)]


def _source(text: str) -> list[str]:
    return text.splitlines(keepends=True)


def notebook(path: Path) -> dict:
    """The page at `path` as a notebook: prose and non-Python blocks as Markdown cells, Python
    blocks as code cells (without outputs), in the page's order."""
    cells = []
    for part in parts(path):
        if isinstance(part, Block) and part.language == "python":
            source = _source(part.code.rstrip("\n"))
            cells.append(
                {"cell_type": "code", "execution_count": None, "metadata": {}, "outputs": [], "source": source}
            )
            continue
        text = part.text if isinstance(part, Prose) else f"```{part.language}\n{part.code}```"
        if cells and cells[-1]["cell_type"] == "markdown":
            cells[-1]["source"] = _source("".join(cells[-1]["source"]) + "\n\n" + text)
        else:
            cells.append({"cell_type": "markdown", "metadata": {}, "source": _source(text)})
    return {
        "cells": cells,
        "metadata": {
            "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
            "language_info": {"name": "python"},
        },
        "nbformat": NOTEBOOK_FORMAT[0],
        "nbformat_minor": NOTEBOOK_FORMAT[1],
    }


def notebook_text(path: Path) -> str:
    """`notebook(path)` as the .ipynb file's text."""
    return json.dumps(notebook(path), indent=1, ensure_ascii=False) + "\n"
