"""The shipped BSDFs (`bsdf_sample`, `bsdf_eval`, `bsdf_pdf`) run on the GPU, incident directions in
their local frame, and a grid on the hemisphere over which their pdf and eval are integrated and
their samples counted: what the chi-square and furnace tests compare.

Cells form a (cos theta, phi) grid on wi's side, where every material but glass sends its light;
the horizon is a cell edge, so no cell has a jump inside, and cells crowd around the mirror
direction at the scale of the lobe (`lobe_grid`). Each cell is integrated by Gauss-Legendre
quadrature, the same rule at half the order its error estimate (`integrate`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from wgputrace import Glossy
from wgputrace.scene import Material
from wgputrace.testing.harness import WORKGROUP, run_kernel
from wgputrace.testing.oracles import UNIT_ROUNDOFF

# The most invocations one dispatch may hold: 65,535 workgroups (the per-dimension limit).
MAX_DISPATCH = 65_535 * WORKGROUP

# (cos theta, phi) cells of every grid: 20 x 40 leaves ~1,300 samples per cell at 2^20 samples,
# fine enough to see a lobe's shape and coarse enough for the chi-square test to keep its power.
GRID_CELLS = (20, 40)
# Gauss-Legendre points per axis in each piece of a cell; half as many give the error estimate.
QUADRATURE_ORDER = 8
# Pieces of a cell are halved along both axes at most this often (down to 1/64 of the cell).
MAX_REFINEMENTS = 6

# The harness input v holds a direction or random numbers in xyz and the case's index in w.
_KERNEL = """
//! include "materials/bsdf.wgsl"
fn compute(i: u32) -> vec4<f32> {{
    let v = inputs_2[i];
    let material = inputs_0[u32(v.w)];
    let wi = inputs_1[u32(v.w)].xyz;
    {body}
}}
"""
# v.xy drives the lobe's direction, v.z the choice of lobe.
_SAMPLE = "let s = bsdf_sample(material, wi, v.xy, v.z);\n    return vec4<f32>(s.direction, s.pdf);"
_EVALUATE = "return vec4<f32>(bsdf_eval(material, wi, v.xyz), bsdf_pdf(material, wi, v.xyz));"
# Channels of evaluate_bsdf's result.
EVAL, PDF = 0, 3
# Sampled directions are built from sqrt, cos, sin and normalize: a few roundings off unit length.
UNIT_LENGTH_TOLERANCE = 16 * UNIT_ROUNDOFF


def incident_directions(rng: np.random.Generator, cos_theta: np.ndarray) -> np.ndarray:
    """Unit float32 directions with the given z (sign included) at random azimuths."""
    cos_theta = np.asarray(cos_theta, np.float64)
    phi = rng.uniform(0.0, 2.0 * np.pi, size=cos_theta.shape)
    sin_theta = np.sqrt(np.maximum(0.0, 1.0 - cos_theta**2))
    return np.stack([sin_theta * np.cos(phi), sin_theta * np.sin(phi), cos_theta], axis=-1).astype(np.float32)


def sin_theta(v: np.ndarray) -> np.ndarray:
    v = v.astype(np.float64)
    return np.hypot(v[:, 0], v[:, 1])


def refraction_indices(ior: np.ndarray, wi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(eta_i, eta_t) of glass of `ior` for incident directions wi: the ior is inside, on the -z
    side; outside is 1."""
    outside = wi[:, 2] >= 0.0
    return np.where(outside, 1.0, ior), np.where(outside, ior, 1.0)


def _run(context, body: str, materials: np.ndarray, wi: np.ndarray, items: np.ndarray, case: np.ndarray) -> np.ndarray:
    """(n, 4) results of `body` for items (n, 3) of cases `case` (n,): materials[case], wi[case]."""
    if len(materials) >= 2**24:
        raise ValueError(f"{len(materials):,} cases: a case index must stay exact in float32 (below 2^24)")
    packed = np.empty((len(items), 4), np.float32)
    packed[:, :3] = items
    packed[:, 3] = case
    wi4 = np.zeros((len(wi), 4), np.float32)
    wi4[:, :3] = wi
    out = np.empty((len(items), 4), np.float32)
    for start in range(0, len(items), MAX_DISPATCH):
        chunk = packed[start : start + MAX_DISPATCH]
        out[start : start + len(chunk)] = run_kernel(
            context,
            _KERNEL.format(body=body),
            [np.ascontiguousarray(materials), wi4, chunk],
            np.dtype((np.float32, 4)),
            len(chunk),
            input_types=["Material", "vec4<f32>", "vec4<f32>"],
            output_type="vec4<f32>",
        )
    return out


