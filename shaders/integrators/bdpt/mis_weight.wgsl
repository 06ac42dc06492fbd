// MisSums: multiple importance sampling over bidirectional strategies by running sums (Georgiev 2012).
//
// "Implementing Vertex Connection and Merging" (tech. report) rewrites Veach's weight of a
// strategy, 1 / sum over strategies of (p_other / p_taken)^2 (power heuristic), as products that
// each subpath carries along: `dvcm` and `dvc` (its eqs. 31-45, without the merging terms), so that
// a connection's weight needs only its two end vertices, not the whole path. pbrt-v4's recursive
// pdfFwd/pdfRev ratios compute the same sums; these need no stored camera subpath.

// The power heuristic's exponent (2) applied to a density ratio.
fn mis(ratio: f32) -> f32 {
    return ratio * ratio;
}

// Densities are per unit area on geometry (geometric normals' cosines) or per steradian. Where a
// strategy's true density is awkward, every weight uses the same stand-in for it, which keeps the
// weights summing to one per path (any partition of unity leaves the estimate unbiased):
// - next-event estimation's density of a light triangle's point is its area density in the light
//   table (emission_pdf_triangle's position) though sample_light draws by solid angle;
// - the distant lights are one mixture (DistantEmission) and a directional light's disc
//   is the scene's (bdpt_distant_disk_area);
// - Russian roulette is left out of every density;
// - vertices that cannot connect (glass, near-mirrors: material_samples_lights) scatter as deltas
//   whose forward and reverse densities are equal.
//
// A subpath's running sums after its last vertex (Georgiev's dVCM and dVC).
struct MisSums {
    // (the density of the strategy that would have sampled this vertex from the other end) / (this
    // subpath's density of it), squared; with dvc, everything that subpath end needs
    dvcm: f32,
    dvc: f32,
}

// A camera subpath's sums at its start: the camera ray's density over the whole image
// (camera_ray_density), against which light tracing's density is weighed; no vertex before it.
// A parallel camera's density is per unit area already, which mis_sums_at_hit is told at its first
// hit as it is for a distant light's first ray.
fn camera_mis_sums(camera_pdf: f32) -> MisSums {
    return MisSums(mis(1.0 / camera_pdf), 0.0);
}

// A light subpath's sums at its start: `direct_pdf` (the stand-in density with which next-event
// estimation picks this light point, per unit area; per steradian for distant lights),
// `emission_pdf` (the light path's density of point and direction together), `cos_light` (1
// without a surface) and whether the direction is fixed (no BSDF sample can reach the light).
fn light_mis_sums(direct_pdf: f32, emission_pdf: f32, cos_light: f32, fixed_direction: bool) -> MisSums {
    let dvc = select(mis(cos_light / emission_pdf), 0.0, fixed_direction);
    return MisSums(mis(direct_pdf / emission_pdf), dvc);
}

// The sums after the subpath's ray reached its next vertex at `distance`, hitting it at `cos_hit`
// (geometric). `from_infinity`: the first ray of a distant light's path, whose density is per
// steradian already (no distance to convert by).
fn mis_sums_at_hit(sums: MisSums, distance: f32, cos_hit: f32, from_infinity: bool) -> MisSums {
    var dvcm = sums.dvcm;
    if !from_infinity {
        dvcm *= mis(distance * distance);
    }
    let per_cos = 1.0 / mis(cos_hit);
    return MisSums(dvcm * per_cos, sums.dvc * per_cos);
}

// The sums after the vertex scattered to a direction leaving it at `cos_out` (geometric), drawn with
// density `pdf_forward` (per steradian) where the reverse direction would have had `pdf_reverse`.
// A delta lobe ends every strategy that would have connected here (dvcm 0).
fn mis_sums_after_scattering(sums: MisSums, cos_out: f32, pdf_forward: f32, pdf_reverse: f32, delta: bool) -> MisSums {
    if delta {
        return MisSums(0.0, sums.dvc * mis(cos_out));
    }
    return MisSums(mis(1.0 / pdf_forward), mis(cos_out / pdf_forward) * (sums.dvc * mis(pdf_reverse) + sums.dvcm));
}

// What the strategies beyond a connection's end vertex add: its subpath's sums, the vertex's
// reverse density (`pdf_reverse`: of its subpath's previous direction, given the connection's) and
// the other end's density of this vertex per unit area (`pdf_area_from_other`).
fn mis_subpath_term(sums: MisSums, pdf_reverse: f32, pdf_area_from_other: f32) -> f32 {
    return mis(pdf_area_from_other) * (sums.dvcm + sums.dvc * mis(pdf_reverse));
}

// The weight of a camera subpath that found emission itself (s = 0): `direct_pdf` is next-event
// estimation's density of that point (per unit area; per steradian for distant lights) and
// `emission_pdf` the light path's density of point and direction.
fn emission_hit_weight(sums: MisSums, direct_pdf: f32, emission_pdf: f32) -> f32 {
    return 1.0 / (1.0 + mis(direct_pdf) * sums.dvcm + mis(emission_pdf) * sums.dvc);
}

// The weight of next-event estimation (s = 1): `bsdf_pdf` the camera vertex's density of the
// light's direction (0 for lights no BSDF sample can hit), `direct_pdf_solid_angle` next-event
// estimation's (stand-in) density of it, `emission_ratio` the light path's density of the camera
// vertex per unit area over next-event estimation's of the light point, `pdf_reverse` the camera
// vertex's density of its own previous direction given the light's.
fn next_event_weight(sums: MisSums, bsdf_pdf: f32, direct_pdf_solid_angle: f32, emission_ratio: f32, pdf_reverse: f32) -> f32 {
    let light_side = mis(bsdf_pdf / direct_pdf_solid_angle);
    let camera_side = mis(emission_ratio) * (sums.dvcm + sums.dvc * mis(pdf_reverse));
    return 1.0 / (1.0 + light_side + camera_side);
}

// The weight of a connection between the two subpaths' ends (s >= 2, t >= 2; t = 1 with no camera
// term): each end's mis_subpath_term.
fn connection_weight(light_term: f32, camera_term: f32) -> f32 {
    return 1.0 / (1.0 + light_term + camera_term);
}
