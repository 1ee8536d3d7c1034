// antialias/specular.wgsl — specular anti-aliasing (technique/antialias/mod.rs): a GGX lobe
// narrower than the spread of normals a pixel covers makes a highlight that one sample per
// pixel either hits or misses — it sparkles, and the pixel's average is wrong. Both methods
// widen the lobe by that spread, as if the pixel's normals were one rougher surface:
//
// - SPECULAR_AA = 1, geometric (Kaplanyan, Hill, Patney & Lefohn 2016, "Filtering
//   Distributions of Normals for Shading Antialiasing", HPG; in the form of Tokuyoshi &
//   Kaplanyan 2019, "Improved Geometric Specular Antialiasing", I3D, Listing 1): the variance
//   of the shading normal over the pixel filter is σ²·(|∂n/∂x|² + |∂n/∂y|²), and
//   α² ← min(α² + min(2·variance, κ), 1).
// - SPECULAR_AA = 2, Toksvig (Toksvig 2005, "Mipmapping Normal Maps", JGT 10(3), §3): the
//   MIP-filtered normal map's average n̄ is shorter the more its normals spread; for normals
//   of slope variance σ², |n̄| ≈ 1/(1 + σ²), so σ² = (1 − |n̄|)/|n̄|; a GGX lobe of α has
//   slope variance α²/2 per axis near its peak (as Beckmann's), so α² ← min(α² + 2σ², 1).
//
// Ground truth: the oracle's box filter over the pixel of the unfiltered BSDF and normals.
// Failure mode: both add roughness the pixel does not contain where the normal's change is
// not spread inside it — up close, a smooth curved highlight gets wider and dimmer than the
// truth (the +1 % three.js shows on a metal sphere); the geometric kernel's derivatives
// come from the 2×2 quad (deferred: the G-buffer's stored normals, wrong across edges) and see
// only the normal's change between pixel centres, not bumps smaller than a pixel, which is
// what Toksvig's MIP levels hold; Toksvig sees only normal-map detail, not curvature. Only the
// GGX and metal-rough materials are widened (Phong keeps its exponent).

override SPECULAR_AA: u32 = 0u;

// The family's block of the frame uniform (SpecularAaUniforms in antialias/mod.rs): the
// geometric method's parameters (zeros under every other method).
struct SpecularAaUniforms {
    // σ² of the pixel filter in screen space.
    variance: f32,
    // Most α² the kernel adds (κ).
    clamp: f32,
}

// |∂n/∂x|² + |∂n/∂y|² of the shading normal of the pixel being shaded (geometric), per target
// pixel. Zero until set.
var<private> normal_change: f32;

// |n̄| of the pixel's last normal-map lookup before renormalising (Toksvig); 1 without one.
var<private> normal_map_length: f32 = 1.0;

// The normal's change from its quad derivatives. Call in uniform control flow.
fn set_normal_derivatives(n: vec3<f32>) {
    if SPECULAR_AA == 1u {
        set_normal_differences(dpdx(n), dpdy(n));
    }
}

// The normal's change from its differences to the neighbouring pixels in x and in y.
fn set_normal_differences(dx: vec3<f32>, dy: vec3<f32>) {
    let c = dot(dx, dx) + dot(dy, dy);
    normal_change = select(0.0, c, c < 1e30);
}

// GGX α widened by the method (the lobe's α, not roughness; α = roughness²).
fn specular_aa_alpha(alpha: f32) -> f32 {
    if SPECULAR_AA == 0u {
        return alpha;
    }
    var a2 = alpha * alpha;
    if SPECULAR_AA == 1u {
        a2 += min(2.0 * frame.families.specular_aa.variance * normal_change, frame.families.specular_aa.clamp);
    } else if SPECULAR_AA == 2u {
        let l = clamp(normal_map_length, 1e-4, 1.0);
        a2 += 2.0 * (1.0 - l) / l;
    }
    return sqrt(min(a2, 1.0));
}
