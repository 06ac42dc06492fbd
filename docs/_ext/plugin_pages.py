"""A page per material kind, light kind and integrator, and one for the environment, generated under
reference/plugins when the site builds, as Mitsuba 3 generates its plugin pages: the parameters
from the class (dataclass fields: type and default) joined with the parameter table of its module
docstring (range and meaning), the rest of that docstring, the Mitsuba 3 plugin a default instance
exports to, and a small picture. Every registered kind gets its page, so adding a plugin adds it;
a parameter table that disagrees with the fields is a build warning."""

from __future__ import annotations

import inspect
import json
import pprint
import re
import sys
from dataclasses import MISSING, dataclass, fields
from pathlib import Path

import numpy as np
from sphinx.application import Sphinx
from sphinx.util import logging

from wgputrace.integrators import integrator, integrator_names
from wgputrace.reference.mitsuba_scene import bsdf_dict, emitter_dict
from wgputrace.scene.lights import light_classes
from wgputrace.scene.lights.environment import Environment
from wgputrace.scene.materials import material_classes

from . import plugin_pictures
from .generated_files import markdown_table, plain_text, remove_stale, write_page

logger = logging.getLogger(__name__)

FOLDER = "reference/plugins"
RESULTS = Path(__file__).parents[2] / "bench" / "results"


@dataclass(frozen=True)
class Docstring:
    """A plugin module's docstring cut around its parameter table: the table's rows by parameter
    (cells by lower-case column name), what comes before it and what after."""

    before: str
    rows: dict[str, dict[str, str]]
    after: str

    @classmethod
    def of(cls, module_name: str) -> Docstring:
        lines = plain_text(inspect.getdoc(sys.modules[module_name]) or "").splitlines()
        start = next((i for i, line in enumerate(lines) if _cells(line)[:1] == ["parameter"]), None)
        if start is None:
            return cls("\n".join(lines), {}, "")
        end = start
        while end < len(lines) and lines[end].startswith("|"):
            end += 1
        header = [name.lower() for name in _cells(lines[start])]
        rows = {}
        for line in lines[start + 2 : end]:
            values = dict(zip(header, _cells(line), strict=False))
            rows[values["parameter"].strip("`")] = values
        return cls("\n".join(lines[:start]).strip(), rows, "\n".join(lines[end:]).strip())


def _cells(line: str) -> list[str]:
    if not line.startswith("|"):
        return []
    return [cell.strip() for cell in line.strip().strip("|").split("|")]


def _check_table(name: str, docstring: Docstring, parameters: list[str], module: str) -> None:
    documented, declared = set(docstring.rows), set(parameters)
    if documented != declared:
        logger.warning(
            "%s: the parameter table of %s names %s; the class declares %s",
            name,
            module,
            sorted(documented - declared) or "nothing else",
            sorted(declared - documented) or "nothing else",
            location=sys.modules[module].__file__,
        )


def _default_text(default: object) -> str:
    if default is MISSING:
        return "required"
    return f"`{default!r}`"


def _meaning(row: dict[str, str]) -> str:
    return next((value for key, value in row.items() if key.startswith("meaning")), "")


def parameter_table(cls: type, docstring: Docstring) -> str:
    """The parameters of a dataclass kind: type and range, and meaning, from the docstring's table;
    the default from the field (with the docstring's where the field's is None: "3/4 of cutoff")."""
    rows = []
    for field in fields(cls):
        if field.name == "name":
            continue
        doc = docstring.rows.get(field.name, {})
        default = field.default_factory() if field.default_factory is not MISSING else field.default
        shown = _default_text(default)
        if default is None and doc.get("default", "None") not in ("", "None", "-"):
            shown = f"{shown}: {doc['default']}"
        rows.append((f"`{field.name}`", doc.get("type") or f"`{field.type}`", shown, _meaning(doc)))
    return markdown_table(("parameter", "type and range", "default", "meaning"), rows)


def _plain(value: object) -> object:
    """A Mitsuba dict with numpy numbers as Python floats, to 6 significant digits: as it reads."""
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if isinstance(value, (float, np.floating)):
        return float(f"{float(value):.6g}")
    return value


def _mitsuba_block(plugin: dict | None, what: str) -> str:
    if plugin is None:
        return f"No Mitsuba 3 {what}.\n"
    return f"```python\n{pprint.pformat(_plain(plugin), sort_dicts=False, width=100)}\n```\n"


def _call(cls: type, arguments: dict[str, object]) -> str:
    return f"{cls.__name__}({', '.join(f'{name}={value!r}' for name, value in arguments.items())})"


def _summary(text: str, title: str) -> str:
    """The index's line for a plugin: the first sentence of its docstring, less a leading "Title:"."""
    paragraph = re.sub(rf"^(the )?{title}:\s*", "", " ".join(text.split("\n\n")[0].split()), flags=re.IGNORECASE)
    return re.split(r"(?<=\.)\s", paragraph, maxsplit=1)[0].rstrip(".")


@dataclass(frozen=True)
class Page:
    slug: str
    title: str
    summary: str
    text: str


