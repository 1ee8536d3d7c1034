//! Study: the input written as a study file in the scratch copy of `scenes/studies/` (so
//! `scene = "scenes/…"` resolves) and loaded with `compare::study::load`, which checks the
//! whole file and loads the scene at every scene-sweep point.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = verity_fuzz::scratch_file("studies/fuzz-study.toml", data);
    let _ = compare::study::load(&path);
});
