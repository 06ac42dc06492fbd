"""Every built-in scene under every integrator and sampler (and the flat list and the denoiser's
guides on the Cornell box), small and short, to check that a change leaves renders bit for bit as
they were at the same seed.

    python scripts/render_matrix.py --out after.npz
    PYTHONPATH=OLD_CHECKOUT python scripts/render_matrix.py --out before.npz   (run by path, not -m)
    python scripts/render_matrix.py --compare before.npz after.npz

The renders use whichever wgputrace Python imports, so PYTHONPATH selects the checkout measured
(an older checkout needs no copy of this script). `--compare` exits 1 if any image differs.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

SIZE = (64, 48)
SPP = 4
SEED = 3
# The default scene as the README's first command renders it, for full-size coverage.
DEFAULT_SIZE = 512
DEFAULT_SPP = 2


def methods() -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The integrators and samplers of the checkout imported (older ones named them elsewhere)."""
    try:
        from wgputrace.integrators import integrator_names
        from wgputrace.kernels.sampler import SAMPLERS
    except ImportError:
        from wgputrace.gpu.generated import INTEGRATORS as names
        from wgputrace.gpu.sampler import SAMPLERS

        return names, SAMPLERS
    return integrator_names(), SAMPLERS


def render_matrix() -> dict[str, np.ndarray]:
    import wgputrace as wt
    from wgputrace.scenes import BUILTIN_SCENES

    def mean(scene, **options) -> np.ndarray | None:
        """The render, or None where the integrator refuses the scene (bdpt an absorbing material)."""
        try:
            renderer = wt.Renderer(scene, *SIZE, seed=SEED, **options)
        except ValueError as refusal:
            print(f"skipped: {refusal}", file=sys.stderr)
            return None
        renderer.render(SPP)
        return renderer.image()

    integrators, samplers = methods()
    renders = {
        f"{name}_{integrator}_{sampler}": mean(make(), integrator=integrator, sampler=sampler)
        for name, make in BUILTIN_SCENES.items()
        for integrator in integrators
        for sampler in samplers
    }
    images = {name: image for name, image in renders.items() if image is not None}
    images["cornell_flat"] = mean(BUILTIN_SCENES["cornell"](), accel="flat")
    guided = wt.Renderer(BUILTIN_SCENES["textured_asset"](), *SIZE, seed=SEED, guides=True)
    guided.render(SPP)
    images |= {f"textured_asset_guide_{name}": guide for name, guide in guided.guides().items()}
    images["default_512"] = wt.render(wt.default_scene(), DEFAULT_SPP, DEFAULT_SIZE, DEFAULT_SIZE, seed=1)
    return images


def differing(before: dict[str, np.ndarray], after: dict[str, np.ndarray]) -> list[str]:
    """Names of the images missing from `after` or not equal bit for bit."""
    return [name for name in before if name not in after or before[name].tobytes() != after[name].tobytes()]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--out", help="write the renders to this .npz")
    action.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"), help="compare two .npz files")
    args = parser.parse_args(argv)
    if args.out:
        images = render_matrix()
        np.savez(args.out, **images)
        print(f"wrote {len(images)} images to {args.out}")
        return 0
    before, after = (dict(np.load(path)) for path in args.compare)
    bad = differing(before, after)
    print(f"{len(before)} images: " + (f"differ: {', '.join(bad)}" if bad else "identical"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
