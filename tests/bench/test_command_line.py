"""bench.command_line: every benchmark's counts are checked alike."""

from __future__ import annotations

import pytest

from bench.command_line import argument_parser, parse


def test_counts_below_one_are_refused(capsys):
    parser = argument_parser("A benchmark.\n\nMore.", spp=4, repeats=3)
    parser.add_argument("--runs", type=int, default=1)
    assert parse(parser, ["--spp", "2"], "runs").spp == 2
    for argv in (["--spp", "0"], ["--repeats", "-1"], ["--runs", "0"]):
        with pytest.raises(SystemExit):
            parse(parser, argv, "runs")
        assert f"{argv[0]} {argv[1]}" in capsys.readouterr().err
