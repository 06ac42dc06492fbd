"""A result's chart: a matplotlib figure drawn off screen, titled with the adapter and revision
that made the result."""

from __future__ import annotations

from pathlib import Path


def figure(width: float, height: float):
    """A matplotlib Figure drawn off screen (no pyplot state, no display needed)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    chart = Figure(figsize=(width, height))
    FigureCanvasAgg(chart)
    return chart


def save_figure(chart, path: Path, result: dict, title: str, *, fontsize: float = 9, dpi: int = 110) -> None:
    """Title the chart with `title` and the adapter and revision that made `result`, and save it."""
    adapter = result["adapter"]
    chart.suptitle(
        f"{title}\n{adapter['adapter']} ({adapter['backend']}), rev {result['git_revision']}, "
        f"{result['environment']['cpu_count']} cores, load {result.get('load_average_before_after', ['-'])[0]}",
        fontsize=fontsize,
    )
    chart.tight_layout()
    chart.savefig(path, dpi=dpi)
