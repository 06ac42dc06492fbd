"""Prepare what scripts/gpu_measurements.sh carries to a lent GPU machine, which reaches no network:
the Python wheels the benchmarks need (for that machine's Python 3.12, at the versions installed
here), Mitsuba 3 cut down to the variants and plugins our scenes load so that one call's 64 MiB
holds it, and the Vulkan loader's Debian packages. Writes `.whl/` and `.gl/` in the checkout, both
excluded from git through .git/info/exclude.

    python scripts/gpu_payload.py            (run here, in the checkout's root)
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import zipfile
from importlib.metadata import version
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
WHEELS, DEBS = ROOT / ".whl", ROOT / ".gl"
# What the benchmarks import beyond what the lent machine's image holds (numpy, scipy, matplotlib,
# pillow, tqdm are there): at the versions this checkout was tested with.
PACKAGES = ("wgpu", "rendercanvas", "glfw", "OpenEXR", "trimesh", "cffi", "pycparser")
MITSUBA = "mitsuba"
# The variants the measurements use: CUDA's beside ours on the GPU, LLVM's to check the cut here;
# scalar_rgb is what mitsuba itself loads first.
KEPT_VARIANTS = ("cuda_ad_rgb", "llvm_ad_rgb", "scalar_rgb")
PLATFORMS = [f"manylinux_2_{n}_x86_64" for n in (17, 24, 27, 28, 31, 34, 35)] + ["manylinux2014_x86_64"]
CARRY_LIMIT = 64 * 2**20
VULKAN_DEBS = ("libvulkan1", "libegl1", "libglvnd0", "libopengl0", "libgl1", "libglx0", "libgles2")


def download(requirements: list[str], into: Path, *, here: bool = False) -> None:
    """Wheels for the lent machine's Python 3.12 (`here`: for this interpreter, to run them here)."""
    platforms = [word for platform in PLATFORMS for word in ("--platform", platform)]
    target = [] if here else ["--python-version", "3.12", "--implementation", "cp", *platforms, "--platform", "any"]
    subprocess.run(
        [sys.executable, "-m", "pip", "download", "-q", "--no-deps", "--only-binary=:all:", *target]
        + ["-d", str(into), *requirements],
        check=True,
    )


def used_plugins(requirements: list[str]) -> set[str]:
    """The Mitsuba plugins that loading every built-in scene and rendering it with each sampler the
    benchmarks use loads, read from the process's memory maps (a plugin is a shared library; the
    same plugins serve every Python version)."""
    probe = """
import mitsuba as mi
from wgputrace.reference.mitsuba_scene import LLVM_VARIANT, load_mitsuba, mitsuba_scene
from wgputrace.scenes import BUILTIN_SCENES
mi = load_mitsuba(LLVM_VARIANT)
for name, make in BUILTIN_SCENES.items():
    scene = mitsuba_scene(mi, make(), 8, 8, 4)
    for sampler in ("independent", "multijitter"):
        sensor = scene.sensors()[0]
        mi.render(scene, spp=1, sensor=sensor, seed=0)
        mi.load_dict({"type": sampler})
maps = open("/proc/self/maps").read()
print(" ".join(sorted({line.rsplit("/", 1)[1][:-3] for line in maps.splitlines() if "/mitsuba/plugins/" in line})))
"""
    with tempfile.TemporaryDirectory() as wheels, tempfile.TemporaryDirectory() as target:
        download(requirements, Path(wheels), here=True)
        install(Path(wheels), Path(target))
        out = run_probe(probe, Path(target))
    return set(out.split())


def install(wheels: Path, target: Path) -> None:
    subprocess.run(
        [sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target)]
        + [str(wheel) for wheel in wheels.glob("*.whl")],
        check=True,
    )


def run_probe(code: str, target: Path) -> str:
    env = {"PYTHONPATH": f"{target}:{ROOT}", "PATH": "/usr/bin:/bin"}
    return subprocess.run(
        [sys.executable, "-c", code], env=env, cwd=ROOT, check=True, capture_output=True, text=True
    ).stdout