def material_page(cls: type, folder: Path) -> Page:
    docstring = Docstring.of(cls.__module__)
    _check_table(cls.__name__, docstring, list(cls.parameter_names()), cls.__module__)
    material = cls(name=cls.__name__.lower())
    slug = cls.__name__.lower()
    plugin_pictures.render_picture(folder / f"{slug}.png", plugin_pictures.material_scene(material))
    flags = [
        ("kind", f"`{cls.kind}` (WGSL `MATERIAL_{cls.kind_name}`)"),
        ("BSDF code", f"`{cls.shader.file}`" if cls.shader else "none: it reflects nothing, a path ends on it"),
        ("every lobe a delta", cls.delta),
        ("the same seen from both sides", cls.two_sided_wgsl or cls.two_sided),
        ("emits", cls.emission_wgsl is not None or material.emits()),
    ]
    text = f"""# {cls.__name__}

{docstring.before}

`wgputrace.{cls.__name__}`, a material: {{py:class}}`API <wgputrace.{cls.__name__}>`.

## Parameters

{parameter_table(cls, docstring)}
## How it works

{docstring.after}

{markdown_table(("what the renderer asks", "answer"), flags)}
## Mitsuba 3

`{cls.__name__}("{material.name}")`, its parameters at their defaults, exports to this BSDF:

{_mitsuba_block(bsdf_dict(material) if cls.shader else None, "BSDF: it reflects nothing")}
and this emitter (of each side):

{_mitsuba_block(emitter_dict(material), "emitter")}
## Picture

![{cls.__name__} with its default parameters]({slug}.png)

A sphere of `{cls.__name__}("{material.name}")` on a grey floor before light and dark stripes, under a square lamp
({plugin_pictures.WIDTH}x{plugin_pictures.HEIGHT}, {plugin_pictures.SPP} samples per pixel, rendered when this page was built).
"""
    return Page(slug, cls.__name__, _summary(docstring.before, cls.__name__), text)


def light_page(cls: type, folder: Path) -> Page:
    docstring = Docstring.of(cls.__module__)
    _check_table(cls.__name__, docstring, list(cls.parameter_names()), cls.__module__)
    arguments = plugin_pictures.example_arguments(cls)
    light, call = cls(**arguments), _call(cls, arguments)
    slug = cls.__name__.lower()
    plugin_pictures.render_picture(folder / f"{slug}.png", plugin_pictures.light_scene(light))
    flags = [
        ("kind", f"`{cls.kind}` (WGSL `LIGHT_{cls.kind_name}`)"),
        ("sampling code", f"`{cls.shader.file}`"),
        ("a delta light (only light sampling reaches it)", cls.delta),
        ("infinitely far", cls.distant),
        ("the parameter that scales `color`", f"`{cls.strength}`"),
    ]
    text = f"""# {cls.__name__}

{docstring.before}

`wgputrace.{cls.__name__}`, a light: {{py:class}}`API <wgputrace.{cls.__name__}>`; add it with
`scene.add_light(...)`.

## Parameters

{parameter_table(cls, docstring)}
## How it works

{docstring.after}

{markdown_table(("what the renderer asks", "answer"), flags)}
## Mitsuba 3

`{call}`, its other parameters at their defaults, exports to this emitter:

{_mitsuba_block(light.mitsuba_emitter(), "emitter of this form")}
## Picture

![{cls.__name__}]({slug}.png)

`{call}` alone lighting a sphere and a box before a wall
({plugin_pictures.WIDTH}x{plugin_pictures.HEIGHT}, {plugin_pictures.SPP} samples per pixel, rendered when this page was built).
"""
    return Page(slug, cls.__name__, _summary(docstring.before, cls.__name__), text)


def environment_page(folder: Path) -> Page:
    docstring = Docstring.of(Environment.__module__)
    parameters = [name for name in inspect.signature(Environment).parameters if name != "source"]
    _check_table("Environment", docstring, parameters, Environment.__module__)
    environment = plugin_pictures.example_environment()
    plugin_pictures.render_picture(folder / "environment.png", plugin_pictures.environment_scene(environment))
    signature = inspect.signature(Environment)
    rows = [
        (
            f"`{name}`",
            _default_text(MISSING if parameter.default is inspect.Parameter.empty else parameter.default),
            docstring.rows[name].get("type", ""),
            _meaning(docstring.rows[name]),
        )
        for name, parameter in signature.parameters.items()
        if name in docstring.rows
    ]
    text = f"""# Environment

{docstring.before}

`wgputrace.Environment`: {{py:class}}`API <wgputrace.Environment>`; set it with `scene.environment = ...`,
or read a map with `Environment.from_file(path, intensity, rotation_degrees, visible)`.

## Parameters

{markdown_table(("parameter", "default", "type", "meaning (Mitsuba 3)"), rows)}
## How it works

{docstring.after}

## Picture

![An environment map]({"environment.png"})

A mirror-like sphere on a floor under a 64x32 map made in numpy (blue sky, bright horizon, dark
ground, a small bright sun) and nothing else ({plugin_pictures.WIDTH}x{plugin_pictures.HEIGHT},
{plugin_pictures.SPP} samples per pixel, rendered when this page was built).
"""
    return Page("environment", "Environment", _summary(docstring.before, "Environment"), text)


