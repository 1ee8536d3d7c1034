//! glTF/glb: the input written to a file in the scratch copy of `scenes/assets/` (`.glb` when it
//! starts with the GLB magic, glTF 2.0 §4.4.3, else `.gltf`) and loaded with
//! `scenes::gltf::load`, which reads its buffers and images.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let name = if data.starts_with(b"glTF") {
        "assets/fuzz.glb"
    } else {
        "assets/fuzz.gltf"
    };
    let path = verity_fuzz::scratch_file(name, data);
    let _ = scenes::gltf::load(&path);
});
