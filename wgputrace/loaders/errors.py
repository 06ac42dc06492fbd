"""The one error type every loader raises, and the warning for what a loader repaired or skipped."""

from __future__ import annotations

from pathlib import Path


class SceneLoadError(ValueError):
    """A scene file cannot be loaded. `path` is the file at fault (an .mtl or .bin beside the file
    asked for, perhaps), `line` its 1-based line for text formats (None for binary ones); the
    message starts with both and names the problem."""

    def __init__(self, path: Path | str, problem: str, line: int | None = None) -> None:
        self.path, self.line, self.problem = Path(path), line, problem
        where = f"{self.path}:{line}" if line is not None else str(self.path)
        super().__init__(f"{where}: {problem}")


class SceneLoadWarning(UserWarning):
    """A loader repaired or skipped something: a missing material, inconsistently wound triangles."""
