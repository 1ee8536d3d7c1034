//! Scene TOML: `scenes::toml::load_str` on the input as UTF-8, as if it were a scene file in
//! the scratch copy of `scenes/` (so `assets/…` references resolve). Any error is fine; a
//! panic, an abort or a hang is a finding.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let root = verity_fuzz::setup();
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = scenes::toml::load_str(text, &root.join("fuzz-scene.toml"));
    }
});
