"""SceneView: what the viewer makes for one scene at one window size on the device."""

from __future__ import annotations

from ..bvh.levels import node_levels
from ..cli_arguments import TEMPORAL_PREVIEW
from ..render import Renderer
from ..view.banded import BandedRenderer
from ..view.denoised import DenoisedPicture
from ..view.display import Display
from ..view.temporal_picture import TemporalPicture
from .options import ViewerOptions


class SceneView:
    """Everything that depends on the scene and the window size: renderer, bands, display, the
    moving picture, and the denoised picture once the denoiser has been on (`denoiser_device`:
    OIDN's device)."""

    def __init__(self, scene, size: tuple[int, int], options: ViewerOptions, denoiser_device: str | None) -> None:
        guides = denoiser_device is not None
        self.renderer = Renderer(
            scene,
            size[0],
            size[1],
            seed=options.seed,
            max_depth=options.max_depth,
            guides=guides,
            integrator=options.integrator,
        )
        self.banded = BandedRenderer(self.renderer)
        self.display = Display(self.banded)
        self.denoised = DenoisedPicture(self.banded, denoiser_device) if guides else None
        # the moving picture: --preview temporal, where the integrator writes the G-buffer it needs
        temporal = options.preview == TEMPORAL_PREVIEW and self.renderer.integrator.gbuffer
        self.moving = TemporalPicture(self.renderer) if temporal else None
        # the binary tree's levels: the GPU's 4-wide records are derived from it
        bvh = self.renderer.records.acceleration
        self.levels = node_levels(bvh.left_or_first, bvh.triangle_count)

    def start_denoiser(self, denoiser_device: str) -> None:
        """Accumulate the guides from now on (which restarts the samples) and make the denoised
        picture. The guides stay on when the denoiser is switched off: they cost no measurable
        time (a pass at 640x480 took 1.06 s with them, 1.05 s without, on lavapipe), and switching
        back then shows OIDN's picture of the same samples without starting again."""
        self.renderer.guides_enabled = True
        self.denoised = DenoisedPicture(self.banded, denoiser_device)
