//! `compare/python/trace_rays.py`, the Mitsuba side of BENCHMARKS.md's "Traversal alone"
//! table, runs on an exported built-in scene, prints its figures, and traces the rays the
//! oracle's `traversal` bench traces: its hit and blocked fractions on the Cornell box agree
//! with the oracle's over the same distributions (origins uniform in the scene's bounds,
//! uniform directions; shadow rays between two such points) within sampling error. Mitsuba
//! missing is a failure that says what to install, never a skip.

use std::path::Path;
use std::process::Command;

use compare::mitsuba::runner::{Mitsuba, LIBLLVM_PATH};
use glam::{Vec2, Vec3};
use oracle::geometry::{Accel, Ray};
use oracle::sampling::square_to_uniform_sphere;
use scenes::random::SplitMix64;

/// Rays of each kind.
const RAYS: usize = 1 << 14;

/// A number printed as `key=value` in `out`.
fn figure(out: &str, key: &str) -> f64 {
    out.split_whitespace()
        .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("trace_rays.py printed no `{key}`:\n{out}"))
}

#[test]
fn trace_rays_traces_the_oracle_benchs_ray_distributions() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let scene_path = root.join("scenes/cornell-box.toml");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("trace-rays-cornell");
    let export = Command::new(env!("CARGO_BIN_EXE_verity"))
        .arg("export-mitsuba")
        .arg(&scene_path)
        .args(["--resolution", "64x64", "--out"])
        .arg(&out)
        .output()
        .expect("verity runs");
    assert!(
        export.status.success(),
        "{}",
        String::from_utf8_lossy(&export.stderr)
    );
    let mitsuba = Mitsuba::locate().unwrap_or_else(|e| panic!("{e}"));
    let mut run = Command::new(&mitsuba.python);
    run.arg(root.join("compare/python/trace_rays.py"))
        .arg(out.join("scene.xml"))
        .args(["--rays", &RAYS.to_string(), "--threads", "1"]);
    // Debian's libLLVM unless the user names another, as `verity bench` does.
    if std::env::var_os("DRJIT_LIBLLVM_PATH").is_none() {
        run.env("DRJIT_LIBLLVM_PATH", LIBLLVM_PATH);
    }
    let run = run.output().expect("the venv's python runs");
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for key in ["closest_mrays_s", "preliminary_mrays_s", "shadow_mrays_s"] {
        assert!(figure(&text, key) > 0.0, "{key}:\n{text}");
    }
    assert_eq!(figure(&text, "threads"), 1.0, "{text}");

    // The oracle over the same distributions (its own random numbers).
    let scene = scenes::load(&scene_path).unwrap();
    let accel = Accel::build(&scene).unwrap();
    let (lo, hi) = scene.bounds();
    let mut rng = SplitMix64(3);
    let mut in_box = || lo + (hi - lo) * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
    let (mut hits, mut blocked) = (0usize, 0usize);
    let mut dirs = SplitMix64(4);
    for _ in 0..RAYS {
        let d = square_to_uniform_sphere(Vec2::new(dirs.next_f32(), dirs.next_f32()));
        hits += usize::from(accel.intersect(&Ray::new(in_box(), d), f32::INFINITY).is_some());
        let (a, b) = (in_box(), in_box());
        blocked += usize::from(accel.occluded(&Ray::new(a, (b - a).normalize()), (b - a).length()));
    }
    let n = RAYS as f64;
    for (name, ours, key) in [
        ("hit", hits, "hit_fraction"),
        ("blocked", blocked, "blocked_fraction"),
    ] {
        let (p, theirs) = (ours as f64 / n, figure(&text, key));
        // Two independent binomial fractions: σ of the difference √(2p(1−p)/n), 5σ allowed.
        let tol = 5.0 * (2.0 * p * (1.0 - p) / n).sqrt();
        assert!(
            (p - theirs).abs() < tol,
            "{name} fraction: oracle {p:.4}, Mitsuba {theirs:.4} (±{tol:.4}):\n{text}"
        );
    }
}
