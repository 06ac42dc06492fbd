"""The viewer's denoiser (Shift+D): Intel Open Image Denoise's picture of the resting camera's
samples once it is ready (DenoisedPicture makes it in the background, again as the samples grow);
while the camera moves, and wherever OIDN is not installed, the a-trous filter's picture instead."""

from __future__ import annotations

import dataclasses
import sys

from ..denoise import DenoiserMissing, denoiser_device
from ..view.denoised import DenoisedPicture, DenoiseFailure
from ..view.display import ViewSettings
from ..view.layout import View


class ViewerDenoiser:
    """Whether OIDN's picture is asked for (`on`), OIDN's device or why it cannot run here
    (`missing`), both asked once per viewer, and which picture of a view's samples a frame shows.
    `settings` are the viewer's own, read as the keys change them."""

    def __init__(self, on: bool, settings: ViewSettings) -> None:
        self.on = on
        self.settings = settings
        self.missing: str | None = None
        self._device: str | None = None

    def device(self) -> str | None:
        """OIDN's device ("CPU", "CUDA"), or None where it cannot run (`missing` says why, once on
        the console too)."""
        if self._device is None and self.missing is None:
            try:
                self._device = denoiser_device()
            except DenoiserMissing as missing:
                self.missing = str(missing)
                print(f"wgputrace view: {missing}; the a-trous filter serves instead", file=sys.stderr, flush=True)
        return self._device

    def wanted_device(self) -> str | None:
        """OIDN's device for a new view: None with the denoiser off."""
        return self.device() if self.on else None

    def _denoised(self, view) -> DenoisedPicture | None:
        """The denoised picture where the frame may show it: the denoiser on, the radiance view."""
        if not self.on or view is None or self.settings.view != View.RADIANCE:
            return None
        return view.denoised

    def update(self, view, now: float, *, start: bool = True) -> str | None:
        """Let the denoised picture start (where `start`) or collect a denoise; a failure switches
        the denoiser off and comes back as the status line saying so."""
        denoised = self._denoised(view)
        if denoised is None:
            return None
        try:
            denoised.update(now, start=start)
        except DenoiseFailure as failure:
            self.on = False
            print(f"wgputrace view: {failure}; the denoiser is off", file=sys.stderr, flush=True)
            return f"{failure}; the denoiser is off"
        return None

    def picture(self, view, moving: bool):
        """What the frame shows: the texture and the size of the image in it from its top-left
        corner. OIDN's picture where it is ready; else the resolved samples (display_settings)."""
        denoised = self._denoised(view)
        if denoised is not None and denoised.shown:
            return denoised.texture, view.banded.full_size
        return view.display.render(self.display_settings(view, moving)), view.banded.size

    def display_settings(self, view, moving: bool) -> ViewSettings:
        """The settings the resolved image is shown with: with the denoiser on, through the a-trous
        filter while the camera moves and wherever OIDN cannot run. Not at rest while OIDN's first
        picture is on its way: filtering the whole window every frame of the first full-size pass
        made that pass (and so the denoise) 5 times slower at 640x480 on lavapipe; the first pass
        comes in over the last filtered preview instead (the fallback)."""
        serves = self.on and (moving or view.denoised is None)
        return dataclasses.replace(self.settings, filter_enabled=True) if serves else self.settings

    def shown_label(self, view) -> str:
        """Which picture of the samples the radiance view shows: "OIDN (CPU), 16 spp", "a-trous" or "raw"."""
        denoised = self._denoised(view)
        if denoised is not None and denoised.shown:
            return denoised.label()
        return "a-trous" if view.display.filter_weight > 0.0 else "raw"

    def state(self, view) -> str:
        """The overlay's "on" or "off", with the time the last denoise took."""
        denoised = view.denoised
        if self.on and denoised is not None and denoised.last_seconds is not None:
            return f"on (last took {denoised.last_seconds:.2f} s)"
        return "on" if self.on else "off"

    def notice(self) -> list[str]:
        """The overlay's red line while Shift+D asks for a denoiser that cannot run here."""
        if self.on and self.missing is not None:
            return [f"Shift+D: {self.missing}; the a-trous filter serves instead"]
        return []
