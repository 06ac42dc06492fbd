"""Where a benchmark ran and on what: the checkout and its git revision, versions and machine
facts, and the machine's load while it ran. `result_files.write_result` puts all of it in every
result."""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent
# Where results are written by default; changes there do not make a revision dirty (`git_revision`).
RESULTS_DIR = REPO_ROOT / "bench" / "results"


def git(*arguments: str, repo: Path = REPO_ROOT) -> str:
    """The output of `git ARGUMENTS` in the checkout; CalledProcessError (with git's stderr) if it fails."""
    return subprocess.run(["git", *arguments], cwd=repo, capture_output=True, text=True, check=True).stdout.strip()


def git_revision(repo: Path = REPO_ROOT) -> str:
    """`git rev-parse --short HEAD`, plus "-dirty" when anything outside bench/results differs from HEAD.

    Untracked files count: a module not yet committed is still code that ran. Result files do not,
    so a previous run's output cannot mark the next run dirty.
    """
    try:
        head = git("rev-parse", "--short", "HEAD", repo=repo)
        changes = git("status", "--porcelain", "--", ".", ":(exclude)bench/results", repo=repo)
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return f"{head}-dirty" if changes else head


@contextmanager
def worktree(revision: str) -> Iterator[Path]:
    """A detached checkout of `revision` in a temporary folder, removed afterwards."""
    with tempfile.TemporaryDirectory(prefix="wgputrace-baseline-") as folder:
        path = Path(folder) / revision
        try:
            git("worktree", "add", "--detach", str(path), revision)
        except subprocess.CalledProcessError as error:
            raise SystemExit(f"cannot check out {revision}: {error.stderr.strip()}") from None
        try:
            yield path
        finally:
            git("worktree", "remove", "--force", str(path))


def cpu_model() -> str:
    """The processor's name, which a CPU adapter's speed depends on as much as on its core count."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def environment() -> dict:
    """Versions and machine facts that change benchmark numbers."""
    import wgpu
    import wgpu.backends.wgpu_native as wgpu_native

    import wgputrace
    from wgputrace.gpu.device import describe

    return {
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "wgpu": wgpu.__version__,
        "wgpu_native": wgpu_native.__version__,
        "wgputrace": wgputrace.__version__,
        # the driver and its version, e.g. "Mesa 22.3.6 (LLVM 15.0.6)": lavapipe's speed changes with Mesa's
        "driver": describe()["description"],
        "platform": platform.platform(),
        "cpu": cpu_model(),
        "cpu_count": os.cpu_count(),
        # llvmpipe runs one thread per core unless told otherwise.
        "LP_NUM_THREADS": os.environ.get("LP_NUM_THREADS"),
        "command": typed_command(sys.argv, sys.executable),
    }


def typed_command(argv: Sequence[str], python: str) -> str:
    """`python ARGV` as typed in the checkout's root: a module of the checkout as `-m bench.NAME`, a
    script inside it by its relative path, and an absolute path argument as DIR (--out's) or PATH,
    so that no folder of the machine it ran on is recorded."""
    program, *arguments = argv
    words = [Path(python).name, *typed_program(program)]
    for previous, argument in zip(["", *arguments], arguments, strict=False):
        option, equals, value = argument.partition("=") if argument.startswith("--") else ("", "", argument)
        if Path(value).is_absolute():
            value = "DIR" if "--out" in (option, previous) else "PATH"
        words.append(f"{option}{equals}{value}")
    return " ".join(words)


def typed_program(program: str) -> list[str]:
    """sys.argv[0] as typed: `-m bench` for bench/__main__.py, `-m bench.throughput` for a module run
    with -m, a script's path relative to the checkout, `-m pytest` for another package's __main__.py."""
    path = Path(program)
    if not path.is_file():  # "-c", or the interactive interpreter's ""
        return [program]
    path = path.resolve()
    inside = path.is_relative_to(REPO_ROOT)
    relative = path.relative_to(REPO_ROOT) if inside else path
    packages = list(relative.parents)[:-1]
    if inside and packages and all((REPO_ROOT / package / "__init__.py").is_file() for package in packages):
        parts = relative.with_suffix("").parts
        return ["-m", ".".join(parts[:-1] if parts[-1] == "__main__" else parts)]
    # another package's, wherever it is installed (a virtual environment inside the checkout too)
    if path.name == "__main__.py":
        return ["-m", path.parent.name]
    return [relative.as_posix() if inside else path.name]


def recorded_path(path: Path) -> str:
    """A file as a result names it: relative to the checkout when inside it, else by its name alone."""
    path = Path(path).resolve()
    return path.relative_to(REPO_ROOT).as_posix() if path.is_relative_to(REPO_ROOT) else path.name


def load_average() -> list[float] | None:
    """1/5/15-minute load: other processes on a CPU adapter's cores slow it down."""
    try:
        return [round(value, 2) for value in os.getloadavg()]
    except OSError:
        return None


@dataclass
class Run:
    """A benchmark's start and the machine's load then; `write_result` records both ends."""

    started: float = field(default_factory=time.perf_counter)
    load_before: list[float] | None = field(default_factory=load_average)

    def record(self) -> dict:
        return {
            "load_average_before_after": [self.load_before, load_average()],
            "wall_seconds": time.perf_counter() - self.started,
        }
