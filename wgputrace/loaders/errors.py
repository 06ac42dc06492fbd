"""The one error type every loader and the scene resolver raise, and the warning for what a
loader repaired or skipped."""

from __future__ import annotations

from pathlib import Path


class SceneLoadError(ValueError):
    """A scene cannot be loaded. `path` is the file at fault (an .mtl or .bin beside the file
    asked for, perhaps; None for an unknown built-in name), `line` its 1-based line for text
    formats and Python scenes (None for binary ones); the message starts with both and names the
    problem."""

    def __init__(self, path: Path | str | None, problem: str, line: int | None = None) -> None:
        self.path = None if path is None else Path(path)
        self.line, self.problem = line, problem
        where = [str(part) for part in (self.path, line) if part is not None]
        super().__init__(": ".join([":".join(where), problem] if where else [problem]))

    def __reduce__(self):
        # rebuilt from the fields __init__ takes (not from the message), so that it crosses processes
        # (Ray workers) as itself
        return SceneLoadError, (self.path, self.problem, self.line)


class SceneLoadWarning(UserWarning):
    """A loader repaired or skipped something: a missing material, inconsistently wound triangles."""
