// A 4-wide node's children sorted nearest first (a sorting network), for the BVH's traverse.
// Sorting all four measured no slower than only the nearest first (bench/README.md), and nearer
// boxes first shorten the hit distance sooner.

fn order_children(c0: ptr<function, vec2<u32>>, c1: ptr<function, vec2<u32>>, c2: ptr<function, vec2<u32>>, c3: ptr<function, vec2<u32>>) {
    order_pair(c0, c1);
    order_pair(c2, c3);
    order_pair(c0, c2);
    order_pair(c1, c3);
    order_pair(c1, c2);
}
