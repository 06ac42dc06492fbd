"""The package's layers, read from the source with `ast`: no import cycle between wgputrace's modules
(imports inside functions count too; imports under `if TYPE_CHECKING:` do not, as they never run and
serve annotations only), no import upwards across the layers, nothing imports the viewer's app but
the command line, nothing imports the test support, and no tracked file edits sys.path."""

from __future__ import annotations

import ast
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

import wgputrace

PACKAGE = Path(wgputrace.__file__).resolve().parent
CHECKOUT = PACKAGE.parent

# Lowest first; a module may import its own layer and the ones below. The key is the first name
# below `wgputrace` ("" for the package itself, whose __init__ is the public API).
LAYERS: tuple[frozenset[str], ...] = (
    frozenset({"scene", "bvh", "image_io", "denoise"}),  # pure numpy (denoise: and pyoidn)
    frozenset({"loaders", "scenes", "reference"}),  # scenes from files and names, and to Mitsuba
    frozenset({"gpu"}),  # the only layer that talks to wgpu's device
    frozenset({"kernels", "integrators"}),  # what a kernel compiles in, and the integrators' descriptors
    frozenset({"render", "provenance", "", "cluster", "temporal_frames"}),  # "": the package, which offers wt.cluster
    frozenset({"view"}),  # the viewer's GPU side
    frozenset({"cli_arguments"}),  # arguments the command line and the viewer share
    frozenset({"app", "cli", "__main__"}),
    frozenset({"testing"}),  # test and benchmark support: may import anything
)
# Imported by nobody in the package except these modules (a module inside the package is exempt).
IMPORTED_ONLY_BY = {"app": {"wgputrace.cli"}, "testing": set()}
# The test support may import anything, the viewer's app included.
MAY_IMPORT_ANYTHING = {"testing"}
# wgputrace.cli opens the viewer's package only when the `view` command runs.
LAZY_ONLY = {("wgputrace.cli", "app")}
SYS_PATH_EDITS = {"insert", "append", "extend", "remove", "pop", "clear"}


def module_name(path: Path) -> str:
    parts = path.relative_to(CHECKOUT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}


def layer_key(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def layer_of(module: str) -> int:
    key = layer_key(module)
    for level, keys in enumerate(LAYERS):
        if key in keys:
            return level
    raise AssertionError(f"{module} has no layer: add {key!r} to LAYERS in {Path(__file__).name}")


def imports(module: str) -> Iterator[tuple[str, int, bool]]:
    """(imported wgputrace module, line, whether the import runs inside a function) for every import
    statement of `module`. `from package import name` counts as importing package.name when that is
    a module, else the package."""
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    tree = ast.parse(path.read_text(), str(path))
    functions = [node for node in ast.walk(tree) if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)]
    lazy = {id(inner) for function in functions for inner in ast.walk(function)}
    typing_only = {id(inner) for block in ast.walk(tree) if _is_type_checking(block) for inner in ast.walk(block)}
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                source = f"{base}.{node.module}" if node.module else base
            else:
                source = node.module or ""
            targets = [
                f"{source}.{alias.name}" if f"{source}.{alias.name}" in MODULES else source for alias in node.names
            ]
        else:
            continue
        for target in targets:
            while target and target not in MODULES:  # `import wgputrace.a.b` names a module; trim names
                target = target.rpartition(".")[0]
            if target.startswith("wgputrace") and target != module:
                yield target, node.lineno, id(node) in lazy


def _is_type_checking(node: ast.AST) -> bool:
    """An `if TYPE_CHECKING:` block."""
    return isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING"


GRAPH = {module: sorted({target for target, _, _ in imports(module)}) for module in MODULES}


def test_every_module_has_a_layer():
    for module in MODULES:
        layer_of(module)


def test_no_import_cycle():
    """Depth-first search; the first cycle found is reported as a chain of modules."""
    state: dict[str, str] = {}  # "open" while on the current path, "done" after

    def visit(module: str, path: list[str]) -> list[str] | None:
        state[module] = "open"
        for target in GRAPH[module]:
            if state.get(target) == "open":
                return path[path.index(target) :] + [target] if target in path else [module, target]
            if target not in state and (cycle := visit(target, [*path, target])):
                return cycle
        state[module] = "done"
        return None

    for module in MODULES:
        if module not in state and (cycle := visit(module, [module])):
            pytest.fail("import cycle: " + " -> ".join(cycle))


def test_imports_go_down_the_layers():
    upward = [
        f"{MODULES[module].relative_to(CHECKOUT)}:{line}: {module} ({layer_key(module) or 'wgputrace'}) "
        f"imports {target} ({layer_key(target) or 'wgputrace'}), a higher layer"
        for module in MODULES
        for target, line, _ in imports(module)
        if layer_of(target) > layer_of(module)
    ]
    assert not upward, "\n".join(upward)


def test_app_and_testing_are_imported_only_where_allowed():
    wrong = []
    for module in MODULES:
        for target, line, lazy in imports(module):
            key = layer_key(target)
            if key not in IMPORTED_ONLY_BY or layer_key(module) in {key, *MAY_IMPORT_ANYTHING}:
                continue
            where = f"{MODULES[module].relative_to(CHECKOUT)}:{line}: {module} imports {target}"
            if module not in IMPORTED_ONLY_BY[key]:
                wrong.append(f"{where}; only {sorted(IMPORTED_ONLY_BY[key]) or 'tests and bench'} may")
            elif (module, key) in LAZY_ONLY and not lazy:
                wrong.append(f"{where} at module level; import it inside the function that needs it")
    assert not wrong, "\n".join(wrong)


def is_sys_path(node: ast.AST) -> bool:
    return (
        isinstance(node, ast.Attribute)
        and node.attr == "path"
        and isinstance(node.value, ast.Name)
        and node.value.id == "sys"
    )


def sys_path_edits(tree: ast.AST) -> Iterator[int]:
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            if node.func.attr in SYS_PATH_EDITS and is_sys_path(node.func.value):
                yield node.lineno
        elif isinstance(node, ast.Assign | ast.AugAssign | ast.AnnAssign | ast.Delete):
            targets = node.targets if isinstance(node, ast.Assign | ast.Delete) else [node.target]
            for target in targets:
                if is_sys_path(target) or (isinstance(target, ast.Subscript) and is_sys_path(target.value)):
                    yield node.lineno


def test_the_sys_path_check_finds_edits():
    # spelled in pieces so that a plain-text search for sys.path edits finds none in this file
    path = "sys." + "path"
    source = f"import sys\n{path}.insert(0, 'x')\n{path} += ['y']\n{path}[0] = 'z'\nprint({path})\n"
    assert sorted(sys_path_edits(ast.parse(source))) == [2, 3, 4]


@pytest.mark.skipif(shutil.which("git") is None or not (CHECKOUT / ".git").exists(), reason="not a git checkout")
def test_no_file_edits_sys_path():
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard", "*.py"],
        cwd=CHECKOUT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    edits = [
        f"{name}:{line}"
        for name in listed
        if (CHECKOUT / name).is_file()
        for line in sys_path_edits(ast.parse((CHECKOUT / name).read_text(), name))
    ]
    assert not edits, "sys.path edited at " + ", ".join(edits)
