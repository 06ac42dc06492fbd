"""The hemisphere grids of `wgputrace.testing.bsdf_grid`, on which the chi-square and furnace tests rest: their
quadrature integrates known functions, and their histogram puts each direction in the cell whose
quadrature covers it. Pure numpy."""

from __future__ import annotations

import numpy as np
import pytest

from wgputrace import Diffuse, Glossy
from wgputrace.testing.bsdf_grid import incident_directions, integrate, lobe_grid

# Error budget of the whole hemisphere in the tests below, relative to the integral: far below
# what the chi-square and furnace tests ask, and far above float64 rounding.
QUADRATURE_RTOL = 1e-10

GRIDS = [(Diffuse("diffuse"), 0.5)] + [
    (Glossy(f"glossy {r}", roughness=r), c) for r in (0.01, 0.1, 1.0) for c in (1.0, 0.1, 1e-3, -0.5)
]


def grid_id(case) -> str:
    material, cos_theta = case
    return f"{material.name}, cos {cos_theta:g}"


def even_budget(total: float):
    """An error budget that splits `total` evenly over the cells."""
    return lambda values: np.full(values.shape, total / values.size)


@pytest.mark.parametrize("case", GRIDS, ids=grid_id)
def test_quadrature_integrates_the_hemisphere(case):
    """1 and cos theta integrate to 2 pi and pi (the weights carry the right Jacobians, even in
    the outermost cells of the tightest grids, which span factors of ~10^4), to within the error
    the integration reports, which meets its budget."""
    material, cos_theta = case
    wi = incident_directions(np.random.default_rng(1), np.array([cos_theta]))[0]
    grid = lobe_grid(material, wi)
    for integrand, exact in ((lambda case, d: np.ones(len(d)), 2.0 * np.pi), (lambda case, d: np.abs(d[:, 2]), np.pi)):
        result = integrate([grid], integrand, even_budget(QUADRATURE_RTOL * exact))
        error = result.error.sum()
        assert error <= QUADRATURE_RTOL * exact
        assert abs(result.value.sum() - exact) <= error + 64 * np.finfo(np.float64).eps * exact


@pytest.mark.parametrize("case", GRIDS, ids=grid_id)
def test_histogram_counts_each_cell_centre_in_its_cell(case):
    material, cos_theta = case
    wi = incident_directions(np.random.default_rng(1), np.array([cos_theta]))[0]
    grid = lobe_grid(material, wi)
    rows, columns = grid.cells
    s_c, s_phi = grid.cell_ranges()
    centres, _ = grid.rule(np.arange(rows * columns) // columns, s_c, s_phi, 1)
    counts = grid.histogram(centres[:, 0])
    assert np.all(counts == 1), f"{np.sum(counts != 1)} cells of {counts.size} miss their own centre"
