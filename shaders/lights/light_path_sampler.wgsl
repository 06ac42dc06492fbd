// sample_emission beside emission_pdf: where light paths start (a light by power, a point, a direction).
//
// The light is the one sample_light would choose with `u_select` (choose_light), so light paths and
// next-event estimation share its selection probability; pdf_position includes it. Triangles start
// here; the light sources in their own files, through the generated dispatch.
//! include "lights/direct_light_sampler.wgsl"
//! include "lights/light_path_sample.wgsl"
// sample_light_source_emission, light_source_emission_pdf, distant_emission and
// distant_lights_emission_pdf, generated for the scene's LightFeatures (light_emission_dispatch)
//! include "generated/light_emission.wgsl"

// Distant lights start on the scene's disc (distant_emission_sample). The environment and the suns
// are mixed: whichever was chosen, the sample carries the radiance of all of them along its
// direction and the densities of their mixture (DistantEmission), which emission_pdf_distant
// returns too, so that a light path's densities and those a camera path escaping along -direction
// is weighed with are one. A directional light is a delta in direction: not in that mixture.
fn sample_emission(u_select: vec2<f32>, u_position: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample {
    if frame.light_count == 0u {
        return no_emission_sample();
    }
    let word = choose_light(u_select);
    if !is_light_source(word) {
        return triangle_emission_sample(word, u_position, u_direction);
    }
    var sample = sample_light_source_emission(word, u_position, u_direction);
    if sample.distant && !sample.delta_direction {
        let mixture = distant_emission(-sample.direction);
        let pdf = distant_emission_pdf(mixture, scene_disk());
        // a direction on a map cell's border may round into a cell of density 0: it carries nothing
        if !(pdf.direction > 0.0) {
            return no_emission_sample();
        }
        sample.radiance = mixture.radiance;
        sample.pdf_position = pdf.position;
        sample.pdf_direction = pdf.direction;
    }
    return sample;
}

// The unit normal of a light triangle's front (the side cross(v1 - v0, v2 - v0) points to), or
// zero for a degenerate one.
fn light_triangle_front(triangle: Triangle) -> vec3<f32> {
    let n = cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0);
    let length_squared = dot(n, n);
    return select(vec3<f32>(0.0), n * inverseSqrt(length_squared), length_squared > 0.0);
}

// A light path leaving light triangle `index` (light table word): a point uniform in area, a
// cosine-weighted direction on one side; the radiance its material emits there (material_emitted
// and, through a texture record, surface_emission at the point). Two-sided triangles pick either
// side with probability 1/2 (u_direction.x's halves), so the direction density is |cos| / (2 pi);
// single-sided ones (surface_emits_both_sides false) leave their front only.
fn triangle_emission_sample(index: u32, u_position: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample {
    let triangle = scene_triangle(index);
    let front = light_triangle_front(triangle);
    if all(front == vec3<f32>(0.0)) {
        return no_emission_sample();
    }
    var u = u_direction;
    var normal = front;
    if surface_emits_both_sides(triangle.material) {
        // the lower half of u.x leaves the front, the upper half the back, each rescaled to [0, 1)
        let back = u.x >= 0.5;
        normal = select(front, -front, back);
        u.x = min(2.0 * u.x - select(0.0, 1.0, back), ONE_MINUS_EPSILON);
    }
    let direction = to_world(shading_frame(normal), sample_cosine_hemisphere(u));
    let position = uniform_triangle_point(triangle, u_position);
    let radiance = material_emitted(materials[triangle.material]) + surface_emission(triangle.material, index, triangle, position, -direction);
    let pdf = emission_pdf_triangle(index, triangle, direction);
    return EmissionSample(position, normal, direction, radiance, pdf.position, pdf.direction, index, false, false, false);
}

// The densities triangle_emission_sample has for light triangle `triangle_index` sending `direction`
// (unit, away from the surface): the light table's weight per unit area over the total (the
// selection probability over the area; 0 in a scene without lights, whose black emitters a camera
// path may still hit), and the cosine-weighted density of the side it leaves.
fn emission_pdf_triangle(triangle_index: u32, triangle: Triangle, direction: vec3<f32>) -> EmissionPdf {
    let cos_front = dot(light_triangle_front(triangle), direction);
    var pdf_direction = pdf_cosine_hemisphere(cos_front);
    if surface_emits_both_sides(triangle.material) {
        pdf_direction = 0.5 * pdf_cosine_hemisphere(abs(cos_front));
    }
    let total = frame.light_weight_total;
    return EmissionPdf(select(0.0, light_density(triangle_index, triangle) / total, total > 0.0), pdf_direction);
}

// The densities of a light path from the distant lights travelling along `direction` (unit, into
// the scene: minus the direction of a ray that escaped), as sample_emission gives them.
fn emission_pdf_distant(direction: vec3<f32>) -> EmissionPdf {
    return distant_lights_emission_pdf(direction);
}

// The densities sample_emission has for the light of table word `word` sending `direction` (unit,
// leaving it): a triangle's, a light source's (point, spot: its selection probability and
// direction density) or the distant lights' mixture.
fn emission_pdf(word: u32, direction: vec3<f32>) -> EmissionPdf {
    if is_light_source(word) {
        return light_source_emission_pdf(word, direction);
    }
    return emission_pdf_triangle(word, scene_triangle(word), direction);
}
