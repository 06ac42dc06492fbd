"""Mitsuba 3 on the other side of a comparison: whether its `llvm_ad_rgb` variant can run here,
its renders timed with every output evaluated, its JIT kernels accounted for, and the threads
both renderers share the cores with."""

from __future__ import annotations

import importlib.util
import itertools
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from types import ModuleType

import numpy as np


def mitsuba_missing(variant: str = "llvm_ad_rgb") -> str | None:
    """Why Mitsuba's `variant` cannot run here, or None (a CUDA variant is known only once it runs)."""
    from wgputrace.reference.mitsuba_scene import libllvm_path

    # found, not imported: importing starts drjit, which then no longer reads DRJIT_CACHE_DIR
    if importlib.util.find_spec("mitsuba") is None:
        return "mitsuba is not installed: pip install -e '.[reference]'"
    if variant.startswith("llvm") and libllvm_path() is None:
        return f"Mitsuba's {variant} needs LLVM >= 16: install Debian's libllvm19 or set DRJIT_LIBLLVM_PATH"
    return None


def add_mitsuba_variant(parser) -> None:
    """--mitsuba-variant: llvm_ad_rgb on a CPU, cuda_ad_rgb beside ours on an NVIDIA GPU."""
    parser.add_argument(
        "--mitsuba-variant",
        default="llvm_ad_rgb",
        help="Mitsuba 3's variant (default llvm_ad_rgb; cuda_ad_rgb on an NVIDIA GPU)",
    )


def threads(drjit: ModuleType) -> dict:
    """The threads both renderers run on the shared cores: llvmpipe's (one per core unless
    LP_NUM_THREADS says otherwise) and drjit's pool."""
    return {
        "llvmpipe": int(os.environ.get("LP_NUM_THREADS") or os.cpu_count()),
        "drjit": drjit.thread_count(),
        "cpu_count": os.cpu_count(),
    }


# Far above any reference seed (0 .. passes - 1): reusing one would correlate a comparison's error
# with the reference's.
MITSUBA_SEED_START = 1_000_000


@dataclass
class MitsubaSide:
    """Mitsuba, its scenes by image size, and a seed that changes with every render."""

    mi: ModuleType
    dr: ModuleType
    scene_name: str
    seed_start: int = MITSUBA_SEED_START
    scenes: dict[int, object] = field(default_factory=dict)
    kernels: list[dict] = field(default_factory=list)  # drjit's history since the last kernel_report()

    def __post_init__(self) -> None:
        self.seeds = itertools.count(self.seed_start)

    def scene(self, size: int, max_depth: int):
        from wgputrace import load_scene
        from wgputrace.reference.mitsuba_scene import mitsuba_scene

        if size not in self.scenes:
            self.scenes[size] = mitsuba_scene(self.mi, load_scene(self.scene_name), size, size, max_depth)
        return self.scenes[size]

    def render(self, size: int, max_depth: int, spp: int) -> tuple[np.ndarray, float, float]:
        """A fresh image with a new seed: (image, wall seconds, process CPU seconds), evaluation included."""
        scene = self.scene(size, max_depth)
        image, wall, cpu = self.timed(lambda: self.mi.render(scene, spp=spp, seed=next(self.seeds)))
        return np.asarray(image, dtype=np.float32), wall, cpu

    def timed(self, launch: Callable[[], object]):
        """(result of `launch`, wall seconds, process CPU seconds), every output evaluated and waited for."""
        self.dr.sync_thread()
        wall, cpu = time.perf_counter(), time.process_time()
        result = launch()
        self.dr.eval(result)  # drjit is lazy: the kernel runs here
        self.dr.sync_thread()
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        self.kernels += [entry for entry in self.dr.kernel_history() if entry["type"] == self.dr.KernelType.JIT]
        return result, wall, cpu

    def kernel_report(self) -> dict:
        """The JIT kernels launched since the last report: compiled, loaded from disk, or reused from memory."""
        kernels, self.kernels = self.kernels, []
        compiled = [k for k in kernels if not k["cache_hit"]]
        return {
            "launches": len(kernels),
            "compiled": len(compiled),
            "loaded_from_disk_cache": sum(1 for k in kernels if k["cache_hit"] and k["cache_disk"]),
            "reused_from_memory": sum(1 for k in kernels if k["cache_hit"] and not k["cache_disk"]),
            "codegen_ms": sum(k["codegen_time"] for k in kernels),
            "llvm_backend_ms": sum(k["backend_time"] for k in kernels),
        }

    def compiled_nothing(self, what: str) -> dict:
        """The kernel report of timed work, which must not have compiled: the warm-up compiles."""
        report = self.kernel_report()
        if report["compiled"]:
            raise SystemExit(f"Mitsuba compiled {report['compiled']} kernels during {what}: the warm-up missed them")
        return report
