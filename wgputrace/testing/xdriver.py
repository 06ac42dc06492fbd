"""Driving a real X window from a test: find it, type keys, drag and scroll the mouse through the
XTEST extension (the events reach the program exactly as a person's would), and grab its pixels."""

from __future__ import annotations

import time

import numpy as np
from Xlib import XK, X, display
from Xlib.ext import xtest

# X buttons 4 and 5 are the mouse wheel, one notch per press.
WHEEL_UP, WHEEL_DOWN = 4, 5
POLL_SECONDS = 0.05


class XDriver:
    def __init__(self, name: str) -> None:
        self.display = display.Display()
        self.root = self.display.screen().root
        self.name = name

    def close(self) -> None:
        self.display.close()

    def find_window(self, title: str, timeout: float):
        """The top-level window whose title is `title`, waiting for it to appear."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for window in self.root.query_tree().children:
                if window.get_wm_name() == title:
                    return window
            time.sleep(POLL_SECONDS)
        raise TimeoutError(f"no window titled {title!r} appeared within {timeout} s")

    def _sync(self) -> None:
        self.display.sync()

    def pointer_to(self, window, x: int, y: int) -> None:
        """Move the pointer to (x, y) inside `window` (which, with no window manager, gives it the keyboard)."""
        origin = window.translate_coords(self.root, 0, 0)
        xtest.fake_input(self.display, X.MotionNotify, x=-origin.x + x, y=-origin.y + y)
        self._sync()

    def _keycode(self, key: str) -> int:
        keysym = XK.string_to_keysym(key)
        if keysym == 0:
            raise ValueError(f"no X keysym called {key!r}")
        return self.display.keysym_to_keycode(keysym)

    def key_down(self, key: str) -> None:
        xtest.fake_input(self.display, X.KeyPress, self._keycode(key))
        self._sync()

    def key_up(self, key: str) -> None:
        xtest.fake_input(self.display, X.KeyRelease, self._keycode(key))
        self._sync()

    def tap(self, key: str) -> None:
        self.key_down(key)
        self.key_up(key)

    def hold(self, key: str, seconds: float) -> None:
        self.key_down(key)
        time.sleep(seconds)
        self.key_up(key)

    def drag(self, window, start: tuple[int, int], end: tuple[int, int], steps: int) -> None:
        """Press the left button at `start`, move to `end` in `steps`, release."""
        self.pointer_to(window, *start)
        xtest.fake_input(self.display, X.ButtonPress, 1)
        self._sync()
        for k in range(1, steps + 1):
            self.pointer_to(
                window,
                start[0] + (end[0] - start[0]) * k // steps,
                start[1] + (end[1] - start[1]) * k // steps,
            )
            time.sleep(POLL_SECONDS)
        xtest.fake_input(self.display, X.ButtonRelease, 1)
        self._sync()

    def scroll(self, button: int, notches: int) -> None:
        for _ in range(notches):
            xtest.fake_input(self.display, X.ButtonPress, button)
            xtest.fake_input(self.display, X.ButtonRelease, button)
        self._sync()

    def resize(self, window, width: int, height: int) -> None:
        window.configure(width=width, height=height)
        self._sync()

    def grab(self, window) -> np.ndarray:
        """The window's pixels as (height, width, 3) uint8 RGB (8-bit sRGB, as shown)."""
        geometry = window.get_geometry()
        raw = window.get_image(0, 0, geometry.width, geometry.height, X.ZPixmap, 0xFFFFFFFF)
        pixels = np.frombuffer(raw.data, np.uint8).reshape(geometry.height, geometry.width, 4)
        return pixels[:, :, [2, 1, 0]].copy()  # a 24-bit TrueColor visual stores B, G, R, pad
