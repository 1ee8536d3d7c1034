// ssao/lighting.wgsl — what the SSAO family adds to the shading module: its block of the frame
// uniform, read by the deferred lighting pass (passes.wgsl), which multiplies the environment's
// light by 1 − the obscurance the family's passes (technique/ssao/passes.rs) left in group 1.

// The family's block of the frame uniform (AmbientOcclusionUniforms in ssao/mod.rs).
struct AmbientOcclusionUniforms {
    // What the lighting writes: 0 the shaded image, 1 the AO factor (an SSAO method's
    // `output = ao`).
    output: u32,
}
