// counters_on.wgsl — the counting variant: each shaded sample adds its cost to its target row.
//
// Technique: hardware-independent cost counters — texel fetches and shading-loop iterations
// per visible sample, summed per target row with atomics, then in u64 on the CPU. They are
// measured once per render by a dedicated frame: a G-buffer pass (no counters), then the
// lighting entry point compiled with this file, so every visible sample (background included)
// is shaded exactly once, whatever the pipeline's overdraw and whether the hardware tests depth
// before or after shading. The G-buffer stage's one lookup, the bilinear normal map (4 texels),
// is added by `count_surface_fetches`. Timed pipelines use counters_off.wgsl and carry no
// atomics (storage side effects would turn early depth testing off).
// Failure mode: a row's u32 sums overflow past ~4·10⁹ (e.g. 8192 samples × 5·10⁵ fetches per
// sample); forward overdraw (occluded fragments shaded before the visible one) is not counted.
// Inputs: the private `cost` of common.wgsl, the `counters` buffer (group 0, binding 7).

// The texel reads the G-buffer stage made for shape `s` (its normal map's bilinear lookup).
fn count_surface_fetches(s: Shape) {
    if s.normal_map != NONE {
        cost.x += 4u;
    }
}

fn flush_counters(row: u32) {
    atomicAdd(&counters[2u * row], cost.x);
    atomicAdd(&counters[2u * row + 1u], cost.y);
}
