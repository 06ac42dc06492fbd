// texel_at: texel `index` of a texture of records whose width is a power of two (texture_shape).

fn texel_at(texels: texture_storage_2d<rgba32uint, read>, index: u32) -> vec4<u32> {
    let width = textureDimensions(texels).x;
    return textureLoad(texels, vec2<u32>(index & (width - 1u), index >> countTrailingZeros(width)));
}
