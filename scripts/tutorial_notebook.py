"""Write docs/tutorials/library.ipynb from docs/tutorials/library.md (its prose as Markdown cells,
its Python blocks as code cells), after editing the page:

    PYTHONPATH=. python scripts/tutorial_notebook.py

tests/docs/test_tutorials.py runs the page's blocks and fails while the notebook differs from it.
"""

from __future__ import annotations

from pathlib import Path

from wgputrace.testing.doc_pages import notebook_text

PAGE = Path(__file__).resolve().parents[1] / "docs" / "tutorials" / "library.md"

if __name__ == "__main__":
    PAGE.with_suffix(".ipynb").write_text(notebook_text(PAGE))
    print(f"wrote {PAGE.with_suffix('.ipynb')}")
