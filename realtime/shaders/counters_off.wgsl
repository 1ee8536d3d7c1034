// counters_off.wgsl — the timed variant: cost counters are not written (see counters_on.wgsl).
//
// Technique: none. Failure mode: none. Inputs: none.

// The G-buffer's object-id field: shape index + 1 (0 is the background).
fn gbuffer_tag(shape: u32) -> f32 {
    return f32(shape + 1u);
}

// The shape index of a G-buffer object-id field.
fn gbuffer_shape(tag: f32) -> u32 {
    return u32(tag) - 1u;
}

fn flush_counters(row: u32) {}
