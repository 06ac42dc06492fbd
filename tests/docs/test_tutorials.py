"""The tutorials run as a reader runs them: each page's Python and shell blocks in order, in one
fresh folder, the Python blocks in one namespace, the shell commands with this checkout's Python
(`wgputrace ...` as `python -m wgputrace ...`). A block's test comment (wgputrace.testing.doc_pages)
skips it, parses it only, names the module it needs, its exit status, or leaves it to the slow
tests. The library's notebook is its page, cell for cell."""

from __future__ import annotations

import importlib.util
import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from wgputrace import load_scene
from wgputrace.cli import argument_parser
from wgputrace.testing.checkout import checkout_file, checkout_root
from wgputrace.testing.doc_pages import Block, code_blocks, notebook_text

PAGES = ("viewer", "headless", "library")
COMMAND_SECONDS = 120


def page_path(name: str) -> Path:
    return checkout_file("docs", "tutorials", f"{name}.md")


def commands(block: Block) -> list[list[str]]:
    """The block's command lines as argument lists, continuation lines joined, comments dropped."""
    text = block.code.replace("\\\n", " ")
    return [words for line in text.splitlines() if (words := shlex.split(line, comments=True))]


def as_run(words: list[str]) -> list[str]:
    if words[0] == "wgputrace":
        return [sys.executable, "-m", "wgputrace", *words[1:]]
    if words[0] == "python":
        return [sys.executable, *words[1:]]
    return words


def parse_only(words: list[str], where: str) -> None:
    """A viewer's command line, checked by the parser the program uses and its scene loaded (a
    window would open)."""
    if words[:2] == ["python", "app.py"]:
        words = ["wgputrace", "view", *words[2:]]
    assert words[0] == "wgputrace", f"{where}: only wgputrace command lines can be parsed, not {words}"
    load_scene(argument_parser().parse_args(words[1:]).scene)


def run_shell(block: Block, where: str) -> None:
    expected = int(block.test_argument) if block.test == "status" else 0
    environment = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(filter(None, [str(checkout_root()), os.environ.get("PYTHONPATH")])),
    }
    for words in commands(block):
        done = subprocess.run(as_run(words), capture_output=True, text=True, timeout=COMMAND_SECONDS, env=environment)
        assert done.returncode == expected, (
            f"{where}: `{shlex.join(words)}` exited with {done.returncode}, not {expected}:\n{done.stdout}\n{done.stderr}"
        )


def run(path: Path, blocks: list[Block]) -> None:
    namespace: dict = {"__name__": f"tutorial_{path.stem}"}
    for block in blocks:
        where = f"{path.name}:{block.line}"
        if block.test == "needs" and importlib.util.find_spec(block.test_argument) is None:
            continue
        if block.test == "parse":
            for words in commands(block):
                parse_only(words, where)
        elif block.runs and block.language == "python":
            exec(compile(block.code, where, "exec"), namespace)
        elif block.runs:
            run_shell(block, where)


@pytest.mark.gpu
@pytest.mark.parametrize("name", PAGES)
def test_the_page_runs(name, tmp_path, monkeypatch):
    path = page_path(name)
    blocks = code_blocks(path)
    assert any(block.runs for block in blocks), f"{path} has no block the test runs"
    monkeypatch.chdir(tmp_path)
    run(path, [block for block in blocks if block.test != "slow"])


@pytest.mark.gpu
@pytest.mark.slow
@pytest.mark.parametrize(
    "name", [name for name in PAGES if any(b.test == "slow" for b in code_blocks(page_path(name)))]
)
def test_the_pages_slow_blocks_run(name, tmp_path, monkeypatch):
    path = page_path(name)
    monkeypatch.chdir(tmp_path)
    run(path, [block for block in code_blocks(path) if block.test == "slow"])


def test_the_notebook_is_the_library_page():
    page = page_path("library")
    committed = page.with_suffix(".ipynb").read_text()
    assert committed == notebook_text(page), (
        f"{page.with_suffix('.ipynb').name} differs from {page.name}: run `PYTHONPATH=. python scripts/tutorial_notebook.py`"
    )
