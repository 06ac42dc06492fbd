"""The debug overlay: lines of text drawn by Pillow into an RGBA array, which the present pass
blends over the picture. Redrawn a few times per second, never per frame (`Overlay`)."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
from PIL import Image, ImageDraw, ImageFont

FONT_SIZE = 14
LINE_SPACING = 4
MARGIN = 8
BACKGROUND = (0, 0, 0, 170)
TEXT = (255, 255, 255, 255)
ERROR_TEXT = (255, 90, 90, 255)
# The text is redrawn this often (Pillow costs milliseconds; per frame would show in the fps).
OVERLAY_SECONDS = 0.25
STATUS_SECONDS = 4.0
OVERLAY_POSITION = (8, 8)


def _font() -> ImageFont.ImageFont:
    try:
        return ImageFont.load_default(size=FONT_SIZE)
    except TypeError:  # Pillow built without FreeType: the fixed bitmap font
        return ImageFont.load_default()


def _wrap(measure: ImageDraw.ImageDraw, font, text: str, width: int | None) -> list[str]:
    """`text` in lines at most `width` pixels wide, broken at spaces (or inside words too long for a line)."""
    if width is None or measure.textlength(text, font=font) <= width:
        return [text]
    lines, current = [], ""
    for word in text.split(" "):
        candidate = f"{current} {word}" if current else word
        if measure.textlength(candidate, font=font) <= width:
            current = candidate
            continue
        if current:
            lines.append(current)
        while measure.textlength(word, font=font) > width and len(word) > 1:
            cut = 1
            while measure.textlength(word[: cut + 1], font=font) <= width:
                cut += 1
            lines.append(word[:cut])
            word = word[cut:]
        current = word
    return lines + [current] if current else lines


def text_overlay(lines: list[str], errors: list[str] | None = None, max_width: int | None = None) -> np.ndarray:
    """`errors` in red, then `lines` in white, on a translucent box, as (height, width, 4) uint8
    RGBA; at most `max_width` wide (longer lines are cut)."""
    font = _font()
    measure = ImageDraw.Draw(Image.new("RGBA", (1, 1)))
    # errors are wrapped, not cut: a person has to read all of them
    wrap_width = None if max_width is None else max_width - 2 * MARGIN
    wrapped = [part for error in errors or [] for part in _wrap(measure, font, error, wrap_width)]
    entries = [(line, ERROR_TEXT) for line in wrapped] + [(line, TEXT) for line in lines]
    boxes = [measure.textbbox((0, 0), text or " ", font=font) for text, _ in entries]
    line_height = max((box[3] for box in boxes), default=FONT_SIZE) + LINE_SPACING
    width = max((box[2] for box in boxes), default=1) + 2 * MARGIN
    if max_width is not None:
        width = max(min(width, max_width), 1)
    height = line_height * len(entries) + 2 * MARGIN - LINE_SPACING
    image = Image.new("RGBA", (width, max(height, 1)), BACKGROUND)
    draw = ImageDraw.Draw(image)
    for index, (text, color) in enumerate(entries):
        draw.text((MARGIN, MARGIN + index * line_height), text, font=font, fill=color)
    return np.asarray(image)


class Overlay:
    """When the overlay is redrawn (every OVERLAY_SECONDS, or at the next frame after a change),
    whether it shows the viewer's information (Tab), and a status line shown under it for
    STATUS_SECONDS."""

    def __init__(self, show_info: bool) -> None:
        self.show_info = show_info
        self.status = ""
        self._status_until = 0.0
        self._next = 0.0

    def redraw_soon(self) -> None:
        """Something shown changed: redraw at the next frame."""
        self._next = 0.0

    def show_status(self, message: str) -> None:
        self.status = message
        self._status_until = time.perf_counter() + STATUS_SECONDS
        self._next = 0.0

    def due(self, now: float) -> bool:
        return now >= self._next

    def redraw(
        self, presenter, now: float, size: tuple[int, int], info: Callable[[], list[str]], errors: list[str]
    ) -> None:
        """Give `presenter` the text for a window of `size`: `errors` in red, then `info()` and the status."""
        self._next = now + OVERLAY_SECONDS
        lines = info() if self.show_info else []
        if self.show_info and self.status and now < self._status_until:
            lines.append(self.status)
        if not lines and not errors:
            presenter.set_overlay(None)
            return
        max_width = max(size[0] - 2 * OVERLAY_POSITION[0], 1)
        presenter.set_overlay(text_overlay(lines, errors, max_width), OVERLAY_POSITION)
