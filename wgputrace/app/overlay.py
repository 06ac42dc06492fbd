"""The debug overlay: lines of text drawn by Pillow into an RGBA array, which the present pass
blends over the picture. Redrawn a few times per second, never per frame."""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw, ImageFont

FONT_SIZE = 14
LINE_SPACING = 4
MARGIN = 8
BACKGROUND = (0, 0, 0, 170)
TEXT = (255, 255, 255, 255)
ERROR_TEXT = (255, 90, 90, 255)


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
