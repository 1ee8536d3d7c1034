//! Cone-map precomputation time: `realtime::technique::detail::cone_map` (conservative, exact; relaxed, 64
//! directions on top of the conservative pass) on the heightfields the surface-detail studies
//! use, heights scaled by 0.03 m.
//!
//! Run: `cargo bench -p realtime --bench cone_map` (a plain `main`, `harness = false`);
//! `CONE_MAP_TIMING=bumps768,bricks512,bumps1024` and `CONE_MAP_KIND=conservative|relaxed`
//! pick a subset. Each case is built `REPEATS` times; the figure is the best wall time, on
//! rayon's default pool (the thread count is printed).

use realtime::technique::detail::cone_map::{cone_map, ConeKind};
use scenes::displacement::Procedural;
use scenes::WrapMode;

const REPEATS: usize = 3;
/// Height scale of the studies' patches, metres per unit of h.
const HEIGHT_SCALE: f32 = 0.03;

/// The procedural heightfield sampled at n², scaled to metres.
fn heights(p: Procedural, n: u32) -> Vec<f32> {
    let t = p.texture(n, [WrapMode::Repeat; 2]);
    (0..i64::from(n))
        .flat_map(|j| (0..i64::from(n)).map(move |i| (j, i)))
        .map(|(j, i)| t.texel(i, j).x * HEIGHT_SCALE)
        .collect()
}

fn main() {
    let only = std::env::var("CONE_MAP_TIMING").unwrap_or_default();
    let kind_only = std::env::var("CONE_MAP_KIND").unwrap_or_default();
    let inputs = [
        (
            "bumps768",
            Procedural::Bumps { tiles: 16 },
            768,
            [WrapMode::Clamp; 2],
        ),
        (
            "bricks512",
            Procedural::Bricks { rows: 12 },
            512,
            [WrapMode::Repeat; 2],
        ),
        (
            "bumps1024",
            Procedural::Bumps { tiles: 16 },
            1024,
            [WrapMode::Clamp; 2],
        ),
    ];
    println!("rayon threads: {}", rayon::current_num_threads());
    println!("| heightfield | wrap | kind | best of {REPEATS} (s) | median cone ratio |");
    println!("|---|---|---|---|---|");
    for (name, p, n, wrap) in inputs {
        if !only.is_empty() && !only.split(',').any(|o| o == name) {
            continue;
        }
        let w = heights(p, n);
        for kind in [ConeKind::Conservative, ConeKind::Relaxed] {
            if !kind_only.is_empty() && !format!("{kind:?}").eq_ignore_ascii_case(&kind_only) {
                continue;
            }
            let mut best = f64::INFINITY;
            let mut cones = Vec::new();
            for _ in 0..REPEATS {
                let t = std::time::Instant::now();
                cones = cone_map(&w, n, n, wrap, kind);
                best = best.min(t.elapsed().as_secs_f64());
            }
            cones.sort_by(f32::total_cmp);
            println!(
                "| {name} | {:?} | {kind:?} | {best:.2} | {} |",
                wrap[0],
                cones[cones.len() / 2]
            );
        }
    }
}
