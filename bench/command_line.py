"""A benchmark's command line: the options every benchmark spells alike, the check that counts are
at least 1, and progress on stderr (stdout holds the summary)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from bench.error_curves import FIT_MIN_SPP
from bench.provenance import RESULTS_DIR
from wgputrace.cli_arguments import parse_size


def argument_parser(
    doc: str,
    *,
    size: tuple[int, int] | None = None,
    spp: int | None = None,
    repeats: int | None = None,
    seed: int | None = None,
) -> argparse.ArgumentParser:
    """A parser described by the first paragraph of `doc`, with --out and, for each default given,
    the option every benchmark spells the same way; `parse` checks the counts."""
    parser = argparse.ArgumentParser(description=" ".join(doc.split("\n\n")[0].split()))
    if size is not None:
        parser.add_argument("--size", type=parse_size, default=size, help=f"WIDTHxHEIGHT (default {size[0]}x{size[1]})")
    if spp is not None:
        parser.add_argument("--spp", type=int, default=spp, help=f"samples per pixel of a timed render (default {spp})")
    if repeats is not None:
        parser.add_argument("--repeats", type=int, default=repeats, help=f"timed runs; medians (default {repeats})")
    if seed is not None:
        parser.add_argument("--seed", type=int, default=seed, help=f"random seed (default {seed})")
    parser.add_argument("--out", type=Path, default=RESULTS_DIR, help="results folder (default bench/results)")
    return parser


def parse(parser: argparse.ArgumentParser, argv: list[str] | None, *counts: str) -> argparse.Namespace:
    """Parse `argv`; every option named in `counts` (and --spp, --repeats where present) must be at least 1."""
    args = parser.parse_args(argv)
    names = dict.fromkeys([*(name for name in ("spp", "repeats") if hasattr(args, name)), *counts])
    low = [f"--{name.replace('_', '-')} {getattr(args, name)}" for name in names if np.min(getattr(args, name)) < 1]
    if low:
        parser.error(f"must be at least 1: {', '.join(low)}")
    return args


def log(message: str) -> None:
    """Progress, on stderr: stdout holds the summary."""
    print(message, file=sys.stderr, flush=True)


def add_max_spp(parser: argparse.ArgumentParser, default: int) -> None:
    """--max-spp, the last checkpoint of a convergence curve: a power of two leaving a few to fit."""

    def power_of_two(text: str) -> int:
        value = int(text)
        if value < FIT_MIN_SPP * 4 or value & (value - 1):
            raise argparse.ArgumentTypeError(f"must be a power of two >= {FIT_MIN_SPP * 4}, got {value}")
        return value

    parser.add_argument("--max-spp", type=power_of_two, default=default, help=f"last checkpoint (default {default})")
