// A heat colour ramp for scalar debug views: dark blue (0) through cyan, green, yellow to red (1).

const HEAT_STOPS = array<vec3<f32>, 6>(
    vec3<f32>(0.0, 0.0, 0.25),
    vec3<f32>(0.0, 0.2, 1.0),
    vec3<f32>(0.0, 0.9, 0.9),
    vec3<f32>(0.1, 0.9, 0.1),
    vec3<f32>(1.0, 0.9, 0.0),
    vec3<f32>(1.0, 0.0, 0.0),
);

fn heat_color(x: f32) -> vec3<f32> {
    let position = clamp(x, 0.0, 1.0) * 5.0;
    let lower = min(u32(position), 4u);
    return mix(HEAT_STOPS[lower], HEAT_STOPS[lower + 1u], position - f32(lower));
}
