"""The desktop viewer (`python app.py [SCENE]`, `wgputrace view [SCENE]`) and its notebook form.

Nothing else in wgputrace imports this package: windows and input live here only. Importing it
is light; rendercanvas, glfw and the GPU are loaded when a viewer starts.

In Jupyter (`pip install wgputrace[notebook]`):

    from wgputrace.app import notebook_viewer
    viewer = notebook_viewer("cornell", size=(480, 360))
    viewer.canvas  # the last expression of a cell: shows the live picture; keys and mouse work there too
"""

from __future__ import annotations

import argparse
import sys

from ..cli_arguments import add_view_arguments
from ..scenes import DEFAULT_SCENE
from .options import ViewerOptions


def options_from(args: argparse.Namespace) -> ViewerOptions:
    return ViewerOptions(
        scene=args.scene,
        camera=args.camera,
        size=args.size,
        max_depth=args.max_depth,
        integrator=args.integrator,
        seed=args.seed,
        exposure=args.exposure,
        tonemap=args.tonemap,
        target_fps=args.fps,
        filter=args.filter,
        denoise=args.denoise,
        preview=args.preview,
        env=args.env,
        env_intensity=args.env_intensity,
        env_rotation=args.env_rotation,
        info=not args.no_info,
        screenshot_dir=args.screenshots,
    )


def run(args: argparse.Namespace) -> int:
    """Open the window and run until it closes: 0, or 1 when the device was lost and no new one
    could be started; 2 with a message when no window can be opened."""
    from .viewer import Viewer
    from .window import NoDisplayError, create_canvas, run_loop

    options = options_from(args)
    try:
        canvas = create_canvas(options.size, f"wgputrace - {options.scene}")
    except NoDisplayError as error:
        print(f"wgputrace view: error: {error}", file=sys.stderr)
        return 2
    viewer = Viewer(canvas, options)
    run_loop()
    return viewer.exit_status


def notebook_viewer(scene: str = DEFAULT_SCENE, size: tuple[int, int] = (480, 360), **options):
    """A viewer drawing into a Jupyter widget (rendercanvas's notebook backend, needs the
    `notebook` extra); show `viewer.canvas` in a cell. `scene` as wgputrace.load_scene reads it;
    keyword options as ViewerOptions."""
    from rendercanvas.jupyter import RenderCanvas

    from .viewer import Viewer
    from .window import MAX_FPS

    canvas = RenderCanvas(size=size, title=f"wgputrace - {scene}", update_mode="continuous", max_fps=MAX_FPS)
    return Viewer(canvas, ViewerOptions(scene=scene, size=size, **options))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="app.py", description="wgputrace's interactive viewer")
    add_view_arguments(parser)
    return run(parser.parse_args(argv))
