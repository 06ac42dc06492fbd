"""The one way a result is written: <benchmark>_<adapter slug>.json with the metadata every result
carries (`provenance`), its chart beside it, and a CSV where the rows matter."""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Sequence
from pathlib import Path

from bench.command_line import log
from bench.provenance import RESULTS_DIR, Run, environment, git_revision, load_average

# What a result file must say about the picture it measured; None where one does not apply (a BVH
# build renders nothing), so a missing key is always an oversight.
SETTINGS_KEYS = ("scene", "width", "height", "spp", "max_depth")


def slug(*parts: str) -> str:
    """File-name-safe lower-case words joined by '-': ("llvmpipe (LLVM 15.0.6)", "Vulkan") -> llvmpipe-llvm-15-0-6-vulkan."""
    return "-".join(word for part in parts for word in re.findall(r"[a-z0-9]+", part.lower()))


def result_stem(name: str, out: Path = RESULTS_DIR) -> Path:
    """out/<name>_<adapter slug>: results from different adapters sit side by side."""
    from wgputrace.gpu.device import describe

    adapter = describe()
    return out / f"{name}_{slug(adapter['adapter'], adapter['backend'])}"


def write_json(path: Path, data: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2) + "\n")


def write_result(
    name: str,
    data: dict,
    *,
    out: Path = RESULTS_DIR,
    plot: Callable[[Path, dict], None] | None = None,
    run: Run | None = None,
) -> dict[str, Path]:
    """Write `data` with the metadata every result carries as <stem>.json (stem: `result_stem`), and
    `plot(png_path, result)` as <stem>.png where given; says where on stderr and returns the paths
    by kind ("json", "png").

    The metadata (benchmark name, git revision, adapter, versions, load average now; with `run`,
    the load when it started and its wall time) comes first in the file and is what `plot` sees
    too, so a chart can name adapter and revision. `data` must hold SETTINGS_KEYS.
    """
    from wgputrace.gpu.device import describe

    missing = [key for key in SETTINGS_KEYS if key not in data]
    if missing:
        raise ValueError(f"the {name} result lacks {', '.join(missing)}: record each, None where it does not apply")
    result = {
        "benchmark": name,
        "git_revision": git_revision(),
        "adapter": describe(),
        "environment": environment(),
        "load_average_at_write": load_average(),
        **(run.record() if run else {}),
        **data,
    }
    stem = result_stem(name, out)
    paths = {"json": stem.with_suffix(".json")}
    write_json(paths["json"], result)
    if plot is not None:
        paths["png"] = stem.with_suffix(".png")
        plot(paths["png"], result)
    log(f"wrote {' and '.join(str(path) for path in paths.values())}")
    return paths


def write_csv(name: str, rows: list[dict], columns: Sequence[str], out: Path) -> Path:
    """Rows (dicts with `columns`) as <stem>.csv beside the JSON."""
    path = result_stem(name, out).with_suffix(".csv")
    lines = [",".join(columns)] + [",".join(str(row[column]) for column in columns) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    log(f"wrote {path}")
    return path


def record_skip(name: str, settings: dict, reason: str, out: Path) -> int:
    """File why `name` did not run as <name>_skipped_<adapter>.json; the suite reports it as skipped."""
    write_result(f"{name}_skipped", {**settings, "skipped": reason}, out=out)
    print(f"{name} skipped: {reason} (recorded in {result_stem(f'{name}_skipped', out)}.json)")
    return 0