def sample_bsdf(context, materials: np.ndarray, wi: np.ndarray, u: np.ndarray) -> np.ndarray:
    """bsdf_sample for each case (MATERIAL records, wi (cases, 3)) and each of its random triples
    u (cases, n, 3): (cases, n, 4) holding the direction and the pdf (0: no sample)."""
    cases, count = u.shape[:2]
    out = _run(context, _SAMPLE, materials, wi, u.reshape(-1, 3), np.repeat(np.arange(cases), count))
    return out.reshape(cases, count, 4)


def evaluate_bsdf(context, materials: np.ndarray, wi: np.ndarray, wo: np.ndarray, case: np.ndarray) -> np.ndarray:
    """bsdf_eval (channels 0-2) and bsdf_pdf (channel PDF) at directions wo (n, 3) of cases `case`."""
    return _run(context, _EVALUATE, materials, wi, wo, case)


@dataclass(frozen=True)
class Axis:
    """One coordinate of a grid, x in [lo, hi], crowding around `center` at scale `width`
    (broadcast against x; infinite: no crowding).

    Cell edges are quantiles of a Cauchy distribution with that centre and scale, truncated to
    [lo, hi]: half of the cells lie within `width` of the centre. Integrals run over
    s = asinh((x - center) / width) instead of x: a lobe's core and its power-law tails both
    become smooth in s, where Gauss-Legendre quadrature converges fast (a Cauchy quantile map
    would put a near-singular Jacobian into the outermost cells)."""

    lo: float
    hi: float
    center: float = 0.0
    width: float | np.ndarray = np.inf

    def _scale(self) -> tuple[np.ndarray, np.ndarray]:
        finite = np.isfinite(self.width)
        return finite, np.where(finite, self.width, 1.0)

    def _quantile_angles(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        finite, width = self._scale()
        return finite, width, np.arctan((self.lo - self.center) / width), np.arctan((self.hi - self.center) / width)

    def edges(self, cells: int) -> np.ndarray:
        finite, width, a, b = self._quantile_angles()
        u = np.linspace(0.0, 1.0, cells + 1)
        cauchy = np.clip(self.center + width * np.tan(a + u * (b - a)), self.lo, self.hi)
        edges = np.where(finite, cauchy, self.lo + u * (self.hi - self.lo))
        edges[..., 0], edges[..., -1] = self.lo, self.hi
        return edges

    def cell(self, x: np.ndarray, cells: int) -> np.ndarray:
        """Index of the cell (of `cells`) holding each x: the inverse of `edges`."""
        finite, width, a, b = self._quantile_angles()
        u = np.where(finite, (np.arctan((x - self.center) / width) - a) / (b - a), (x - self.lo) / (self.hi - self.lo))
        return np.clip(np.floor(u * cells).astype(np.int64), 0, cells - 1)

    def s(self, x: np.ndarray) -> np.ndarray:
        finite, width = self._scale()
        return np.where(finite, np.arcsinh((x - self.center) / width), x)

    def x(self, s: np.ndarray) -> np.ndarray:
        finite, width = self._scale()
        return np.where(finite, self.center + width * np.sinh(s), s)

    def dx_ds(self, s: np.ndarray) -> np.ndarray:
        finite, width = self._scale()
        return np.where(finite, width * np.cosh(s), 1.0)


@dataclass(frozen=True)
class HemisphereGrid:
    """Cells in (cos theta, phi) on the hemisphere of `side` (+1 above the surface, -1 below),
    cos theta measured on that side. Rows split cos theta; each row splits phi, once around the
    circle, at its own width (a lobe's azimuthal width changes with elevation)."""

    side: float
    cos_theta: Axis
    phi_center: float
    phi_width: np.ndarray  # per row; inf: uniform
    cells: tuple[int, int] = GRID_CELLS

    def phi(self, row: np.ndarray | int) -> Axis:
        width = self.phi_width[row]
        return Axis(self.phi_center - np.pi, self.phi_center + np.pi, self.phi_center, width)

    def histogram(self, directions: np.ndarray) -> np.ndarray:
        """Counts (cells) of unit directions on the grid's side."""
        rows, columns = self.cells
        d = np.asarray(directions, np.float64)
        lo = self.phi_center - np.pi
        phi = lo + np.mod(np.arctan2(d[:, 1], d[:, 0]) - lo, 2.0 * np.pi)
        row = self.cos_theta.cell(np.clip(self.side * d[:, 2], 0.0, 1.0), rows)
        column = self.phi(row).cell(phi, columns)
        return np.bincount(row * columns + column, minlength=rows * columns).reshape(self.cells)

    def cell_ranges(self) -> tuple[np.ndarray, np.ndarray]:
        """Each cell's range (cells, 2) of the integration variable s of cos theta and of phi."""
        rows, columns = self.cells
        c = self.cos_theta.s(self.cos_theta.edges(rows))
        row = np.arange(rows)[:, None]
        phi = self.phi(row).s(self.phi(row).edges(columns))
        c_range = np.stack([c[:-1], c[1:]], axis=1)
        phi_range = np.stack([phi[:, :-1], phi[:, 1:]], axis=-1)
        return np.repeat(c_range, columns, axis=0), phi_range.reshape(-1, 2)

    def rule(self, row: np.ndarray, s_c: np.ndarray, s_phi: np.ndarray, order: int) -> tuple[np.ndarray, np.ndarray]:
        """Gauss-Legendre rule of `order` per axis on pieces of cells: row (n,), s_c and s_phi
        (n, 2) the piece's ranges of the integration variables. Directions (n, order^2, 3) and
        solid-angle weights (n, order^2)."""
        t, w = np.polynomial.legendre.leggauss(order)
        half_c, half_phi = 0.5 * (s_c[:, 1:] - s_c[:, :1]), 0.5 * (s_phi[:, 1:] - s_phi[:, :1])
        sc = 0.5 * (s_c[:, :1] + s_c[:, 1:]) + half_c * t
        sp = 0.5 * (s_phi[:, :1] + s_phi[:, 1:]) + half_phi * t
        phi_axis = self.phi(row[:, None])
        c, wc = self.cos_theta.x(sc), w * half_c * self.cos_theta.dx_ds(sc)
        phi, wp = phi_axis.x(sp), w * half_phi * phi_axis.dx_ds(sp)
        c, phi = c[:, :, None], phi[:, None, :]
        s = np.sqrt(1.0 - c**2)
        directions = np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), self.side * c), axis=-1)
        return directions.reshape(len(row), -1, 3), (wc[:, :, None] * wp[:, None, :]).reshape(len(row), -1)


