// Textures: texture_sample, surface_uv, and resolve_material (a material with its textures applied).
//
// Every texture is a rectangle of texels in one atlas (pack_atlas: 8-bit bytes, sRGB or linear, or
// linear float32), filtered by hand, bilinearly, after decoding each texel: filtering float32
// textures is an optional WebGPU feature, and the hardware filters sRGB bytes only in a texture
// whose every texel is sRGB. Only mip level 0 exists: a path tracer averages many samples per pixel
// over the pixel's footprint, which filters minified textures as supersampling does.
//! include "common/constants.wgsl"
//! include "geometry/barycentric.wgsl"
//! include "shading/corner_vertices.wgsl"
//! include "generated/instancing.wgsl"

const TEXTURE_COORDINATE_MAX: f32 = 16777216.0;

// Texel index i of an axis of n texels under its wrap mode (WRAP_<MODE>, numbered as WRAP_MODES):
// repeat, clamp to the edge, or mirror (glTF's MIRRORED_REPEAT: period 2n, the second half reversed).
fn texture_wrap(i: i32, n: i32, mode: u32) -> i32 {
    if mode == WRAP_REPEAT {
        return ((i % n) + n) % n;
    }
    if mode == WRAP_CLAMP {
        return clamp(i, 0, n - 1);
    }
    let m = ((i % (2 * n)) + 2 * n) % (2 * n);
    return select(m, 2 * n - 1 - m, m >= n);
}

// The sRGB transfer function inverted (IEC 61966-2-1), as srgb_to_linear.
fn srgb_decode(encoded: vec3<f32>) -> vec3<f32> {
    return select(pow((encoded + 0.055) / 1.055, vec3<f32>(2.4)), encoded / 12.92, encoded <= vec3<f32>(0.04045));
}

// A texel of texture `t`, its colour linear.
fn texture_texel(t: Texture, column: i32, row: i32) -> vec4<f32> {
    let x = texture_wrap(column, i32(t.size.x), t.wrap_s);
    let y = texture_wrap(row, i32(t.size.y), t.wrap_t);
    let texel = textureLoad(texture_atlas, t.origin + vec2<u32>(u32(x), u32(y)), 0);
    if t.srgb == 0u {
        return texel;
    }
    return vec4<f32>(srgb_decode(texel.rgb), texel.a);
}

// Texture `id` at texture coordinates `uv` (glTF's: (0, 0) the image's top-left corner, v down),
// through its transform, bilinear between the four nearest texel centres ((j + 1/2) / W).
fn texture_sample(id: u32, uv: vec2<f32>) -> vec4<f32> {
    let t = textures[id];
    // non-finite coordinates (a degenerate triangle's) read texel (0, 0) rather than NaN
    let finite = select(vec2<f32>(0.0), uv, abs(uv) < vec2<f32>(FLOAT_MAX));
    let st = vec2<f32>(dot(t.transform_u, vec3<f32>(finite, 1.0)), dot(t.transform_v, vec3<f32>(finite, 1.0)));
    // beyond 2^24 texels f32 has no fraction left to interpolate, and inf - inf would be NaN
    let xy = clamp(st * vec2<f32>(t.size) - 0.5, vec2<f32>(-TEXTURE_COORDINATE_MAX), vec2<f32>(TEXTURE_COORDINATE_MAX));
    let corner = floor(xy);
    let f = xy - corner;
    let c = vec2<i32>(corner);
    let top = mix(texture_texel(t, c.x, c.y), texture_texel(t, c.x + 1, c.y), f.x);
    let bottom = mix(texture_texel(t, c.x, c.y + 1), texture_texel(t, c.x + 1, c.y + 1), f.x);
    return mix(top, bottom, f.y);
}

// The texture coordinates at `p` on triangle `triangle_index`, interpolated from its corners.
fn surface_uv(triangle_index: u32, triangle: Triangle, p: vec3<f32>) -> vec2<f32> {
    let v = corner_vertices(mesh_triangle(triangle_index));
    let b = triangle_barycentric(triangle, p);
    return (1.0 - b.x - b.y) * vertex_uvs[v.x].uv + b.x * vertex_uvs[v.y].uv + b.y * vertex_uvs[v.z].uv;
}

// The material at a hit with its textures applied, so that BSDF code reads constants. Only the
// Principled material has textures; its record keeps base_color in `color`, roughness in `alpha`
// and metallic in `metallic` (Principled.fill_record), which glTF's
// metallic-roughness texture scales by its G and B channels.
fn resolve_material(material: Material, material_index: u32, triangle_index: u32, triangle: Triangle, p: vec3<f32>) -> Material {
    let slots = material_textures[material_index];
    if slots.base_color == NO_TEXTURE && slots.metallic_roughness == NO_TEXTURE {
        return material;
    }
    let uv = surface_uv(triangle_index, triangle, p);
    var resolved = material;
    if slots.base_color != NO_TEXTURE {
        resolved.color *= texture_sample(slots.base_color, uv).rgb;
    }
    if slots.metallic_roughness != NO_TEXTURE {
        let texel = texture_sample(slots.metallic_roughness, uv);
        resolved.alpha *= texel.g;
        resolved.metallic *= texel.b;
    }
    return resolved;
}
