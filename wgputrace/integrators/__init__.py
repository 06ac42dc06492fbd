"""Every integrator, one module each (`Integrator` says what one declares); importing this package
registers them all."""

from ..scene.registry import import_modules
from . import path_tracer  # noqa: F401  (first: the default and the first choices the command line lists)
from .integrator import Integrator, PixelArray, integrator, integrator_names

import_modules(__name__, __path__)

__all__ = ["Integrator", "PixelArray", "integrator", "integrator_names"]