def lobe_grid(material: Material, wi: np.ndarray) -> HemisphereGrid:
    """A grid on wi's side whose cells crowd around the mirror direction at the scale of the
    material's lobe (uniform for diffuse).

    For GGX of roughness alpha, wo = 2 (wi.m) m - wi with microfacet normals m tilted by slopes of
    scale alpha: cos theta_o moves by ~2 alpha (sin theta_i + alpha) and, at elevation
    cos theta_o = c, the azimuth by ~alpha (c + cos theta_i) / sin theta_o, since
    wi.m = (c + cos theta_i) / 2. At grazing incidence the lobe is a thin fan along the horizon."""
    side = 1.0 if wi[2] >= 0.0 else -1.0
    rows = GRID_CELLS[0]
    cos_r, sin_r = abs(float(wi[2])), float(np.hypot(wi[0], wi[1]))
    phi_r = float(np.arctan2(-wi[1], -wi[0]))
    if not isinstance(material, Glossy):
        return HemisphereGrid(side, Axis(0.0, 1.0), phi_r, np.full(rows, np.inf))
    alpha = material.roughness
    cos_theta = Axis(0.0, 1.0, cos_r, 2.0 * alpha * (sin_r + alpha))
    edges = cos_theta.edges(rows)
    c = 0.5 * (edges[:-1] + edges[1:])
    phi_width = alpha * (c + cos_r) / np.sqrt(1.0 - c**2)
    return HemisphereGrid(side, cos_theta, phi_r, np.where(phi_width < np.pi, phi_width, np.inf))


@dataclass(frozen=True)
class CellIntegrals:
    """Integrals of one channel of evaluate_bsdf over each cell (cases, *cells), and the sum of
    the error estimates of the pieces each was integrated in."""

    value: np.ndarray
    error: np.ndarray


