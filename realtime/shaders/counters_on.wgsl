// counters_on.wgsl — the counting variant: each shaded sample adds its cost to its target row.
//
// Technique: hardware-independent cost counters — texel fetches and shading-loop iterations
// per visible sample, summed per target row with atomics, then in u64 on the CPU. They are
// measured once per render by a dedicated frame: a G-buffer pass, then the lighting entry
// point, both compiled with this file, so every visible sample (background included) is shaded
// exactly once, whatever the pipeline's overdraw and whether the hardware tests depth before or
// after shading. The G-buffer stage's fetches (normal map, surface detail) travel to the
// lighting pass in the sample's object-id field (`gbuffer_tag`), so those of occluded
// fragments are not counted either (loop iterations are the shading pass's only). Timed pipelines use counters_off.wgsl and carry no
// atomics (storage side effects would turn early depth testing off).
// Failure mode: a surface's fetches saturate at 4095 per sample, and scenes of 4095 shapes or
// more cannot be counted (render.rs refuses them); a row's u32 sums overflow past ~4·10⁹ (e.g. 8192 samples × 5·10⁵ fetches per
// sample); forward overdraw (occluded fragments shaded before the visible one) is not counted.
// Inputs: the private `cost` of common.wgsl, the `counters` buffer (group 0, binding 7).

// Fetches per sample the G-buffer field can carry, and shapes it can name: tag =
// shape + 1 + COUNT_RANGE·fetches stays an exact f32 integer (< 2²⁴).
const COUNT_RANGE: u32 = 4096u;

// The counting G-buffer's object-id field: the shape and the fetches its surface cost so far.
fn gbuffer_tag(shape: u32) -> f32 {
    return f32(shape + 1u + COUNT_RANGE * min(cost.x, COUNT_RANGE - 1u));
}

// The shape of a counting G-buffer field; its surface's fetches are added to this sample's.
fn gbuffer_shape(tag: f32) -> u32 {
    let t = u32(tag);
    cost.x += t / COUNT_RANGE;
    return t % COUNT_RANGE - 1u;
}

fn flush_counters(row: u32) {
    atomicAdd(&counters[2u * row], cost.x);
    atomicAdd(&counters[2u * row + 1u], cost.y);
}
