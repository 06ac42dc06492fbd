// Variant (bench/kernel_profile.py nearest_child_first): only a 4-wide node's nearest child first, the other three in no particular order.

fn order_children(c0: ptr<function, vec2<u32>>, c1: ptr<function, vec2<u32>>, c2: ptr<function, vec2<u32>>, c3: ptr<function, vec2<u32>>) {
    order_pair(c0, c1);
    order_pair(c0, c2);
    order_pair(c0, c3);
}
