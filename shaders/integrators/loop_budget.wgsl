// Whether the driver's loop budget ran out during this invocation, so some loop may have been cut short.
//
// llvmpipe (Mesa's CPU driver) gives each invocation one budget of 65,535 loop iterations shared by
// every loop it runs, nested or one after another, and silently ends loops once it is spent
// (LLVMPIPE_LOOP_ITERATION_LIMIT). A path whose traversals test
// thousands of triangles each can spend it, and then its hits are missed without a sign. This loop
// must run twice; where the budget is spent it stops after once. The trip count comes from
// `at_least_one` (any value >= 1 the compiler cannot know, e.g. the image width), so the loop
// cannot be unrolled away. Other drivers have no such budget: there this is always false.
fn loop_budget_spent(at_least_one: u32) -> bool {
    let trips = 1u + min(at_least_one, 1u);
    var runs = 0u;
    loop {
        runs++;
        if runs >= trips {
            break;
        }
    }
    return runs < trips;
}
