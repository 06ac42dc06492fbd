"""The benchmark pages, generated from bench/results/*.json when the site builds, so that no figure is
copied by hand into prose: an index of every result with the newest error-against-time chart, and a
page per benchmark with, for each adapter's result, where it ran (revision, adapter, driver, CPU,
date: from the file), its settings, its chart (the PNG beside the JSON) and its figures as tables.
The benchmark's own docstring (bench/<name>.py) says what it measures."""

from __future__ import annotations

import ast
import json
from dataclasses import dataclass
from pathlib import Path

from sphinx.application import Sphinx

from .generated_files import markdown_table, plain_text, remove_stale, write_page

ROOT = Path(__file__).parents[2]
RESULTS = ROOT / "bench" / "results"
INDEX, FOLDER = "benchmarks/index.md", "benchmarks/results"
# the error-against-time chart the index shows: the newest of this benchmark's charts
ERROR_AGAINST_TIME = "convergence"
# keys every result carries (result_files.write_result), shown as its provenance, not as figures
PROVENANCE_KEYS = (
    "benchmark",
    "git_revision",
    "git_revision_note",
    "adapter",
    "adapter_name",
    "environment",
    "load_average_at_write",
    "load_average_before_after",
    "load_average",
    "load_average_before",
    "load_average_after",
    "device",
    "wall_seconds",
    "command",
)
SETTINGS_KEYS = ("scene", "width", "height", "resolution", "size", "spp", "max_depth", "repeats", "seed")
# a list longer than this is summarised by its length: the JSON holds it whole
LONGEST_LIST = 8
# levels of nesting shown; deeper values are left to the JSON
MAX_DEPTH = 3


@dataclass(frozen=True)
class Result:
    path: Path
    data: dict

    @property
    def benchmark(self) -> str:
        return self.data.get("benchmark") or self.path.stem.split("_")[0]

    @property
    def device(self) -> dict:
        """The adapter's description (`describe()`); older results name the adapter in a string."""
        device = self.data.get("adapter") or self.data.get("device")
        return device if isinstance(device, dict) else {"adapter": device} if device else {}

    @property
    def adapter(self) -> str:
        return self.data.get("adapter_name") or self.device.get("adapter") or self.path.stem.split("_", 1)[-1]

    @property
    def created(self) -> str:
        """When it was written, ISO 8601 UTC ("" for results older than the field)."""
        return self.data.get("environment", {}).get("created_utc", "")

    @property
    def date(self) -> str:
        """`created` to the minute, as the pages show it: 2026-12-02 02:10."""
        return self.created[:16].replace("T", " ")

    def relative(self, suffix: str, page: str) -> str | None:
        """The file beside the JSON with `suffix`, as a path from the page `page` (srcdir-relative), or None."""
        path = self.path.with_suffix(suffix)
        if not path.is_file():
            return None
        depth = page.count("/") + 1  # docs/<page's folders>/ up to the checkout's root
        return "../" * depth + path.relative_to(ROOT).as_posix()


def results() -> list[Result]:
    found = [Result(path, json.loads(path.read_text())) for path in sorted(RESULTS.glob("*.json"))]
    return sorted(found, key=lambda result: (result.benchmark, result.created), reverse=False)


def bench_docstring(benchmark: str) -> str:
    """What bench/<benchmark>.py says it measures (the suite's: bench/__main__.py), read without
    importing it (its imports need the bench extra)."""
    name = "__main__" if benchmark == "suite" else benchmark
    path = ROOT / "bench" / f"{name}.py"
    if not path.is_file():
        return ""
    return plain_text(ast.get_docstring(ast.parse(path.read_text())) or "")


def _scalar(value: object) -> bool:
    return value is None or isinstance(value, (str, int, float, bool))


def _text(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, list) and all(_scalar(v) for v in value):
        return ", ".join(_text(v) for v in value) if len(value) <= LONGEST_LIST else f"({len(value)} values)"
    return str(value)


def _records(value: object) -> tuple[list[str] | None, list[dict]] | None:
    """(row labels or None, records) where `value` is a dict or list of flat records (dicts of
    scalars, or of short lists of them): one table; else None."""
    records = list(value.values()) if isinstance(value, dict) else value if isinstance(value, list) else None
    flat = records and all(
        isinstance(r, dict)
        and r
        and all(_scalar(v) or isinstance(v, list) and all(map(_scalar, v)) for v in r.values())
        for r in records
    )
    if not flat:
        return None
    return (list(value) if isinstance(value, dict) else None), records


def _tables(value: object, path: str, depth: int, rows: list, sections: list) -> None:
    """Walk a result: groups of flat records become tables (a section each), other leaves rows of
    `rows`; past MAX_DEPTH levels the rest is left to the JSON."""
    found = _records(value)
    if found is not None:
        labels, records = found
        columns = list(dict.fromkeys(column for record in records for column in record))
        header = ([""] if labels else []) + columns
        table = [
            ([labels[i]] if labels else []) + [_text(record.get(column, "")) for column in columns]
            for i, record in enumerate(records)
        ]
        sections.append(f"### {path}\n\n{markdown_table(header, table)}")
    elif isinstance(value, dict) and depth < MAX_DEPTH:
        for key, item in value.items():
            _tables(item, f"{path}.{key}" if path else str(key), depth + 1, rows, sections)
    elif isinstance(value, list) and not all(map(_scalar, value)) and len(value) <= LONGEST_LIST and depth < MAX_DEPTH:
        for index, item in enumerate(value):
            _tables(item, f"{path}[{index}]", depth + 1, rows, sections)
    elif isinstance(value, (dict, list)) and not (isinstance(value, list) and all(map(_scalar, value))):
        rows.append((path, "(in the JSON)"))
    else:
        rows.append((path, _text(value)))


