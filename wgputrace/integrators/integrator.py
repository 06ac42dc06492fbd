"""What an integrator is to the renderer, the viewer, the command line and the limits: one
descriptor, registered by name, that they ask instead of naming it.

| what                                        | field            | asked by                                    |
|---------------------------------------------|------------------|---------------------------------------------|
| the WGSL kernel that renders whole images   | `entry`          | `tracing_kernel`                            |
| a band-of-rows kernel for the viewer        | `rows_entry`     | `KernelVariant` (None: whole images only)   |
| a kernel over one pixel per block           | `subset_entry`   | `KernelVariant` (None: no upsampling)       |
| a kernel run over the image before each pass | `prepass_entry` | the Renderer (`uses_prepass`)               |
| override constants of its kernel            | `constants`      | `tracing_kernel`                            |
| generated files of its own                  | `files`          | `KernelVariant.files`                       |
| per-pixel arrays beside the accumulation    | `pixel_arrays`   | the pixels group, the Renderer, the limits  |
| per-pixel arrays kept from frame to frame   | `frame_arrays`   | the G-buffer variant's pixels group, render_frame |
| light tracing splats into any pixel         | `splats`         | the Renderer's image, tiles (refused)       |
| the deepest path it can trace               | `max_depth`      | `check_depth`                               |
| several samples per dispatch (regeneration) | `regenerates`    | `KernelVariant` (`check_regeneration`)      |
| how many, by adapter type (measured)        | `dispatch_samples` | the Renderer (`samples_per_dispatch`)     |
| absorption inside materials (`volume`)      | `absorbs`        | the Renderer (`check_materials`)            |
| writes the G-buffer (`write_gbuffer`)       | `gbuffer`        | `KernelVariant` (`check_gbuffer`)           |

A new integrator is one module in this package that registers an instance (`register`), plus its
WGSL entry file: the renderer, the CLI's choices and the limits follow from the descriptor.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..gpu.bindings import STORAGE_READ, Binding
from ..scene.materials.volume import is_absorbing

if TYPE_CHECKING:
    from ..kernels.variant import KernelVariant


@dataclass(frozen=True)
class PixelArray:
    """A buffer of `words_per_pixel` 32-bit words per pixel that an integrator binds in the pixels
    group as `binding`, zeroed whenever accumulation restarts."""

    binding: Binding
    words_per_pixel: int

    @property
    def bytes_per_pixel(self) -> int:
        return 4 * self.words_per_pixel

    @property
    def previous(self) -> Binding:
        """The binding through which the next frame reads what a frame wrote to it (frame_arrays)."""
        return Binding(f"previous_{self.binding.name}", STORAGE_READ, self.binding.holds)


@dataclass(frozen=True)
class Integrator:
    name: str
    entry: str
    description: str
    rows_entry: str | None = None
    # the kernel over one pixel of each block (TemporalUpsampling); None: it has none
    subset_entry: str | None = None
    # a kernel over every pixel that runs before each whole-image dispatch of `entry`, on the same
    # bind groups (restir's candidates, which the pass then shares between neighbours); None: none
    prepass_entry: str | None = None
    constants: tuple[tuple[str, int], ...] = ()
    pixel_arrays: tuple[PixelArray, ...] = ()
    # per-pixel arrays its G-buffer variant writes in each frame of render_frame and reads as they
    # were in the previous frame (`PixelArray.previous`), allocated by render_frame's first call
    frame_arrays: tuple[PixelArray, ...] = ()
    splats: bool = False
    max_depth: int | None = None
    # whether its kernel takes several samples of a pixel per dispatch (`samples_this_dispatch`)
    regenerates: bool = False
    # how many it takes by adapter type ("CPU", "DiscreteGPU", ...), as measured by
    # `python -m bench.regeneration`; 1 on the others
    dispatch_samples: tuple[tuple[str, int], ...] = ()
    # whether its kernel multiplies its segments by their absorption (`segment_transmittance`)
    absorbs: bool = False
    # whether its kernel calls `write_gbuffer` for each pixel (temporal accumulation needs it)
    gbuffer: bool = False

    def files(self, variant: KernelVariant) -> dict[str, str]:
        """Generated files of its own, for `variant`: none here."""
        return {}

    def check_depth(self, max_depth: int) -> None:
        """ValueError unless it can trace paths of `max_depth` (-1: no limit)."""
        if self.max_depth is not None and not 1 <= max_depth <= self.max_depth:
            raise ValueError(f"integrator {self.name!r} takes max_depth from 1 to {self.max_depth}, got {max_depth}")

    def samples_per_dispatch(self, adapter_type: str) -> int:
        """Samples of each pixel a dispatch of its kernel takes on an adapter of `adapter_type`."""
        return dict(self.dispatch_samples).get(adapter_type, 1)

    def check_materials(self, materials) -> None:
        """ValueError naming the first of `materials` it cannot render (one that absorbs light,
        where its kernel does not trace absorption)."""
        if self.absorbs:
            return
        for material in materials:
            if is_absorbing(material):
                others = ", ".join(repr(m.name) for m in _registry.values() if m.absorbs)
                raise ValueError(
                    f"{material.label} absorbs the light inside it (attenuation_color, attenuation_distance), which the "
                    f"{self.name} integrator does not trace; use {others}"
                )

    def check_regeneration(self) -> None:
        """ValueError unless its kernel can take several samples of a pixel per dispatch."""
        if not self.regenerates:
            raise ValueError(f"the {self.name} integrator's kernel takes one sample of each pixel per dispatch")

    def check_gbuffer(self) -> None:
        """ValueError unless its kernel writes the G-buffer that temporal accumulation reads."""
        if not self.gbuffer:
            raise ValueError(f"the {self.name} integrator writes no G-buffer: temporal accumulation needs one")

    def check_rows(self) -> None:
        """ValueError unless it has a band-of-rows kernel for the viewer."""
        if self.rows_entry is None:
            raise ValueError(
                f"the {self.name} integrator renders whole images only: it has no band-of-rows kernel for the viewer"
            )

    def with_overrides(self, overrides: Mapping[str, float]) -> Integrator:
        """The integrator as a Renderer compiled with shader `overrides` uses it: itself here (one
        whose overrides change what it allocates says so)."""
        return self

    def uses_prepass(self, variant: KernelVariant) -> bool:
        """Whether `variant`'s kernel runs after the pre-pass: a whole-image kernel of an integrator
        that has one (bands and subsets trace part of the image)."""
        return self.prepass_entry is not None and not (variant.rows or variant.subset or variant.prepass)

    def check_subset(self) -> None:
        """ValueError unless it has a kernel over one pixel of each block (temporal upsampling)."""
        if self.subset_entry is None:
            raise ValueError(f"the {self.name} integrator has no kernel over a subset of pixels: it cannot upsample")


_registry: dict[str, Integrator] = {}


def register(integrator: Integrator) -> Integrator:
    if integrator.name in _registry:
        raise ValueError(f"an integrator named {integrator.name!r} is already registered")
    _registry[integrator.name] = integrator
    return integrator


def integrator_names() -> tuple[str, ...]:
    """Every registered integrator's name, in registration order."""
    return tuple(_registry)


def integrator(name: str | Integrator) -> Integrator:
    """The integrator registered as `name` (an Integrator is returned as it is)."""
    if isinstance(name, Integrator):
        return name
    if name not in _registry:
        raise ValueError(f"integrator must be one of {integrator_names()}, got {name!r}")
    return _registry[name]
