"""render-frames' frame ranges and output patterns."""

from __future__ import annotations

from pathlib import Path

import pytest

from wgputrace.cluster.frames import frame_path, parse_frames


@pytest.mark.parametrize(("text", "frames"), [("0:240", range(0, 240)), ("3:9:3", range(3, 9, 3)), ("7", range(7, 8))])
def test_frame_ranges(text, frames):
    assert parse_frames(text) == frames


@pytest.mark.parametrize(
    ("text", "message"),
    [("a:b", "must look like 0:240"), ("5:2", "hold no frame"), ("0:9:0", "STEP >= 1"), ("-1:4", "START >= 0")],
)
def test_bad_frame_ranges_are_refused(text, message):
    with pytest.raises(ValueError, match=message):
        parse_frames(text)


def test_the_frame_fills_the_pattern():
    assert frame_path("out/{frame:04d}.png", 12) == Path("out/0012.png")


@pytest.mark.parametrize(("pattern", "message"), [("out.png", "has no {frame}"), ("{frames}.png", "use {frame}")])
def test_patterns_without_the_frame_are_refused(pattern, message):
    with pytest.raises(ValueError, match=message):
        frame_path(pattern, 0)
