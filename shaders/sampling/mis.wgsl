// Multiple importance sampling weights (Veach 1997).

// Power heuristic with beta = 2 for a sample drawn with density pdf_taken, where the other
// strategy would have drawn it with density pdf_other.
fn power_heuristic(pdf_taken: f32, pdf_other: f32) -> f32 {
    let a = pdf_taken * pdf_taken;
    let b = pdf_other * pdf_other;
    return select(0.0, a / (a + b), a > 0.0);
}
