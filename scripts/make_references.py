"""Reference images from Mitsuba 3 for the render tests: tests/references/<scene>.npz.

    pip install -e ".[reference]"                     # mitsuba>=3.5
    python scripts/make_references.py                 # every reference scene
    python scripts/make_references.py cornell --passes 8 --variant scalar_rgb
    python scripts/make_references.py --list          # the references and the cases compared with each

It imports wgputrace as installed (editable, from this checkout) and writes into that checkout.
Which references there are and how each is rendered is wgputrace.testing.reference_cases'
REFERENCES, the registry the reference tests read their cases from.

Each scene is built in Mitsuba from our own triangles, materials and camera
(wgputrace.reference.mitsuba_scene) and rendered with Mitsuba's `path` integrator (`volpath`
where a material absorbs inside) at the same max depth and a box pixel filter; its environment
and lights become Mitsuba's `constant`, `envmap`, `point`, `spot` and `directional` emitters. Several passes with different seeds give a per-pixel mean and
its standard error; both are stored as float16 with the settings and versions used.

The `llvm_ad_rgb` variant is much faster but needs LLVM 16 or newer (Debian: libllvm19; the stock
LLVM 15 aborts, 14 is too old): it is used when DRJIT_LIBLLVM_PATH is set or Debian's libLLVM-19 is
installed, `scalar_rgb` (pip wheels alone) otherwise.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import asdict
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from wgputrace import load_scene
from wgputrace.reference.mitsuba_scene import choose_variant, load_mitsuba, mitsuba_scene
from wgputrace.testing.checkout import checkout_root
from wgputrace.testing.reference_cases import CASES, REFERENCE_SIZE, REFERENCES, ReferenceSettings

REFERENCE_DIR = checkout_root() / "tests" / "references"
WIDTH = HEIGHT = REFERENCE_SIZE
FLOAT16_MAX = float(np.finfo(np.float16).max)


def render_passes(mi, scene, name: str, settings: ReferenceSettings) -> tuple[np.ndarray, np.ndarray]:
    """Per-pixel mean and standard error of `passes` independent Mitsuba renders."""
    images = []
    for seed in range(settings.passes):
        image = np.asarray(mi.render(scene, spp=settings.spp, seed=seed), dtype=np.float64)
        bad = np.argwhere(~np.isfinite(image))
        if len(bad):
            row, column, channel = bad[0]
            raise RuntimeError(
                f"{name}: Mitsuba pass {seed} has {len(bad)} non-finite values, the first at row {row}, "
                f"column {column}, channel {channel}: {image[row, column, channel]}"
            )
        images.append(image)
        print(f"  pass {seed + 1}/{settings.passes}", file=sys.stderr, end="\r", flush=True)
    stack = np.stack(images)
    return stack.mean(axis=0), stack.std(axis=0, ddof=1) / np.sqrt(settings.passes)


def to_float16(name: str, label: str, values: np.ndarray) -> np.ndarray:
    too_big = np.argwhere(values > FLOAT16_MAX)
    if len(too_big):
        row, column, channel = too_big[0]
        raise ValueError(
            f"{name}: {label} at row {row}, column {column}, channel {channel} is {values[row, column, channel]:.6g}, "
            f"above float16's largest value {FLOAT16_MAX}"
        )
    return values.astype(np.float16)


def make_reference(name: str, settings: ReferenceSettings, variant: str, out_dir: Path) -> Path:
    import drjit

    mi = load_mitsuba(variant)
    start = time.perf_counter()
    scene = mitsuba_scene(mi, load_scene(name), WIDTH, HEIGHT, settings.max_depth)
    mean, standard_error = render_passes(mi, scene, name, settings)
    seconds = time.perf_counter() - start
    metadata = {
        "scene": name,
        "width": WIDTH,
        "height": HEIGHT,
        **asdict(settings),
        "renderer": "mitsuba",
        "integrator": "path",
        "mitsuba": mi.__version__,
        "drjit": drjit.__version__,
        "variant": variant,
        "seconds": round(seconds, 1),
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / f"{name}.npz"
    np.savez_compressed(
        path,
        mean=to_float16(name, "mean", mean),
        standard_error=to_float16(name, "standard error", standard_error),
        metadata=np.array(json.dumps(metadata)),
    )
    print(f"{name}: {settings.passes} x {settings.spp} spp in {seconds:.1f} s -> {path}", file=sys.stderr)
    return path


def list_references(names: list[str]) -> str:
    """One line per reference: its settings and the cases compared with it."""
    lines = []
    for name in names:
        settings = REFERENCES[name]
        cases = ", ".join(f"{case.family}:{case.name}" for case in CASES if case.reference == name)
        lines.append(
            f"{name}: max depth {settings.max_depth}, {settings.passes} x {settings.spp} spp at {WIDTH}x{HEIGHT}; "
            f"cases {cases}"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="*", default=list(REFERENCES), help=f"default: {' '.join(REFERENCES)}")
    parser.add_argument("--variant", help="Mitsuba variant (default: llvm_ad_rgb where LLVM >= 16 is found)")
    parser.add_argument("--spp", type=int, help="samples per pixel per pass (default: per scene)")
    parser.add_argument("--passes", type=int, help="independent passes (default: per scene)")
    parser.add_argument("--out", type=Path, default=REFERENCE_DIR, help=f"output folder (default {REFERENCE_DIR})")
    parser.add_argument("--list", action="store_true", help="list the references and their cases, render nothing")
    args = parser.parse_args(argv)
    unknown = [name for name in args.scenes if name not in REFERENCES]
    if unknown:
        parser.error(f"no reference settings for {', '.join(unknown)}; known: {', '.join(REFERENCES)}")
    if args.list:
        print(list_references(args.scenes))
        return 0
    variant = choose_variant(args.variant)
    for name in args.scenes:
        settings = REFERENCES[name]
        settings = ReferenceSettings(
            settings.max_depth, args.spp or settings.spp, args.passes if args.passes else settings.passes
        )
        make_reference(name, settings, variant, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
