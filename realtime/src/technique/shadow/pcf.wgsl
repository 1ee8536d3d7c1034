// shadow/pcf.wgsl — percentage-closer filtering: the fraction of shadow-map comparisons that pass
// around the lookup (`pcf_hw_2x2`, `pcf_box`, `pcf_poisson`).
//
// Technique: Reeves, Salesin & Cook 1987, "Rendering Antialiased Shadows with Depth Maps",
// SIGGRAPH '87 (https://doi.org/10.1145/37402.37435): filter the results of the depth
// comparisons, never the depths. Three kernels:
// - `pcf_hw_2x2`: one hardware comparison with a linear-filtering comparison sampler — the
//   2×2 texels around the lookup compared and bilinearly weighted (WebGPU
//   `textureSampleCompareLevel`; a tent of one texel's radius);
// - `pcf_box`: k×k nearest comparisons on the texel grid centred on the lookup, averaged —
//   a box of k texels (V in steps of 1/k²);
// - `pcf_poisson`: N bilinear comparisons at Poisson-disk taps of radius R texels, averaged
//   (the tap pattern: shadow/poisson.rs `poisson_disk`, Mitchell 1991 best candidate; a fixed
//   pattern, so undersampling shows as banding, unless `rotate` turns it per pixel by
//   interleaved gradient noise, Jimenez 2014 — shadow/map_common.wgsl — trading it for noise).
// Each tap compares against the receiver plane's depth there when the receiver-plane bias is
// on (shadow/map_common.wgsl); the single-comparison `pcf_hw_2x2` cannot.
// Failure mode: the penumbra width is the kernel's, fixed in texels — it does not grow with the
// blocker–receiver distance (no contact hardening) and shrinks in world units as the map's
// resolution rises; wide kernels on receivers tilted to the light self-shadow (one reference
// depth for the whole kernel), and light leaks under thin blockers.
// Inputs: the receiver's lookup, the map layer and side, the kernel size / tap count and radius,
// the taps' rotation.

fn pcf_hw_2x2(r: ShadowReceiver, layer: u32) -> f32 {
    return shadow_compare_bilinear(layer, r.uv, r.depth);
}

// k×k texels centred on the lookup's texel offset grid.
fn pcf_box(r: ShadowReceiver, layer: u32, k: u32, side: f32) -> f32 {
    let half = f32(k - 1u) * 0.5;
    let texel = 1.0 / side;
    var lit = 0.0;
    for (var j = 0u; j < k; j++) {
        for (var i = 0u; i < k; i++) {
            count_iteration();
            let offset = vec2<f32>(f32(i) - half, f32(j) - half) * texel;
            lit += shadow_compare_nearest(layer, r.uv + offset, shadow_tap_depth(r, offset));
        }
    }
    return lit / f32(k * k);
}

// `taps` bilinear comparisons on the Poisson disk of radius `radius_uv` (map coordinates),
// turned by `rot` = (cos φ, sin φ).
fn pcf_poisson(r: ShadowReceiver, layer: u32, taps: u32, radius_uv: f32, rot: vec2<f32>) -> f32 {
    var lit = 0.0;
    for (var k = 0u; k < taps; k++) {
        count_iteration();
        let offset = poisson_tap(k, rot) * radius_uv;
        lit += shadow_compare_bilinear(layer, r.uv + offset, shadow_tap_depth(r, offset));
    }
    return lit / f32(taps);
}