def slimmed(wheel: Path, plugins: set[str], out: Path) -> Path:
    """`wheel` without the variants and plugins the measurements do not load."""

    def kept(name: str) -> bool:
        stem = name.rsplit("/", 1)[-1].split(".", 1)[0]
        if "/plugins/" in name and name.endswith(".so"):
            return stem in plugins
        is_variant = (
            name.count("/") == 1 and name.endswith(".so") and stem.split("_", 1)[0] in ("cuda", "llvm", "scalar")
        )
        return not is_variant or stem in KEPT_VARIANTS

    slim = out / wheel.name
    with zipfile.ZipFile(wheel) as source, zipfile.ZipFile(slim, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as target:
        for item in source.infolist():
            if kept(item.filename):
                target.writestr(item, source.read(item))
    return slim


def main(argv: list[str] | None = None) -> int:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    exclude = ROOT / ".git" / "info" / "exclude"
    listed = exclude.read_text() if exclude.exists() else ""
    exclude.write_text(listed + "".join(f"{line}\n" for line in ("/.whl/", "/.gl/") if line not in listed))
    WHEELS.mkdir(exist_ok=True)
    download([f"{name}=={version(name)}" for name in PACKAGES], WHEELS)
    # the package itself, as users install it (its version, its shaders inside)
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(WHEELS), str(ROOT)], check=True)
    with tempfile.TemporaryDirectory() as folder:
        full = Path(folder)
        download([f"{MITSUBA}=={version(MITSUBA)}" if _installed(MITSUBA) else MITSUBA], full)
        mitsuba_wheel = next(full.glob("mitsuba-*.whl"))
        pins = [
            mitsuba_wheel.name.split("-")[0] + "==" + mitsuba_wheel.name.split("-")[1],
            requirement(mitsuba_wheel, "drjit"),
        ]
        download(pins[1:], full)
        plugins = used_plugins(pins)
        slimmed(mitsuba_wheel, plugins, WHEELS)
        for wheel in full.glob("drjit-*.whl"):
            (WHEELS / wheel.name).write_bytes(wheel.read_bytes())
    DEBS.mkdir(exist_ok=True)
    lists = Path(tempfile.mkdtemp())
    options = ["-oAPT::Architecture=amd64", "-oAPT::Architectures=amd64", f"-oDir::State::Lists={lists}"]
    (lists / "partial").mkdir()
    subprocess.run(["apt-get", *options, "update", "-qq"], check=True)
    subprocess.run(["apt-get", *options, "download", *VULKAN_DEBS], cwd=DEBS, check=True)
    carried = sum(path.stat().st_size for folder in (WHEELS, DEBS) for path in folder.iterdir())
    tracked = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    tree = sum(
        (ROOT / name).stat().st_size for name in tracked.decode().split("\0") if name and (ROOT / name).is_file()
    )
    print(
        f"{len(plugins)} Mitsuba plugins kept; carried {carried / 2**20:.1f} MiB + tree {tree / 2**20:.1f} MiB "
        f"of {CARRY_LIMIT / 2**20:.0f} MiB a call"
    )
    return 0 if carried + tree <= CARRY_LIMIT else 1


def requirement(wheel: Path, name: str) -> str:
    """`wheel`'s requirement on `name` as its metadata states it (mitsuba pins its drjit)."""
    with zipfile.ZipFile(wheel) as archive:
        metadata = archive.read(next(item for item in archive.namelist() if item.endswith(".dist-info/METADATA")))
    prefix = f"Requires-Dist: {name}"
    return next(
        line[len("Requires-Dist: ") :].strip() for line in metadata.decode().splitlines() if line.startswith(prefix)
    )


def _installed(name: str) -> bool:
    try:
        version(name)
    except Exception:
        return False
    return True


if __name__ == "__main__":
    sys.exit(main())
