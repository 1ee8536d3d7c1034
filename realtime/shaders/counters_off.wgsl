// counters_off.wgsl — the timed variant: cost counters are not written (see counters_on.wgsl).
//
// Technique: none. Failure mode: none. Inputs: none.

fn count_surface_fetches(s: Shape) {}

fn flush_counters(row: u32) {}
