"""The ways `bench.realtime` makes a moving picture under a frame budget, one player per mode, each
with its own renderer and its own copy of the fly-through's scene.

- `preview`: today's viewer while the camera moves (reset on every move): the viewer's own
  `FramePacing` picks the reduced size whose one sample per pixel fits its trace budget, its
  `BandedRenderer` traces it, its `Display` runs the a-trous filter and its `Presenter` scales the
  picture up to the window (nearest neighbour) and tones it. `PreviewPlayer` holds all of it.
- `temporal`, `temporal+svgf`, `temporal+svgf+oidn`: `Renderer.render_frame` (with `filtered`),
  the last with Intel Open Image Denoise on the filtered picture, guided by the frame's albedo and
  normal, its time counted in the frame. `TemporalPlayer` holds them; `SampleBudget` picks the
  samples per pixel that fit the budget, at least one.
- `upsampled+svgf`: the viewer's own moving picture (`TemporalPicture`, its default while the
  camera moves): `render_frame(filtered=True)` at the upscale factor `choose_upscale` takes for the
  frame's budget from each factor's measured cost, tracing one pixel of every f x f block where a
  full frame does not fit. `ViewerPlayer` holds it.
- `upsampled2`, `upsampled4`, `upsampled8` (not run unless named): the same picture at a fixed
  factor, one sample per traced pixel whatever the budget (`FixedFactorPlayer`): what each factor
  gives, its time recorded, to compare factors and the reconstruction's choices.

A mode is one entry of MODES: a name, a label, a colour and how to make its player.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from bench.fly_throughs import FlyThrough
from bench.frame_metrics import DISPLAY_TONE, displayed
from bench.validation import image_failures
from wgputrace import Renderer
from wgputrace.app.pacing import FramePacing
from wgputrace.denoise import denoise
from wgputrace.view.banded import COST_SMOOTHING, BandedRenderer
from wgputrace.view.display import Display, ViewSettings
from wgputrace.view.present import Presenter
from wgputrace.view.temporal_picture import TemporalPicture

# OIDN's quality in the timed mode: its interactive one.
OIDN_QUALITY = "fast"
# The presenter draws to this format; it encodes sRGB itself, as for a window of a plain format.
PRESENT_FORMAT = "rgba8unorm"
# Frames the sample budget measures before the run, after the one that compiles.
WARM_UP_FRAMES = 2


@dataclass
class Frame:
    """A mode's frame: the picture as displayed, the seconds it took, samples per pixel traced and
    the size traced at."""

    shown: np.ndarray
    seconds: float
    spp: float
    traced: tuple[int, int]


@dataclass(frozen=True)
class Settings:
    """What every player of a run shares."""

    width: int
    height: int
    budget_seconds: float
    seed: int
    max_depth: int


class SampleBudget:
    """Samples per pixel for the next frame: a frame costs a fixed part plus its samples, both
    followed frame by frame as the viewer follows its cost (COST_SMOOTHING); as many samples as fit
    the budget, at least one."""

    def __init__(self, budget_seconds: float) -> None:
        self.budget_seconds = budget_seconds
        self.per_sample: float | None = None
        self.fixed = 0.0

    def spp(self) -> int:
        if self.per_sample is None:
            return 1
        return max(1, math.floor((self.budget_seconds - self.fixed) / self.per_sample))

    def measured(self, spp: int, trace_seconds: float, frame_seconds: float) -> None:
        per_sample, fixed = trace_seconds / spp, max(frame_seconds - trace_seconds, 0.0)
        if self.per_sample is None:
            self.per_sample, self.fixed = per_sample, fixed
        else:
            self.per_sample += COST_SMOOTHING * (per_sample - self.per_sample)
            self.fixed += COST_SMOOTHING * (fixed - self.fixed)


class TemporalPlayer:
    """`Renderer.render_frame` frame by frame; `filtered` through SVGF, `oidn` then denoised;
    tracing with `integrator` compiled with `overrides`."""

    def __init__(
        self,
        fly: FlyThrough,
        settings: Settings,
        *,
        filtered: bool,
        oidn: bool,
        integrator: str = "mis",
        overrides: dict[str, float] | None = None,
    ) -> None:
        self.fly, self.filtered, self.oidn = fly, filtered, oidn
        self.scene = fly.build()
        fly.pose(self.scene, 0)
        self.renderer = Renderer(
            self.scene,
            settings.width,
            settings.height,
            seed=settings.seed,
            max_depth=settings.max_depth,
            guides=oidn,
            integrator=integrator,
            shader_overrides=overrides,
        )
        self.budget = SampleBudget(settings.budget_seconds)

    def warm_up(self) -> list[str]:
        """Frames of the first pose: one that compiles, forgotten by the budget, and WARM_UP_FRAMES
        that it measures; then every history forgotten. What is wrong with the last of them."""
        self.frame(0)
        self.budget = SampleBudget(self.budget.budget_seconds)
        for _ in range(WARM_UP_FRAMES):
            self.frame(0)
        self.renderer.restart()
        return image_failures(self._linear, self.renderer.dropped_samples)

    def frame(self, index: int) -> Frame:
        self.fly.pose(self.scene, index)
        spp = self.budget.spp()
        start = time.perf_counter()
        linear = self.renderer.render_frame(spp=spp, filtered=self.filtered)
        trace_seconds = self.renderer.stats.render_seconds
        if self.oidn:
            linear = denoise(linear, **self.renderer.guides(), quality=OIDN_QUALITY)
        seconds = time.perf_counter() - start
        self.budget.measured(spp, trace_seconds, seconds)
        self._linear = linear
        return Frame(displayed(linear), seconds, spp, (self.renderer.width, self.renderer.height))


class PreviewPlayer:
    """Today's viewer while moving, through its own pacing, banded renderer, display and presenter:
    every frame starts the samples again at the reduced size that fits, traces one whole pass (or
    as many as fit), filters it and shows it scaled up."""

    def __init__(self, fly: FlyThrough, settings: Settings) -> None:
        self.fly = fly
        self.scene = fly.build()
        fly.pose(self.scene, 0)
        renderer = Renderer(
            self.scene, settings.width, settings.height, seed=settings.seed, max_depth=settings.max_depth
        )
        self.banded = BandedRenderer(renderer)
        self.display = Display(self.banded)
        self.presenter = Presenter(renderer.context, PRESENT_FORMAT)
        self.target_fps = 1.0 / settings.budget_seconds
        self.pacing = FramePacing(self.target_fps)
        # the trace budget the pacing gave each frame
        self.trace_budgets: list[float] = []

    def warm_up(self) -> list[str]:
        """Frames of the first pose (the display's kernels compile in the first), then a new pacing, so
        that compiling counts in no frame's measured overhead; the viewer's pacing learns its
        overhead from the frames that follow, as it does from its first."""
        for _ in range(1 + WARM_UP_FRAMES):
            self.frame(0)
        self.pacing = FramePacing(self.target_fps)
        self.trace_budgets.clear()
        return image_failures(self.display.read_image(), self.banded.renderer.dropped_samples)

    def frame(self, index: int) -> Frame:
        self.fly.pose(self.scene, index)
        start = time.perf_counter()
        if self.fly.moves_shapes:
            self.banded.renderer.update()  # the shapes' new transforms (the camera alone needs none)
        self.banded.restart(self.scene.camera, self.pacing.preview_size(self.banded))
        self.display.camera_changed()
        self.trace_budgets.append(self.pacing.trace_budget())
        trace_seconds = self.banded.advance(self.pacing.trace_budget(), whole_pass=True)
        texture = self.display.render(ViewSettings(filter_enabled=True))
        pixels = self.presenter.screenshot(texture, self.banded.size, self.banded.full_size, DISPLAY_TONE)
        end = time.perf_counter()
        self.pacing.frame_done(start, end, trace_seconds)
        return Frame(pixels / 255.0, end - start, self.banded.samples_done, self.banded.size)


class ViewerPlayer:
    """The viewer's moving picture (`TemporalPicture`): the upscale factor and the samples chosen
    from the whole frame's budget and each factor's measured cost, as the viewer chooses them."""

    def __init__(self, fly: FlyThrough, settings: Settings) -> None:
        self.fly, self.budget_seconds = fly, settings.budget_seconds
        self.scene = fly.build()
        fly.pose(self.scene, 0)
        renderer = Renderer(
            self.scene, settings.width, settings.height, seed=settings.seed, max_depth=settings.max_depth
        )
        self.picture = TemporalPicture(renderer)

    def warm_up(self) -> list[str]:
        """Frames of the first pose until the factor it settles on has been measured (each factor's
        first frame compiles and is not measured), then every history forgotten, the costs kept."""
        for _ in range(1 + 2 * WARM_UP_FRAMES):
            self.frame(0)
        renderer = self.picture.renderer
        renderer.restart()
        return image_failures(self._last, renderer.dropped_samples)

    def frame(self, index: int) -> Frame:
        self.fly.pose(self.scene, index)
        start = time.perf_counter()
        self._last = self.picture.frame(self.scene.camera, self.budget_seconds)
        seconds = time.perf_counter() - start
        traced = self.picture.traced_size
        return Frame(displayed(self._last), seconds, self.picture.samples_per_pixel, traced)


class FixedFactorPlayer(ViewerPlayer):
    """The viewer's moving picture at upscale `factor`, one sample per traced pixel a frame."""

    def __init__(self, fly: FlyThrough, settings: Settings, factor: int) -> None:
        super().__init__(fly, settings)
        self.factor = factor

    def frame(self, index: int) -> Frame:
        self.fly.pose(self.scene, index)
        start = time.perf_counter()
        # a budget nothing fits: one sample per traced pixel
        self._last = self.picture.frame(self.scene.camera, NO_BUDGET, upscale=self.factor)
        seconds = time.perf_counter() - start
        return Frame(displayed(self._last), seconds, self.picture.samples_per_pixel, self.picture.traced_size)


# A frame budget nothing fits (FixedFactorPlayer traces one sample, the least a frame takes).
NO_BUDGET = 1e-9


@dataclass(frozen=True)
class Mode:
    """`denoised`: the mode runs OIDN, which a machine without pyoidn lacks; `default`: run unless
    --modes names others."""

    name: str
    label: str
    color: str
    player: Callable[[FlyThrough, Settings], TemporalPlayer | PreviewPlayer | ViewerPlayer]
    denoised: bool = False
    default: bool = True


def _fixed_factor(factor: int, color: str) -> Mode:
    return Mode(
        f"upsampled{factor}",
        f"upsampled at {factor}x, one sample per traced pixel",
        color,
        lambda fly, settings: FixedFactorPlayer(fly, settings, factor),
        default=False,
    )


MODES = {
    mode.name: mode
    for mode in (
        Mode("preview", "today's preview (reset on move, reduced size, a-trous)", "#888888", PreviewPlayer),
        Mode(
            "temporal",
            "temporal accumulation",
            "#3b75af",
            lambda fly, settings: TemporalPlayer(fly, settings, filtered=False, oidn=False),
        ),
        Mode(
            "temporal+svgf",
            "+ variance-guided filter",
            "#d08030",
            lambda fly, settings: TemporalPlayer(fly, settings, filtered=True, oidn=False),
        ),
        Mode(
            "temporal+svgf+oidn",
            "+ OIDN (timed)",
            "#50a050",
            lambda fly, settings: TemporalPlayer(fly, settings, filtered=True, oidn=True),
            denoised=True,
        ),
        Mode("upsampled+svgf", "the viewer's picture: + temporal upsampling", "#a040a0", ViewerPlayer),
        _fixed_factor(2, "#c07070"),
        _fixed_factor(4, "#70a0c0"),
        _fixed_factor(8, "#a0a060"),
    )
}
# The modes run unless --modes names others.
DEFAULT_MODES = [name for name, mode in MODES.items() if mode.default]
# The baseline the targets are ratios to.
BASELINE = "preview"
