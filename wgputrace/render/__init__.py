"""Rendering: GPU buffers for a scene, the path-tracing dispatch loop, accumulation and read-back."""

from .renderer import UNLIMITED_DEPTH, Renderer, RenderStats, render

__all__ = ["UNLIMITED_DEPTH", "RenderStats", "Renderer", "render"]
