"""The viewer tutorial's pictures (docs/images/viewer_*.png): `python app.py` in a real window on a
virtual X display (Xvfb), driven by X key events as a person drives it, each picture the viewer's
own screenshot (key P) of what its window shows.

    PYTHONPATH=. python scripts/viewer_screenshots.py [--out docs/images] [--size 640x480]

Takes about ten minutes on lavapipe (two cores); needs Xvfb and python-xlib (the test extra), and pyoidn (the
denoise extra) for the denoiser's picture.
"""

from __future__ import annotations

import argparse
import shutil
import time
from pathlib import Path

from PIL import Image

from wgputrace.app.overlay import OVERLAY_SECONDS
from wgputrace.app.pacing import REST_SECONDS
from wgputrace.cli_arguments import parse_size
from wgputrace.testing.display import virtual_display
from wgputrace.testing.running_app import START_SECONDS, RunningApp, Screenshot
from wgputrace.testing.xdriver import XDriver

OUT = Path(__file__).resolve().parents[1] / "docs" / "images"
# Samples per pixel of the resting pictures: converged enough to read, reached in seconds.
RESTING_SPP = 64
# The pre-convergence filter and the denoiser are shown on few samples, where they matter.
FEW_SPP = 4
# A screenshot holds whole passes over the image when its samples per pixel are this close to a whole number.
WHOLE_PASS = 1e-3
POLL_SECONDS = 0.2
DEBUG_VIEWS = {"2": "normals", "3": "albedo", "4": "depth", "5": "heat"}


class Session:
    def __init__(self, app: RunningApp, driver: XDriver, window_id, size: tuple[int, int], out: Path) -> None:
        self.app, self.driver, self.window_id, self.size, self.out = app, driver, window_id, size, out

    def shot(self, name: str | None, min_spp: float, max_spp: float = float("inf"), label: str = "") -> Screenshot:
        """Screenshots until one is of the whole window, between min_spp and max_spp samples per
        pixel (whole passes where max_spp is given: a part-done pass shows as a band), and its
        console line names `label` (what the viewer shows: raw, a-trous, OIDN); kept as
        viewer_<name>.png unless `name` is None."""
        while True:
            self.driver.tap("p")
            shot = self.app.screenshot_line()
            line = self.app.log[-1]
            whole = max_spp == float("inf") or abs(shot.spp - round(shot.spp)) < WHOLE_PASS
            if shot.size == self.size and whole and min_spp <= shot.spp <= max_spp and label in line:
                if name is not None:
                    shutil.copyfile(shot.png, self.out / f"viewer_{name}.png")
                    print(f"viewer_{name}.png: {shot.spp:g} spp ({line.rsplit('(showing ', 1)[1]}")
                return shot
            if shot.spp > max_spp:
                self.restart()
            time.sleep(POLL_SECONDS if shot.spp > min_spp / 2 else 5 * POLL_SECONDS)

    def window(self, name: str) -> None:
        """The window's pixels as they are, overlay included, as viewer_<name>.png."""
        time.sleep(2 * OVERLAY_SECONDS)
        Image.fromarray(self.driver.grab(self.window_id)).save(self.out / f"viewer_{name}.png")

    def restart(self) -> None:
        """Back to the scene's camera: the samples start again."""
        self.driver.tap("r")
        time.sleep(REST_SECONDS)

    def shift(self, key: str) -> None:
        self.driver.key_down("Shift_L")
        self.driver.tap(key)
        self.driver.key_up("Shift_L")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--size", type=parse_size, default=(640, 480))
    args = parser.parse_args()
    width, height = args.size
    with virtual_display() as name:
        folder = args.out / ".screenshots"
        app = RunningApp(["cornell", "--size", f"{width}x{height}", "--screenshots", str(folder)], args.out)
        driver = XDriver(name)
        try:
            app.wait_for("showing cornell", START_SECONDS)
            window = driver.find_window("wgputrace - cornell", START_SECONDS)
            driver.pointer_to(window, width // 2, height // 2)  # no window manager: the pointer gives focus
            session = Session(app, driver, window, args.size, args.out)
            session.restart()
            shot = session.shot(None, RESTING_SPP)
            session.window("overlay")
            print(f"viewer_overlay.png: {shot.spp:g} spp or more")
            driver.tap("Tab")
            for key, view in DEBUG_VIEWS.items():
                driver.tap(key)
                session.restart()
                session.shot(view, RESTING_SPP / 4)
            driver.tap("1")
            session.restart()
            session.shot("raw", 1, FEW_SPP, "raw")
            driver.tap("n")
            session.restart()
            session.shot("filtered", 1, FEW_SPP, "a-trous")
            driver.tap("n")
            session.shift("d")
            session.restart()
            session.shot("denoised", 1, FEW_SPP, "OIDN")
        finally:
            driver.close()
            app.stop()
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
