"""Bounding volume hierarchies in pure numpy: the canonical tree and the builders that produce it."""

from wgputrace.bvh.binned_sah import build_bvh
from wgputrace.bvh.flat import build_flat
from wgputrace.bvh.refit import Refitter
from wgputrace.bvh.tree import BVH

__all__ = ["BVH", "Refitter", "build_bvh", "build_flat"]
