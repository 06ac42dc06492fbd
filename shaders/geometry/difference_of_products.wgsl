// difference_of_products: a * b - c * d with the sign the watertight triangle test's edge functions need.
//
// Never of the wrong sign, exactly zero when a * b equals c * d, and of the opposite sign when the
// two products swap places. With a fused fma this is Kahan's algorithm (relative error at most 2 ulp:
// Jeannerod, Louvet and Muller 2013; the sign is exact). Where fma is not fused (WGSL allows
// either; llvmpipe) `error` is zero and this is the plain expression with both products rounded,
// which has the three properties too (it may round a tiny difference to zero).
//
// Why not write `a * b - c * d`: GPU compilers may contract it into fma(a, b, -(c * d)), which
// rounds only one product, and then none of the three holds: measured on an NVIDIA H100, rays
// slipped between the two triangles of a quad and hit triangles whose three corners coincide. With
// explicit fma calls there is nothing left to contract.
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let error = fma(-c, d, cd);
    return fma(a, b, -cd) + error;
}
