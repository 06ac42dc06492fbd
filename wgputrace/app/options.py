"""ViewerOptions: what the viewer is started with (the `view` command's arguments)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..cli_arguments import TEMPORAL_PREVIEW
from ..image_io import DEFAULT_TONEMAP
from ..scenes import DEFAULT_SCENE
from .pacing import TARGET_FPS


@dataclass
class ViewerOptions:
    scene: str = DEFAULT_SCENE
    camera: str | None = None  # --camera: one of the scene file's own cameras, by name or index
    size: tuple[int, int] = (640, 480)
    max_depth: int = 9
    integrator: str = "mis"  # --integrator: one with a band-of-rows kernel (Integrator.rows_entry)
    seed: int = 1
    exposure: float | str = 0.0  # stops (EV), or "auto": the auto-exposure on from the start
    tonemap: str = DEFAULT_TONEMAP
    target_fps: float = TARGET_FPS
    filter: bool = False
    denoise: bool = False
    preview: str = TEMPORAL_PREVIEW  # --preview: "temporal" or "reset", the picture while the camera moves
    # --env, --env-intensity, --env-rotation as cli_arguments.apply_lighting reads them
    env: str | tuple[float, float, float] | Path | None = None
    env_intensity: float | None = None
    env_rotation: float | None = None
    info: bool = True
    screenshot_dir: Path = field(default_factory=Path.cwd)
