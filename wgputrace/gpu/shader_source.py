"""WGSL from files under shaders/, joined by a tiny include mechanism.

A line `//! include "name.wgsl"` is replaced by that file (paths relative to shaders/). Each file
is included once per shader, a cycle is an error, and every line of the joined text remembers its
original file and line so compile errors can name them.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

_INCLUDE = re.compile(r'^\s*//!\s*include\s+"([^"]+)"\s*$')
_WGSL_LOCATION = re.compile(r"wgsl:(\d+):(\d+)")


class ShaderIncludeError(ValueError):
    """An include names a missing file or forms a cycle."""


def shader_root() -> Path:
    """shaders/ inside the installed wheel, else the source checkout's top-level shaders/."""
    packaged = Path(str(resources.files("wgputrace"))) / "shaders"
    return packaged if packaged.is_dir() else Path(__file__).resolve().parents[2] / "shaders"


@dataclass(frozen=True)
class ShaderSource:
    text: str
    origins: tuple[tuple[str, int], ...]  # (file, line) of each line of `text`, 1-based

    def locate(self, line: int) -> tuple[str, int]:
        return self.origins[line - 1]

    def explain(self, message: str) -> str:
        """Rewrite `wgsl:LINE:COL` positions of a compiler message into `file.wgsl:line:COL`."""

        def replace(match: re.Match) -> str:
            line = int(match.group(1))
            if not 1 <= line <= len(self.origins):
                return match.group(0)
            name, original = self.locate(line)
            return f"{name}:{original}:{match.group(2)}"

        return _WGSL_LOCATION.sub(replace, message)


def load_shader(entry: str, generated: dict[str, str] | None = None, root: Path | None = None) -> ShaderSource:
    """Join `entry` and everything it includes. `generated` maps virtual file names to text
    (the struct definitions made from gpu.layout, for instance)."""
    root = root or shader_root()
    generated = generated or {}
    lines: list[str] = []
    origins: list[tuple[str, int]] = []
    included: set[str] = set()

    def read(name: str, where: str) -> str:
        if name in generated:
            return generated[name]
        path = root / name
        if not path.is_file():
            raise ShaderIncludeError(f"{where}: included file {name!r} not found under {root}")
        return path.read_text()

    def visit(name: str, chain: tuple[str, ...], where: str) -> None:
        if name in chain:
            raise ShaderIncludeError(f"{where}: include cycle {' -> '.join(chain + (name,))}")
        if name in included:
            return
        included.add(name)
        for number, line in enumerate(read(name, where).splitlines(), start=1):
            match = _INCLUDE.match(line)
            if match:
                visit(match.group(1), chain + (name,), f"{name}:{number}")
            else:
                lines.append(line)
                origins.append((name, number))

    visit(entry, (), "entry point")
    return ShaderSource("\n".join(lines) + "\n", tuple(origins))
