// Named numeric constants: every tolerance the shaders depend on, with what it protects.

const PI: f32 = 3.14159265358979;
const INV_PI: f32 = 0.318309886183791;
const TWO_PI: f32 = 6.28318530717959;

// Largest finite f32: the "no hit yet" distance.
const FLOAT_MAX: f32 = 3.40282346e38;

// Direction components smaller than this are replaced by it (sign kept) before taking 1/d in
// slab tests: an axis-parallel ray then gets huge but finite slab distances instead of inf or NaN.
const MIN_DIRECTION_COMPONENT: f32 = 1e-30;

// Slab distances carry up to 3 rounding errors each; widening the far distance by 1 + 2 gamma(3)
// (Ize 2013) keeps boxes from being missed by rays that graze them.
const BOX_FAR_SCALE: f32 = 1.00000036;

// A ray leaving a surface starts this far (relative to the size of the coordinates involved) off
// the surface, on the side it leaves to, so it cannot hit a neighbouring triangle at t ~ 0 through
// rounding. Relative, so a scene scaled by 1e-4 or 1e4 renders the same.
const RAY_OFFSET_RELATIVE: f32 = 1e-5;

// Cosines below this are treated as grazing: no reflection is sampled or evaluated there.
const COS_MIN: f32 = 1e-7;

// GGX with alpha -> 0 is a delta; clamping keeps D finite in f32 (D ~ 1 / (pi alpha^2)).
const GGX_ALPHA_MIN: f32 = 1e-4;

// Shadow rays stop this fraction short of the light point, so the light's own triangle (or a
// neighbour sharing its edge) never counts as an occluder.
const SHADOW_RAY_SHORTENING: f32 = 0.9999;


// The largest f32 below 1: uniform numbers rescaled after a discrete draw are kept below 1 with it.
const ONE_MINUS_EPSILON: f32 = 0.99999994;
