// shadow/hard.wgsl — hard shadows: one depth comparison at the nearest texel (`shadow_hard`).
//
// Technique: Williams 1978, "Casting Curved Shadows on Curved Surfaces", SIGGRAPH '78
// (https://doi.org/10.1145/965139.807402): V = 1 if the receiver's biased depth is not
// greater than the depth stored in the texel its lookup point falls in, else 0.
// Failure mode: V is 0 or 1 — an area light's penumbra collapses to the hard shadow of its
// centre; edges are stair-stepped at the texel size (aliasing), and crawl when the light or
// the receiver moves; acne and peter-panning as the bias is too small or too large
// (shadow/map_common.wgsl).
// Inputs: the receiver's lookup (shadow/map_common.wgsl `ShadowReceiver`), the map layer.

fn shadow_hard(r: ShadowReceiver, layer: u32) -> f32 {
    return shadow_compare_nearest(layer, r.uv, r.depth);
}
