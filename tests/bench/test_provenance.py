"""bench.provenance: a result records its command and files as typed in the checkout, never a
folder of the machine it ran on."""

from __future__ import annotations

from pathlib import Path

import pytest

from bench.provenance import REPO_ROOT, recorded_path, typed_command

PYTHON = "/opt/venv/bin/python"


@pytest.mark.parametrize(
    ("argv", "typed"),
    [
        (
            [REPO_ROOT / "bench" / "__main__.py", "--quick", "--out", "/elsewhere/run"],
            "python -m bench --quick --out DIR",
        ),
        (
            [REPO_ROOT / "bench" / "filter_psnr.py", "--spp", "1", "4", "--out=out"],
            "python -m bench.filter_psnr --spp 1 4 --out=out",
        ),
        ([REPO_ROOT / "bench" / "soak.py", "--out=/elsewhere/run"], "python -m bench.soak --out=DIR"),
        (
            [REPO_ROOT / "scripts" / "render_matrix.py", "--compare", "/a.npz", "b.npz"],
            "python scripts/render_matrix.py --compare PATH b.npz",
        ),
        (["-c", "--out", "results"], "python -c --out results"),
    ],
    ids=["suite", "benchmark", "out-equals", "script", "dash-c"],
)
def test_the_command_is_recorded_as_typed_in_the_checkout(argv, typed):
    assert typed_command([str(word) for word in argv], PYTHON) == typed


def test_another_packages_main_is_named_as_a_module():
    assert typed_command([str(Path(pytest.__file__).with_name("__main__.py")), "-q"], PYTHON) == "python -m pytest -q"


def test_a_result_file_is_recorded_relative_to_the_checkout(tmp_path):
    inside = REPO_ROOT / "bench" / "results" / "throughput_x.json"
    assert recorded_path(inside) == "bench/results/throughput_x.json"
    assert recorded_path(tmp_path / "run" / "throughput_x.json") == "throughput_x.json"
