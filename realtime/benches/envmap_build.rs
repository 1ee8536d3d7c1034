//! Environment-map build time: the six-view capture and the filtering passes of
//! `technique/envmap/build.rs` (box mips, prefiltered levels, irradiance cube or SH9, warps, BRDF
//! table), for each parameterization at sides 64–512, for a glossy (GGX, 64 samples per
//! prefiltered texel) and a diffuse (irradiance cube) ball under the Venice sunset.
//!
//! Run: `cargo bench -p realtime --bench envmap_build` (a plain `main`, `harness = false`).
//! Each case renders once to compile its pipelines, then `REPEATS` more times; the figure is
//! the best build time of those (the header's `environment_map_build_ms`: wall time from the
//! start of the capture to the end of the filtering, submit-and-wait). The adapter is named
//! in the output; on a CPU driver (lavapipe) these are CPU-rasteriser times, not GPU speed.

use std::path::Path;

use realtime::{Method, RasterSettings, Renderer};

const REPEATS: usize = 3;

fn scene(material: &str) -> scenes::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/studies/scenes/envmap-ball.toml");
    let text = std::fs::read_to_string(&path).expect("the study scene exists");
    let text = text.replace("material = \"mirror\"\n", &format!("material = \"{material}\"\n"));
    scenes::toml::load_str(&text, &path).unwrap_or_else(|e| panic!("{e}"))
}

fn main() {
    let renderer = Renderer::new().unwrap_or_else(|e| panic!("a GPU adapter is needed: {e}"));
    println!("adapter: {}", renderer.gpu().adapter_name());
    println!("| method | material | side | build ms (best of {REPEATS}) |");
    println!("|---|---|---|---|");
    for (material, label) in [
        ("glossy", "GGX, 64 samples"),
        ("white", "diffuse, irradiance cube"),
    ] {
        let scene = scene(material);
        for name in ["envmap_cube", "envmap_sphere", "envmap_paraboloid"] {
            for size in [64, 128, 256, 512] {
                let params = [("size".to_string(), size.to_string())];
                let method = Method::parse(name, &params).unwrap_or_else(|e| panic!("{e}"));
                let settings = RasterSettings::new(32, 32).method(method).frames(0, 1);
                let mut best = f64::INFINITY;
                for i in 0..=REPEATS {
                    let out = renderer
                        .render(&scene, &settings)
                        .unwrap_or_else(|e| panic!("{name} {size}: {e}"));
                    let ms: f64 = out
                        .image
                        .attribute("environment_map_build_ms")
                        .and_then(|v| v.parse().ok())
                        .unwrap_or(f64::NAN);
                    if i > 0 {
                        best = best.min(ms);
                    }
                }
                println!("| `{name}` | {label} | {size} | {best:.1} |");
            }
        }
    }
}
