"""Files that live in the source checkout, not in the installed package: the reference images
(tests/references/) and app.py. Found relative to the checkout wgputrace is imported from."""

from __future__ import annotations

from pathlib import Path

import wgputrace

# A folder is the checkout when it holds these beside the package.
_MARKERS = ("pyproject.toml", "tests")


class NotInCheckoutError(FileNotFoundError):
    """wgputrace was imported from an installed copy, which has no tests/ or app.py beside it."""


def checkout_root() -> Path:
    """The checkout holding the imported wgputrace package."""
    package = Path(wgputrace.__file__).resolve().parent
    root = package.parent
    if not all((root / marker).exists() for marker in _MARKERS):
        raise NotInCheckoutError(
            f"wgputrace is imported from {package}, which is not inside a source checkout "
            f"(no {' or '.join(_MARKERS)} beside it): clone the repository and install it editable "
            "(pip install -e '.[test]') to use the files under tests/"
        )
    return root


def checkout_file(*parts: str) -> Path:
    """A file of the checkout, e.g. checkout_file("tests", "references", "cornell.npz")."""
    path = checkout_root().joinpath(*parts)
    if not path.exists():
        raise NotInCheckoutError(f"{path} does not exist in the checkout at {checkout_root()}")
    return path