# budget(a case's integrals so far (cells)) -> the absolute error each of its cells may have
ErrorBudget = Callable[[np.ndarray], np.ndarray]
# integrand(case (n,), directions (n, 3)) -> values (n,)
Integrand = Callable[[np.ndarray, np.ndarray], np.ndarray]


def integrate_bsdf(
    context, materials: np.ndarray, wi: np.ndarray, grids: list[HemisphereGrid], channel: int, budget: ErrorBudget
) -> CellIntegrals:
    """Integrals of evaluate_bsdf's `channel` over every cell of each case's grid."""

    def integrand(case: np.ndarray, directions: np.ndarray) -> np.ndarray:
        return evaluate_bsdf(context, materials, wi, directions, case)[:, channel]

    return integrate(grids, integrand, budget)


def integrate(grids: list[HemisphereGrid], integrand: Integrand, budget: ErrorBudget) -> CellIntegrals:
    """Integrals of `integrand` over every cell of each case's grid (all grids of one shape),
    refined until each cell's error estimate fits its budget: a piece whose error exceeds its share
    is split in four, at most MAX_REFINEMENTS times.
    """
    rows, columns = grids[0].cells
    cells = rows * columns
    # pieces of cells: case, cell, ranges of the integration variables (n, 2), share of the cell
    case = np.repeat(np.arange(len(grids)), cells)
    cell = np.tile(np.arange(cells), len(grids))
    s_c, s_phi = (np.concatenate(r) for r in zip(*(grid.cell_ranges() for grid in grids), strict=True))
    share = np.ones(len(case))
    value = np.zeros((len(grids), cells))
    error = np.zeros((len(grids), cells))
    for refinement in range(MAX_REFINEMENTS + 1):
        fine, coarse = _integrate_pieces(grids, integrand, case, cell, s_c, s_phi)
        piece_error = np.abs(fine - coarse)
        estimate = value.copy()
        np.add.at(estimate, (case, cell), fine)
        budgets = np.stack([budget(e.reshape(rows, columns)).ravel() for e in estimate])
        done = (piece_error <= budgets[case, cell] * share) | (refinement == MAX_REFINEMENTS)
        np.add.at(value, (case[done], cell[done]), fine[done])
        np.add.at(error, (case[done], cell[done]), piece_error[done])
        case, cell, s_c, s_phi, share = (a[~done] for a in (case, cell, s_c, s_phi, share))
        if len(case) == 0:
            break
        # each remaining piece becomes four
        c_mid, phi_mid = s_c.mean(axis=1), s_phi.mean(axis=1)
        c_halves = [np.stack([s_c[:, 0], c_mid], 1), np.stack([c_mid, s_c[:, 1]], 1)]
        phi_halves = [np.stack([s_phi[:, 0], phi_mid], 1), np.stack([phi_mid, s_phi[:, 1]], 1)]
        s_c = np.concatenate(c_halves * 2)
        s_phi = np.concatenate([phi_halves[0]] * 2 + [phi_halves[1]] * 2)
        case, cell, share = np.tile(case, 4), np.tile(cell, 4), np.tile(share / 4.0, 4)
    return CellIntegrals(value.reshape(len(grids), rows, columns), error.reshape(len(grids), rows, columns))


def _integrate_pieces(grids, integrand, case, cell, s_c, s_phi) -> tuple[np.ndarray, np.ndarray]:
    """Integrals over pieces at QUADRATURE_ORDER and at half that order, in one integrand call."""
    orders = (QUADRATURE_ORDER, QUADRATURE_ORDER // 2)
    row = cell // grids[0].cells[1]
    directions, weights, owners = [], [], []
    for order in orders:
        d = np.empty((len(case), order * order, 3))
        w = np.empty((len(case), order * order))
        for k, grid in enumerate(grids):
            mine = case == k
            if mine.any():
                d[mine], w[mine] = grid.rule(row[mine], s_c[mine], s_phi[mine], order)
        directions.append(d.reshape(-1, 3))
        weights.append(w)
        owners.append(np.repeat(case, order * order))
    values = integrand(np.concatenate(owners), np.concatenate(directions))
    fine_points = weights[0].size
    fine = np.sum(weights[0] * values[:fine_points].reshape(weights[0].shape), axis=1)
    coarse = np.sum(weights[1] * values[fine_points:].reshape(weights[1].shape), axis=1)
    return fine, coarse
