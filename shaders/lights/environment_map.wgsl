// An environment map: Mitsuba 3's envmap convention, bilinear lookup by hand, alias-table sampling by cells.
//! include "lights/environment.wgsl"
//! include "sampling/warps.wgsl"
//
// The numpy references are Environment's (its docstring pins the convention): a direction of the
// map's own frame has u = atan2(x, -z) / 2 pi, v = acos(y) / pi; column i's texels sit at
// u = (i + 1/2) / W (column W - 1 blends with column 0), row j's at v = j / (H - 1). The map's frame
// is the world turned by -rotation about +y (lighting.environment_rotation = (cos, sin)).
// textureLoad, since filtering float32 textures is optional.

// True only in bench.environment: the map sampled uniformly over the sphere (as pbrt's
// UniformInfiniteLight) instead of by its tables, the baseline importance sampling is measured against.
override ENVIRONMENT_UNIFORM_SAMPLING: bool = false;

fn environment_cell_rows() -> u32 {
    return max(lighting.environment_size.y, 2u) - 1u;
}

// world -> the map's frame: R^T world, R = [[c, 0, s], [0, 1, 0], [-s, 0, c]] (Mitsuba's to_world)
fn environment_local(world: vec3<f32>) -> vec3<f32> {
    let r = lighting.environment_rotation;
    return vec3<f32>(r.x * world.x - r.y * world.z, world.y, r.y * world.x + r.x * world.z);
}

fn environment_world(local: vec3<f32>) -> vec3<f32> {
    let r = lighting.environment_rotation;
    return vec3<f32>(r.x * local.x + r.y * local.z, local.y, r.x * local.z - r.y * local.x);
}

// (u in [0, 1), v in [0, 1]) of a unit direction of the map's frame; u = 0 straight up or down
fn environment_uv(local: vec3<f32>) -> vec2<f32> {
    var u = 0.0;
    if local.x != 0.0 || local.z != 0.0 {
        u = fract(atan2(local.x, -local.z) * (0.5 * INV_PI));
    }
    return vec2<f32>(u, acos(clamp(local.y, -1.0, 1.0)) * INV_PI);
}

fn environment_texel(column: u32, row: u32) -> vec3<f32> {
    return textureLoad(environment_map, vec2<u32>(column, row), 0).rgb;
}

// The bilinear lookup of the numpy `bilinear`, times the intensity.
fn environment_radiance(direction: vec3<f32>) -> vec3<f32> {
    let size = lighting.environment_size;
    let uv = environment_uv(environment_local(direction));
    let x = fract(uv.x - 0.5 / f32(size.x)) * f32(size.x);
    let y = uv.y * f32(size.y - 1u);
    let column = min(u32(x), size.x - 1u);
    let row = min(u32(y), max(size.y, 2u) - 2u);
    let wx = x - f32(column);
    let wy = y - f32(row);
    let next_column = (column + 1u) % size.x;
    let next_row = min(row + 1u, size.y - 1u);
    let top = mix(environment_texel(column, row), environment_texel(next_column, row), wx);
    let bottom = mix(environment_texel(column, next_row), environment_texel(next_column, next_row), wx);
    return mix(top, bottom, wy) * lighting.environment_radiance;
}

fn environment_cell_pdf(row: u32, column: u32) -> f32 {
    let rows = environment_cell_rows();
    let width = lighting.environment_size.x;
    return bitcast<f32>(environment_tables[2u * rows + 2u * rows * width + row * width + column]);
}

fn environment_pdf(direction: vec3<f32>) -> f32 {
    if ENVIRONMENT_UNIFORM_SAMPLING {
        return pdf_uniform_sphere();
    }
    let uv = environment_uv(environment_local(direction));
    let width = lighting.environment_size.x;
    let rows = environment_cell_rows();
    let column = u32(floor(fract(uv.x - 0.5 / f32(width)) * f32(width))) % width;
    let row = min(u32(uv.y * f32(rows)), rows - 1u);
    return environment_cell_pdf(row, column);
}

struct AliasDraw {
    index: u32,
    // what is left of the uniform number after the draw, uniform in [0, 1) again
    remapped: f32,
}

// One draw from the alias table of `count` entries starting at word `first`, by one uniform `x`:
// slot floor(x count), kept when the remainder is below its threshold, else its alias (as
// the numpy draw_alias); the remainder, rescaled, is uniform and independent of the draw.
fn environment_alias_draw(first: u32, count: u32, x: f32) -> AliasDraw {
    let scaled = x * f32(count);
    let slot = min(u32(scaled), count - 1u);
    let remainder = scaled - f32(slot);
    let threshold = bitcast<f32>(environment_tables[first + 2u * slot]);
    if remainder < threshold {
        return AliasDraw(slot, min(remainder / threshold, ONE_MINUS_EPSILON));
    }
    return AliasDraw(environment_tables[first + 2u * slot + 1u], min((remainder - threshold) / (1.0 - threshold), ONE_MINUS_EPSILON));
}

// One of R x W cells (R = max(H - 1, 1) cell rows between texel rows, W cells between columns)
// drawn by luminance x solid angle from the tables (environment_table_words has their layout),
// then a direction uniform in the cell's solid angle, so the density per steradian is the cell's,
// the same all over it. A cell row by u.x, a cell of it by u.y, then within the cell phi by what
// is left of u.y and cos theta by what is left of u.x (the numpy local_in_cell).
fn environment_sample(u: vec2<f32>) -> vec3<f32> {
    if ENVIRONMENT_UNIFORM_SAMPLING {
        return sample_uniform_sphere(u);
    }
    let rows = environment_cell_rows();
    let width = lighting.environment_size.x;
    let row = environment_alias_draw(0u, rows, u.x);
    let column = environment_alias_draw(2u * rows + 2u * width * row.index, width, u.y);
    let phi = TWO_PI * (f32(column.index) + 0.5 + column.remapped) / f32(width);
    let top = cos(PI * f32(row.index) / f32(rows));
    let bottom = cos(PI * f32(row.index + 1u) / f32(rows));
    let cos_theta = top + (bottom - top) * row.remapped;
    let sin_theta = sqrt(max(0.0, 1.0 - cos_theta * cos_theta));
    return environment_world(vec3<f32>(sin(phi) * sin_theta, cos_theta, -cos(phi) * sin_theta));
}
