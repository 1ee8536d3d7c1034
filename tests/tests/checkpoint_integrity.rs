//! Checkpoint integrity: a damaged, truncated, old-format or impossible checkpoint is refused
//! with a message naming the file, the reason and what to do, never resumed into an image
//! (the intact case, resumed bit for bit, is in determinism.rs).

use std::path::{Path, PathBuf};
use std::time::Duration;

use glam::Vec3;
use oracle::{CheckpointConfig, RenderError, RenderJob, StopRule};
use scenes::*;
use verity_tests::*;

/// An 8×8 floor under a square lamp.
fn tiny_scene() -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 1.0, 4.0), Vec3::ZERO, Vec3::Y, 40.0);
    let mut scene = empty_scene(camera, 8, 8);
    add_shape(
        &mut scene,
        "floor",
        square(Vec3::new(0.0, -1.0, 0.0), 10.0, Vec3::Y),
        diffuse(Vec3::splat(0.6)),
    );
    let light = add_shape(
        &mut scene,
        "lamp",
        square(Vec3::new(0.0, 2.5, 0.0), 1.0, Vec3::NEG_Y),
        diffuse(Vec3::ZERO),
    );
    scene.shapes[light].emission = Some(Emission {
        radiance: TexRgb::Constant(Vec3::splat(5.0)),
        two_sided: false,
    });
    scene
}

fn job<'a>(scene: &'a Scene, path: &Path) -> RenderJob<'a> {
    RenderJob {
        light_visibility: true,
        scene,
        settings: settings(IntegratorKind::Path, 4, 3),
        stop: StopRule {
            spp: 4,
            time: None,
            target_rel_err: None,
        },
        checkpoint: Some(CheckpointConfig {
            path: path.to_path_buf(),
            interval: Duration::ZERO,
            resume: true,
        }),
    }
}

fn checkpoint_path(name: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("verity-ckpt-{name}-{}.ckpt", std::process::id()));
    let _ = std::fs::remove_file(&path);
    path
}

/// Writes a checkpoint of `job` at 1 spp (interrupted after its first pass, always 1 spp).
fn write_checkpoint(job: &RenderJob) {
    match oracle::render(job, &mut |p| p.spp_done < 1) {
        Err(RenderError::Interrupted {
            spp: 1,
            checkpointed: true,
        }) => {}
        Err(e) => panic!("unexpected error: {e}"),
        Ok(r) => panic!("the render was not interrupted ({} spp)", r.spp),
    }
}

/// Resumes `job` from its checkpoint and returns the refusal's message.
fn refusal(job: &RenderJob, what: &str) -> String {
    let path = &job.checkpoint.as_ref().expect("checkpointed job").path;
    match oracle::render(job, &mut |_| true) {
        Ok(_) => panic!("{what}: the checkpoint was resumed"),
        Err(e @ RenderError::Checkpoint { .. }) => {
            let message = e.to_string();
            assert!(
                message.starts_with(&format!("checkpoint {}: ", path.display())),
                "{what}: the message must name the file: {message}"
            );
            assert!(
                message.ends_with("; delete it or drop --resume"),
                "{what}: the message must say what to do: {message}"
            );
            assert!(!message.contains('\n'), "{what}: one line: {message}");
            message
        }
        Err(e) => panic!("{what}: unexpected error {e}"),
    }
}

#[test]
fn checkpoint_damaged_bytes_and_truncations_are_refused() {
    let scene = tiny_scene();
    let path = checkpoint_path("damaged");
    let job = job(&scene, &path);
    write_checkpoint(&job);
    let intact = std::fs::read(&path).unwrap();
    let len = intact.len();
    // Header fields: fingerprint at 8, width 16, height 20, lights 24, spp 28, paths 32,
    // rays 40, non-finite 48, seconds 56; the accumulators from 64; the SHA-256 last.
    let flips: [(&str, &[usize]); 9] = [
        ("fingerprint", &[8]),
        ("fingerprint, 3 bytes", &[9, 12, 15]),
        ("height", &[20]),
        ("spp", &[28]),
        ("rays and seconds", &[41, 60]),
        ("first accumulator", &[64 + 3]),
        (
            "body, 10 bytes",
            &[100, 200, 300, 400, 500, 600, 700, 800, 900, 1000],
        ),
        ("last accumulator", &[len - 33]),
        ("checksum", &[len - 1]),
    ];
    for (what, at) in flips {
        let mut bytes = intact.clone();
        for &o in at {
            bytes[o] ^= 0x5a;
        }
        std::fs::write(&path, &bytes).unwrap();
        let message = refusal(&job, what);
        assert!(
            message
                .contains("is corrupt: the SHA-256 of its contents does not match the checksum it carries"),
            "{what}: {message}"
        );
    }
    for keep in [len - 1, len - 32, len / 2, 64, 9] {
        std::fs::write(&path, &intact[..keep]).unwrap();
        let message = refusal(&job, &format!("truncated to {keep} bytes"));
        assert!(
            message.contains(&format!(
                "holds {keep} bytes where this job's checkpoint holds {len}"
            )) && message.contains("truncated"),
            "truncated to {keep}: {message}"
        );
    }
    std::fs::write(&path, [&intact[..], b"x"].concat()).unwrap();
    let message = refusal(&job, "one byte appended");
    assert!(
        message.contains(&format!("holds more than {len} bytes")),
        "{message}"
    );
    let mut bad_magic = intact.clone();
    bad_magic[0] ^= 0x5a;
    std::fs::write(&path, &bad_magic).unwrap();
    let message = refusal(&job, "magic");
    assert!(
        message.contains("is not a Verity checkpoint (bad magic)"),
        "{message}"
    );

    // The intact file still resumes (to 4 spp).
    std::fs::write(&path, &intact).unwrap();
    let resumed = oracle::render(&job, &mut |_| true).expect("intact checkpoint");
    assert_eq!(resumed.spp, 4);
}

