// A pixel's guide packed into one rgba32uint texel, so a filter tap costs one texture load.
//
// x: the unit normal, octahedral-encoded in two 16-bit snorms (Cigolle et al. 2014; error below
//    GUIDE_NORMAL_ERROR), y: the hit distance's bits, z: albedo as 8-bit unorms (clamped to
//    [0, 1]; an emitter's colour is its radiance), w: BVH nodes visited.

struct Guide {
    normal: vec3<f32>,
    depth: f32,
    albedo: vec3<f32>,
    steps: u32,
}

fn sign_not_zero(v: vec2<f32>) -> vec2<f32> {
    return select(vec2<f32>(-1.0), vec2<f32>(1.0), v >= vec2<f32>(0.0));
}

fn octahedral_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    return select(p, (1.0 - abs(p.yx)) * sign_not_zero(p), n.z < 0.0);
}

fn octahedral_decode(e: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    if n.z < 0.0 {
        n = vec3<f32>((1.0 - abs(n.yx)) * sign_not_zero(n.xy), n.z);
    }
    return normalize(n);
}

fn pack_guide(guide: Guide) -> vec4<u32> {
    return vec4<u32>(
        pack2x16snorm(octahedral_encode(guide.normal)),
        bitcast<u32>(guide.depth),
        pack4x8unorm(vec4<f32>(clamp(guide.albedo, vec3<f32>(0.0), vec3<f32>(1.0)), 0.0)),
        guide.steps,
    );
}

fn unpack_guide(texel: vec4<u32>) -> Guide {
    return Guide(octahedral_decode(unpack2x16snorm(texel.x)), bitcast<f32>(texel.y), unpack4x8unorm(texel.z).xyz, texel.w);
}
