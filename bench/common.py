"""What every benchmark records besides its numbers (git revision, adapter, versions, machine load), and
where its files go: `write_result` is the one way a benchmark writes its results."""

from __future__ import annotations

import json
import os
import platform
import re
import subprocess
import sys
from collections.abc import Callable
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent
RESULTS_DIR = REPO_ROOT / "bench" / "results"


def git_revision(repo: Path = REPO_ROOT) -> str:
    """`git rev-parse --short HEAD`, plus "-dirty" when anything outside bench/results differs from HEAD.

    Untracked files count: a module not yet committed is still code that ran. Result files do not,
    so a previous run's output cannot mark the next run dirty.
    """
    try:
        head = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=repo, capture_output=True, text=True, check=True
        ).stdout.strip()
        changes = subprocess.run(
            ["git", "status", "--porcelain", "--", ".", ":(exclude)bench/results"],
            cwd=repo,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return f"{head}-dirty" if changes else head


def slug(*parts: str) -> str:
    """File-name-safe lower-case words joined by '-': ("llvmpipe (LLVM 15.0.6)", "Vulkan") -> llvmpipe-llvm-15-0-6-vulkan."""
    return "-".join(word for part in parts for word in re.findall(r"[a-z0-9]+", part.lower()))


def environment() -> dict:
    """Versions and machine facts that change benchmark numbers."""
    import wgpu
    import wgpu.backends.wgpu_native as wgpu_native

    import wgputrace

    return {
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "wgpu": wgpu.__version__,
        "wgpu_native": wgpu_native.__version__,
        "wgputrace": wgputrace.__version__,
        "platform": platform.platform(),
        "cpu_count": os.cpu_count(),
        # llvmpipe runs one thread per core unless told otherwise.
        "LP_NUM_THREADS": os.environ.get("LP_NUM_THREADS"),
        "command": " ".join([Path(sys.executable).name, *sys.argv]),
    }


def load_average() -> list[float] | None:
    """1/5/15-minute load: other processes on a CPU adapter's cores slow it down."""
    try:
        return [round(value, 2) for value in os.getloadavg()]
    except OSError:
        return None


def write_json(path: Path, data: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2) + "\n")


# What a result file must say about the picture it measured; None where one does not apply (a BVH
# build renders nothing), so a missing key is always an oversight.
SETTINGS_KEYS = ("scene", "width", "height", "spp", "max_depth")


def result_stem(name: str, out: Path = RESULTS_DIR) -> Path:
    """out/<name>_<adapter slug>: results from different adapters sit side by side."""
    from wgputrace.gpu.device import describe

    adapter = describe()
    return out / f"{name}_{slug(adapter['adapter'], adapter['backend'])}"


def write_result(
    name: str,
    data: dict,
    *,
    out: Path = RESULTS_DIR,
    plot: Callable[[Path, dict], None] | None = None,
) -> dict[str, Path]:
    """Write `data` with the metadata every result carries as <stem>.json (stem: `result_stem`), and
    `plot(png_path, result)` as <stem>.png where given; returns the paths by kind ("json", "png").

    The metadata (benchmark name, git revision, adapter, versions, load average now) comes first in
    the file and is what `plot` sees too, so a chart can name adapter and revision. `data` must hold
    SETTINGS_KEYS.
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
        **data,
    }
    stem = result_stem(name, out)
    paths = {"json": stem.with_suffix(".json")}
    write_json(paths["json"], result)
    if plot is not None:
        paths["png"] = stem.with_suffix(".png")
        plot(paths["png"], result)
    return paths