#[test]
fn checkpoint_of_format_1_is_refused_as_old() {
    let scene = tiny_scene();
    let path = checkpoint_path("format1");
    let job = job(&scene, &path);
    write_checkpoint(&job);
    // Format 1 was format 2 without the trailing checksum, under the magic VRTYCKP1.
    let bytes = std::fs::read(&path).unwrap();
    let old = [&b"VRTYCKP1"[..], &bytes[8..bytes.len() - 32]].concat();
    std::fs::write(&path, old).unwrap();
    let message = refusal(&job, "format 1");
    assert!(
        message.contains("is in checkpoint format `VRTYCKP1`, not this version's `VRTYCKP3`")
            && message.contains("cannot be resumed"),
        "{message}"
    );
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn checkpoint_with_impossible_values_is_refused() {
    let scene = tiny_scene();
    let path = checkpoint_path("impossible");
    let job = job(&scene, &path);
    write_checkpoint(&job);
    let fingerprint = oracle::checkpoint::fingerprint(&job);
    let like = oracle::film::Film::new(8, 8, scene.light_names().len(), 1);
    let state = oracle::checkpoint::load(&path, fingerprint, &like).expect("intact checkpoint");
    assert_eq!((state.film.spp, state.film.paths), (1, 64));
    // Pixel (0, 0) starts the data; its slab (oracle/src/film.rs `PixelStats`): sample
    // count at 0, coverage at 13, then per replicate its count and R, G, B sums (replicate 0
    // at 14..18, which the one sample of this 1-spp render went to).
    type Edit = fn(&mut oracle::film::Film, &mut f64);
    let cases: [(&str, Edit, &str); 11] = [
        (
            "NaN replicate sum",
            |f, _| f.data[15] = f64::NAN,
            "pixel (0, 0): an accumulator is NaN",
        ),
        (
            "infinite replicate sum",
            |f, _| f.data[16] = f64::INFINITY,
            "pixel (0, 0): an accumulator is inf",
        ),
        (
            "replicate count above the samples it was dealt",
            |f, _| f.data[14] = 2.0,
            "replicate 0's sample count 2 is not a whole number in 0..=1",
        ),
        (
            "a sample in a replicate that was dealt none",
            |f, _| f.data[18] = 1.0,
            "replicate 1's sample count 1 is not a whole number in 0..=0",
        ),
        (
            "replicates that miss the pixel's sample",
            |f, _| f.data[14] = 0.0,
            "the replicates hold 0 samples, the pixel 1",
        ),
        (
            "count above spp",
            |f, _| f.data[0] = 3.0,
            "sample count 3 is not a whole number in 0..=1",
        ),
        (
            "fractional count",
            |f, _| f.data[0] = 0.5,
            "sample count 0.5 is not a whole number in 0..=1",
        ),
        (
            "coverage above count",
            |f, _| f.data[13] = 5.0,
            "coverage count 5 is not a whole number in 0..=",
        ),
        (
            "spp without the paths",
            |f, _| f.spp = 3,
            "64 camera paths for 3 spp over 64 pixels",
        ),
        (
            "dropped samples not missing",
            |f, _| f.nonfinite = 1,
            "the pixels miss 0 samples but 1 were dropped as non-finite",
        ),
        ("NaN render time", |_, s| *s = f64::NAN, "render time NaN s"),
    ];
    for (what, edit, expected) in cases {
        let (mut film, mut seconds) = (state.film.clone(), state.seconds);
        edit(&mut film, &mut seconds);
        oracle::checkpoint::save(&path, fingerprint, &film, seconds).unwrap();
        let message = refusal(&job, what);
        assert!(
            message.contains("holds values no render produces (") && message.contains(expected),
            "{what}: expected `{expected}` in {message}"
        );
    }
    std::fs::remove_file(&path).unwrap();
}
