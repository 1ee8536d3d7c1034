//! Frame cost of the distance impostors against the plain cube map: the mirror ball of
//! scenes/studies/scenes/distance-room.toml seen from 1.3 m so that it fills the frame
//! (256², no supersampling), for the lecture slides' comparison of an environment map, a
//! distance impostor and one more iteration, then more iterations, the search, and double
//! refraction through the glass ball of distance-room-glass.toml, and layered distance maps
//! (whose extra cost is mostly the map build: one depth-peeled capture per further layer).
//!
//! Run: `cargo bench -p realtime --bench distance_impostor` (a plain `main`, `harness =
//! false`). Each case renders once to compile its pipelines; then `ROUNDS` rounds over every
//! case in turn, each a render of 2 warm-up and 10 timed frames whose median frame time (GPU
//! timestamps where the adapter has them) is kept; the figure is the median of the rounds.
//! Texel fetches per pixel and the map's build time (`environment_map_build_ms`) come from
//! the counting frame. The adapter is named in the output;
//! on a CPU driver (lavapipe) these are CPU-rasteriser times, not GPU speed. Lavapipe's
//! process memory grows by about 15 MB per 256² frame (BENCHMARKS.md), which bounds the
//! frames one run can afford.

use std::path::Path;

use glam::Vec3;
use realtime::{Method, RasterSettings, Renderer};
use scenes::Camera;

const ROUNDS: usize = 3;
const SIZE: u32 = 256;

fn scene(file: &str) -> scenes::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/studies/scenes")
        .join(file);
    let text = std::fs::read_to_string(&path).expect("the study scene exists");
    let mut scene = scenes::toml::load_str(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    scene.camera = Camera::look_at(Vec3::new(0.0, 0.1, 1.3), Vec3::ZERO, Vec3::Y, 45.0);
    scene
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let renderer = Renderer::new().unwrap_or_else(|e| panic!("a GPU adapter is needed: {e}"));
    println!("adapter: {}", renderer.gpu().adapter_name());
    let mirror = scene("distance-room.toml");
    let glass = scene("distance-room-glass.toml");
    // (ball, method, its parameters as `key=value` pairs separated by commas)
    let cases = [
        ("mirror", "envmap_cube", ""),
        ("mirror", "distance_impostor", "iterations=1"),
        ("mirror", "distance_impostor", "iterations=2"),
        ("mirror", "distance_impostor", "iterations=4"),
        ("mirror", "distance_impostor", "iterations=8"),
        ("mirror", "distance_search", "linear_steps=8"),
        ("mirror", "distance_search", "linear_steps=16"),
        ("mirror", "distance_search", "linear_steps=64"),
        ("mirror", "distance_search", "linear_steps=64,layers=2"),
        ("mirror", "distance_search", "linear_steps=64,layers=3"),
        ("glass", "envmap_cube", ""),
        ("glass", "distance_impostor", "iterations=2,double_refraction=on"),
        ("glass", "distance_search", "double_refraction=on"),
    ];
    let scene_of = |ball: &str| if ball == "glass" { &glass } else { &mirror };
    let settings: Vec<RasterSettings> = cases
        .iter()
        .map(|(_, name, extra)| {
            let params: Vec<(String, String)> = ["n=1", "env_n=0", "size=128"]
                .into_iter()
                .chain(extra.split(',').filter(|kv| !kv.is_empty()))
                .map(|kv| {
                    let (k, v) = kv.split_once('=').expect("key=value");
                    (k.to_string(), v.to_string())
                })
                .collect();
            let method = Method::parse(name, &params).unwrap_or_else(|e| panic!("{e}"));
            RasterSettings::new(SIZE, SIZE).method(method).frames(2, 10)
        })
        .collect();
    let mut fetches = Vec::new();
    let mut build_ms = Vec::new();
    for ((ball, _, _), s) in cases.iter().zip(&settings) {
        let out = renderer
            .render(scene_of(ball), &s.clone().counters(true))
            .expect("render");
        build_ms.push(
            out.image
                .attribute("environment_map_build_ms")
                .and_then(|v| v.parse::<f64>().ok())
                .unwrap_or(f64::NAN),
        );
        fetches.push(out.counters.map_or(f64::NAN, |c| c.texel_fetches_per_pixel));
    }
    let mut times = vec![Vec::new(); cases.len()];
    for _ in 0..ROUNDS {
        for (i, ((ball, _, _), s)) in cases.iter().zip(&settings).enumerate() {
            let out = renderer
                .render(scene_of(ball), &s.clone().counters(false))
                .expect("render");
            times[i].push(out.timing.frame_ms());
        }
    }
    println!(
        "| ball | method | frame ms (median of {ROUNDS} rounds; min–max) | texel fetches per pixel | map build ms |"
    );
    println!("|---|---|---|---|---|");
    for (i, (ball, _, _)) in cases.iter().enumerate() {
        let lo = times[i].iter().copied().fold(f64::INFINITY, f64::min);
        let hi = times[i].iter().copied().fold(0.0, f64::max);
        let mid = median(&mut times[i]);
        println!(
            "| {ball} | `{}` | {mid:.1} ({lo:.1}–{hi:.1}) | {:.1} | {:.0} |",
            settings[i].method, fetches[i], build_ms[i]
        );
    }
}
