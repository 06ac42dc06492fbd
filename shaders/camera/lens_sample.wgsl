// The lens sample of a camera ray: the sampler's next 2D draw for a camera with a lens (CAMERA_LENS), none for the others.
//! include "generated/camera.wgsl"
//! include "sampling/sampler.wgsl"
//
// Drawing nothing for the other kinds keeps their sampler dimensions as they were: their images
// stay the same with the lens code compiled beside them.

fn lens_sample() -> vec2<f32> {
    if CAMERA_LENS {
        return sample_2d();
    }
    return LENS_CENTRE;
}