def _latest_convergence() -> tuple[Path, dict] | None:
    """The newest convergence result that compares strategies scene by scene."""
    results = []
    for path in RESULTS.glob("convergence_*.json"):
        result = json.loads(path.read_text())
        if "table" in result:
            results.append((result["environment"]["created_utc"], path, result))
    if not results:
        return None
    _, path, result = max(results)
    return path, result


def measured_efficiency(name: str) -> str:
    """Where the integrator pays: its efficiency over mis per scene of the newest convergence result."""
    found = _latest_convergence()
    if found is None:
        return "No convergence result compares it yet.\n"
    path, result = found
    rows = []
    for scene, entry in result["table"].items():
        strategy = entry.get("strategies", {}).get(f"{name}/sobol")
        if strategy and "efficiency_over_mis/sobol" in strategy:
            rows.append((scene, f"{strategy['efficiency_over_mis/sobol']:.2f}x"))
    if not rows:
        return "No convergence result compares it yet.\n"
    return (
        f"Efficiency (1 / (error x time)) against `mis`, both with the Sobol sampler, in the newest result of "
        f"the convergence benchmark ({{doc}}`/benchmarks/results/convergence`, `{path.name}`, revision "
        f"`{result['git_revision']}`, {result['adapter']['adapter']}): above 1 it reaches an error sooner.\n\n"
        + markdown_table(("scene", "efficiency over mis"), rows)
    )


def integrator_page(name: str, folder: Path) -> Page:
    method = integrator(name)
    # an integrator's module is named as its kernel's file (path_tracer.py: integrators/path_tracer.wgsl)
    module = sys.modules.get(f"wgputrace.integrators.{Path(method.entry).stem}")
    docstring = plain_text((inspect.getdoc(module) if module else None) or "")
    plugin_pictures.render_picture(folder / f"{name}.png", plugin_pictures.integrator_scene(), integrator=name)
    facts = [
        ("kernel", f"`{method.entry}`"),
        ("in the viewer (a band-of-rows kernel)", f"`{method.rows_entry}`" if method.rows_entry else "no"),
        ("deepest path (`max_depth`)", method.max_depth or "no limit"),
        ("splats into any pixel (no tiles)", method.splats),
        ("override constants", ", ".join(f"`{key} = {value}`" for key, value in method.constants) or "none"),
    ]
    text = f"""# {name}

{method.description[0].upper()}{method.description[1:]}.

`wgputrace render --integrator {name}`, `wgputrace.render(scene, integrator="{name}")`,
`wgputrace.Renderer(scene, integrator="{name}")`.

{docstring}

{markdown_table(("what", "answer"), facts)}
## When it pays

{measured_efficiency(name)}
## Picture

![{name} on the {plugin_pictures.INTEGRATOR_SCENE} scene]({name}.png)

The `{plugin_pictures.INTEGRATOR_SCENE}` built-in scene (a glass sphere focusing a small lamp onto the
floor) with `{name}` at {plugin_pictures.SPP} samples per pixel, {plugin_pictures.WIDTH}x{plugin_pictures.HEIGHT}:
the integrator pages' pictures differ only in the integrator.
"""
    return Page(name, name, method.description, text)


def _index(families: dict[str, list[Page]]) -> str:
    sections = []
    for family, pages in families.items():
        rows = [(f"[{page.title}]({page.slug}.md)", page.summary) for page in pages]
        sections.append(f"## {family}\n\n{markdown_table(('plugin', 'what it is'), rows)}")
    toctree = "\n".join(page.slug for pages in families.values() for page in pages)
    return (
        "# Plugins\n\n"
        "Every material, light and integrator, and the environment: a page each, generated from its class when "
        "the site is built (its parameters, their ranges and defaults, the Mitsuba 3 plugin it equals, a small "
        "picture).\n\n" + "\n".join(sections) + f"\n```{{toctree}}\n:hidden:\n\n{toctree}\n```\n"
    )


def generate(app: Sphinx) -> None:
    folder = Path(app.srcdir) / FOLDER
    folder.mkdir(parents=True, exist_ok=True)
    families = {
        "Materials": [material_page(cls, folder) for cls in material_classes()],
        "Lights": [light_page(cls, folder) for cls in light_classes()] + [environment_page(folder)],
        "Integrators": [integrator_page(name, folder) for name in integrator_names()],
    }
    written = [folder / "index.md"]
    write_page(folder / "index.md", _index(families))
    for page in (page for pages in families.values() for page in pages):
        write_page(folder / f"{page.slug}.md", page.text)
        written += [folder / f"{page.slug}.md", folder / f"{page.slug}.png"]
    remove_stale(folder, "*", written)


def setup(app: Sphinx) -> dict[str, object]:
    app.connect("builder-inited", generate)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
