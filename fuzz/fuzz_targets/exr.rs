//! EXR: the input written to a file and read with `scenes::layered::LayeredImage::read_exr`,
//! the reader behind `verity diff`, textures and environment maps.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = verity_fuzz::scratch_file("fuzz.exr", data);
    let _ = scenes::layered::LayeredImage::read_exr(&path);
});
