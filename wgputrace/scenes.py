"""Scenes available by name on the command line."""

from __future__ import annotations

from collections.abc import Callable

from .scene import Scene, cornell_box

BUILTIN_SCENES: dict[str, Callable[[], Scene]] = {"cornell": cornell_box}
DEFAULT_SCENE = "cornell"


def default_scene() -> Scene:
    """The trac0r Cornell box (listing 16 of the thesis)."""
    return BUILTIN_SCENES[DEFAULT_SCENE]()


def scene_by_name(name: str) -> Scene:
    try:
        return BUILTIN_SCENES[name]()
    except KeyError:
        raise ValueError(f"unknown scene {name!r}; built-in scenes: {', '.join(sorted(BUILTIN_SCENES))}") from None
