"""What the API reference (reference/api) adds to autodoc: the `wgputrace-kinds` directive, which
documents every registered material or light kind (so adding a kind adds its entry), each kind's
entry led by its module's docstring and a link to its plugin page, Markdown tables in docstrings
turned into reST tables, and two checks that make the page complete: every name of
`wgputrace.__all__` is documented, and every parameter of a documented function or constructor is
named in its docstring (else a build warning, an error under -W)."""

from __future__ import annotations

import inspect
import re
import sys

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.environment import BuildEnvironment
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

import wgputrace
from wgputrace.scene.lights import light_classes
from wgputrace.scene.materials import material_classes

logger = logging.getLogger(__name__)

FAMILIES = {"material": material_classes, "light": light_classes}
# parameters a docstring need not name: the receiver, and catch-alls that the text names as a group
UNNAMED_PARAMETERS = {"self", "cls", "args", "kwargs", "options"}


def _kinds() -> set[type]:
    return {cls for classes in FAMILIES.values() for cls in classes()}


class KindsDirective(SphinxDirective):
    """`wgputrace-kinds material` (or `light`): an autoclass entry for every registered kind."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        family = self.arguments[0]
        if family not in FAMILIES:
            raise self.error(f"wgputrace-kinds takes one of {', '.join(FAMILIES)}, got {family!r}")
        lines = []
        for cls in FAMILIES[family]():
            lines += [f".. autoclass:: wgputrace.{cls.__name__}", ""]
        container = nodes.section()
        nested_parse_with_titles(self.state, StringList(lines, source=self.get_source_info()[0]), container)
        return container.children


def _kind_docstring(cls: type) -> list[str]:
    """A kind's entry: its module docstring's first paragraph (the class has no docstring of its own:
    the module's parameter table is its documentation) and a link to its plugin page."""
    first = (inspect.getdoc(sys.modules[cls.__module__]) or "").split("\n\n")[0]
    return [
        *first.splitlines(),
        "",
        f"Parameters, ranges, Mitsuba 3 equivalent and a picture: :doc:`/reference/plugins/{cls.__name__.lower()}`.",
    ]


def _list_table(rows: list[list[str]], indent: str) -> list[str]:
    lines = [f"{indent}.. list-table::", f"{indent}   :header-rows: 1", ""]
    for row in rows:
        lines += [f"{indent}   * - {row[0]}"] + [f"{indent}     - {cell}" for cell in row[1:]]
    return [*lines, ""]


def tables_as_rest(lines: list[str]) -> list[str]:
    """Markdown pipe tables (a header, a |---| line, rows) as reST list-tables; other lines as they are."""
    out, i = [], 0
    while i < len(lines):
        stripped = lines[i].strip()
        following = lines[i + 1].strip() if i + 1 < len(lines) else ""
        if stripped.startswith("|") and re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", following):
            indent = lines[i][: len(lines[i]) - len(lines[i].lstrip())]
            table = []
            j = i
            while j < len(lines) and lines[j].strip().startswith("|"):
                if j != i + 1:
                    table.append([cell.strip() or " " for cell in lines[j].strip().strip("|").split("|")])
                j += 1
            out += _list_table(table, indent)
            i = j
        else:
            out.append(lines[i])
            i += 1
    return out


def _parameters(obj: object, what: str) -> list[str]:
    try:
        signature = inspect.signature(obj.__init__ if what == "class" else obj)
    except (TypeError, ValueError):
        return []
    return [name for name in signature.parameters if name not in UNNAMED_PARAMETERS]


def process_docstring(app: Sphinx, what: str, name: str, obj: object, options: object, lines: list[str]) -> None:
    if what == "class" and obj in _kinds():
        lines[:] = _kind_docstring(obj)
        return
    if what == "property":
        # napoleon reads a property docstring's first "x: y" as a type and a description; ours are prose
        lines[:] = (inspect.getdoc(obj) or "").splitlines()
    lines[:] = tables_as_rest(lines)
    if what not in ("function", "method", "class") or not name.startswith("wgputrace."):
        return
    text = "\n".join(lines)
    unnamed = [p for p in _parameters(obj, what) if not re.search(rf"(?<![\w]){re.escape(p)}(?![\w])", text)]
    if unnamed:
        where = inspect.getsourcefile(obj)
        logger.warning("%s (%s): its docstring does not name %s", name, where, ", ".join(unnamed))


def check_all_documented(app: Sphinx, env: BuildEnvironment) -> None:
    documented = env.get_domain("py").objects
    for name in wgputrace.__all__:
        if f"wgputrace.{name}" not in documented:
            logger.warning("wgputrace.%s is in wgputrace.__all__ but not in the API reference", name)


def setup(app: Sphinx) -> dict[str, object]:
    app.add_directive("wgputrace-kinds", KindsDirective)
    # after napoleon (priority 500), which has turned its sections into reST
    app.connect("autodoc-process-docstring", process_docstring, priority=600)
    app.connect("env-check-consistency", check_all_documented)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
