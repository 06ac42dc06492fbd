"""wgputrace.testing.checkout: the files of the source checkout are found from the imported
package, and an installed copy without them is told so, naming where it was imported from."""

from __future__ import annotations

from pathlib import Path

import pytest

import wgputrace
from wgputrace.testing.checkout import NotInCheckoutError, checkout_file, checkout_root
from wgputrace.testing.references import load_reference, reference_dir


def test_the_checkout_is_the_folder_holding_the_imported_package():
    root = checkout_root()
    assert root == Path(wgputrace.__file__).resolve().parents[1]
    assert checkout_file("app.py") == root / "app.py"
    assert reference_dir() == root / "tests" / "references"


def test_a_missing_file_names_its_path(tmp_path):
    with pytest.raises(NotInCheckoutError, match=r"tests/references/nowhere\.npz does not exist"):
        checkout_file("tests", "references", "nowhere.npz")


def test_an_installed_copy_is_told_it_is_not_in_a_checkout(tmp_path, monkeypatch):
    installed = tmp_path / "site-packages" / "wgputrace"
    installed.mkdir(parents=True)
    monkeypatch.setattr(wgputrace, "__file__", str(installed / "__init__.py"))
    with pytest.raises(NotInCheckoutError, match=f"imported from {installed}, which is not inside a source checkout"):
        load_reference("cornell")
