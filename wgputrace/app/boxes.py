"""The BVH's boxes drawn over the picture as lines: B shows or hides them, [ and ] pick the level
of the tree they are taken from."""

from __future__ import annotations

from ..bvh.levels import box_edges


class BoxLines:
    """Whether the boxes are shown, and their level in the tree (the root's: 0)."""

    def __init__(self) -> None:
        self.shown = False
        self.level = 0

    def toggle(self, presenter, view) -> None:
        self.shown = not self.shown
        self.draw_on(presenter, view)

    def step(self, levels: int, presenter, view) -> None:
        """Show the boxes `levels` deeper (or higher, negative) in `view`'s tree, within it."""
        deepest = int(view.levels.max())
        self.level = min(max(self.level + levels, 0), deepest)
        self.shown = True
        self.draw_on(presenter, view)

    def draw_on(self, presenter, view) -> None:
        """Give `presenter` the edges of the boxes of `view`'s tree at `level`, or none."""
        if view is None or not self.shown:
            presenter.set_box_lines(None)
            return
        bvh, level = view.renderer.records.acceleration, view.levels == self.level
        presenter.set_box_lines(box_edges(bvh.bounds_min[level], bvh.bounds_max[level]))