def figures(data: dict) -> str:
    """The result's figures: groups of flat records as tables, other values as key-value rows."""
    rows, sections = [], []
    for key, value in data.items():
        if key not in PROVENANCE_KEYS and key not in SETTINGS_KEYS:
            _tables(value, key, 1, rows, sections)
    scalars = f"### Figures\n\n{markdown_table(('figure', 'value'), rows)}" if rows else ""
    return "\n".join([scalars, *sections])


def provenance(result: Result) -> str:
    data, environment, adapter = result.data, result.data.get("environment", {}), result.device
    facts = [
        ("git revision", f"`{data.get('git_revision', '')}`"),
        ("note on the revision", data.get("git_revision_note")),
        ("adapter", result.adapter),
        ("driver", environment.get("driver") or adapter.get("description")),
        ("CPU", environment.get("cpu")),
        ("CPU cores", environment.get("cpu_count")),
        ("platform", environment.get("platform")),
        ("Python, numpy, wgpu", ", ".join(str(environment.get(k, "?")) for k in ("python", "numpy", "wgpu"))),
        ("measured (UTC)", result.date),
        ("command", f"`{environment['command']}`" if environment.get("command") else data.get("command")),
        ("wall time", f"{data['wall_seconds']:.0f} s" if isinstance(data.get("wall_seconds"), float) else None),
        ("load average when written", _text(data.get("load_average_at_write", ""))),
    ]
    facts += [(key, _text(data[key])) for key in SETTINGS_KEYS if data.get(key) is not None]
    return markdown_table(("", ""), [(name, value) for name, value in facts if value not in (None, "", "None")])


def result_section(result: Result, page: str) -> str:
    chart = result.relative(".png", page)
    downloads = [
        f"{{download}}`{suffix[1:].upper()} <{path}>`"
        for suffix in (".json", ".csv")
        if (path := result.relative(suffix, page))
    ]
    parts = [f"## {result.adapter}\n", provenance(result)]
    if chart:
        parts.append(f"![{result.benchmark} on {result.adapter}]({chart})\n")
    parts.append(f"The whole result: {', '.join(downloads)} (`{result.path.name}`).\n")
    parts.append(figures(result.data))
    return "\n".join(parts)


def benchmark_page(benchmark: str, found: list[Result]) -> str:
    page = f"{FOLDER}/{benchmark}.md"
    about = bench_docstring(benchmark)
    sections = [result_section(result, page) for result in sorted(found, key=lambda r: r.created, reverse=True)]
    return f"# {benchmark}\n\n{about}\n\n" + "\n".join(sections)


def index_page(by_benchmark: dict[str, list[Result]]) -> str:
    rows = [
        (
            f"[{benchmark}](results/{benchmark}.md)",
            result.adapter,
            f"`{result.data.get('git_revision', '')}`",
            result.date,
        )
        for benchmark, found in by_benchmark.items()
        for result in found
    ]
    charts = [r for r in by_benchmark.get(ERROR_AGAINST_TIME, []) if r.relative(".png", INDEX)]
    newest = max(charts, key=lambda r: r.created, default=None)
    chart = ""
    if newest is not None:
        chart = (
            f"## Error against time\n\nThe newest [{ERROR_AGAINST_TIME}](results/{ERROR_AGAINST_TIME}.md) chart: "
            f"{newest.adapter}, revision `{newest.data.get('git_revision', '')}`, measured {newest.date} UTC.\n\n"
            f"![Error against time, {newest.adapter}]({newest.relative('.png', INDEX)})\n\n"
        )
    toctree = "\n".join(f"results/{benchmark}" for benchmark in by_benchmark)
    return (
        "# Benchmark results\n\n"
        "Every result in `bench/results`, as its JSON file says it was measured: this page and the pages "
        "below are generated from those files when the site is built. How they are measured: "
        "[methods](methods.md); `python -m bench` runs the suite.\n\n"
        f"{chart}## Results\n\n"
        + markdown_table(("benchmark", "adapter", "revision", "measured (UTC)"), rows)
        + f"\n```{{toctree}}\n:hidden:\n\nmethods\n{toctree}\n```\n"
    )


def generate(app: Sphinx) -> None:
    srcdir = Path(app.srcdir)
    by_benchmark: dict[str, list[Result]] = {}
    for result in results():
        by_benchmark.setdefault(result.benchmark, []).append(result)
    write_page(srcdir / INDEX, index_page(by_benchmark))
    written = []
    for benchmark, found in by_benchmark.items():
        written.append(srcdir / FOLDER / f"{benchmark}.md")
        write_page(written[-1], benchmark_page(benchmark, found))
    remove_stale(srcdir / FOLDER, "*.md", written)


def setup(app: Sphinx) -> dict[str, object]:
    app.connect("builder-inited", generate)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
