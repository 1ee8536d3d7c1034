//! The reproducers of issue 19 ("Hostile input"), minimised: what each runs, the exit status
//! it must give and the substrings its one `error:` line must contain (file, line where the
//! file has lines, field, reason). The files named are in this folder; `make` lists what the
//! test generates (binary files, and text too large to read: `corpus.rs`). Every hostile
//! run is bounded by `--memory-limit 1G` unless the case sets its own, an address-space cap
//! and a timeout (tests/hostile_support/process.rs).
//!
//! Exit statuses (compare/README.md): 2 bad input; `verity diff`'s 4 a file cannot be read,
//! 2 a failed comparison; 1 for a refused checkpoint (`--resume`: "the work failed", as the
//! README documents for a mismatched checkpoint).

use crate::hostile_support::corpus::{Case, Corrupt, Make, BASE, CHECKPOINTED};

/// `verity render FILE` at 8×8, 1 spp, no checkpoints, quiet.
macro_rules! render {
    ($file:expr $(, $extra:expr)*) => {
        &["render", $file, "--resolution", "8x8", "--spp", "1", "--checkpoint-every", "0", "-q", "--out", "out/x.exr" $(, $extra)*]
    };
}

/// `verity report FILE --dry-run`, quiet, writing nowhere but the case folder.
macro_rules! dry_run {
    ($file:expr) => {
        &[
            "report",
            $file,
            "--dry-run",
            "-q",
            "--out",
            "{DIR}/report",
            "--cache",
            "{DIR}/cache",
        ]
    };
}

/// A glTF buffer whose `uri` is `$uri`: refused with the field and, for a path outside the
/// asset's folder, the flag that would allow it.
macro_rules! buffer_uri {
    ($name:expr, $uri:expr, $reason:expr) => {
        Case {
            name: $name,
            files: &["buffer-uri.gltf"],
            make: &[Make::Fifo],
            subst: &[("@URI@", $uri)],
            args: render!("buffer-uri.gltf"),
            error: &["buffer-uri.gltf", "buffers[0].uri", $reason],
            ..BASE
        }
    };
}

/// A shape or light name in a TOML scene that is not letters, digits, `_` and `-` (written as
/// TOML source: `\n` and `\u202E` are escapes); the message echoes it escaped.
macro_rules! bad_name {
    ($name:expr, $file:expr, $line:expr, $value:expr) => {
        Case {
            name: $name,
            files: &[$file],
            subst: &[("@NAME@", $value)],
            args: render!($file),
            error: &[$line, ".name`"],
            // Echoed raw, U+202E turns the rest of the terminal line around.
            absent: &["\u{202E}"],
            ..BASE
        }
    };
}

/// A SHA-256 hex digest no study has.
macro_rules! zeros {
    () => {
        "0000000000000000000000000000000000000000000000000000000000000000"
    };
}

/// The `outputs` of the ground truth [`zeros!`] in the cache folder `cache`, as JSON list items.
macro_rules! cached_zeros {
    () => {
        concat!(
            "\"cache/",
            zeros!(),
            ".exr\", \"cache/",
            zeros!(),
            ".exr.sha256\""
        )
    };
}

/// `verity run-job plan.json ground_truth` on a plan of study-control.toml whose `cache`,
/// `out`, ground-truth `hash` and `outputs` (JSON list items) are given; `study = …` first
/// names another study file.
macro_rules! plan {
    (study = $study:expr, $name:expr, $cache:expr, $out:expr, $hash:expr, $outputs:expr, $error:expr) => {
        Case {
            name: $name,
            files: &["plan.json", "study-control.toml"],
            builtins: &["soft-shadow.toml"],
            subst: &[
                ("@STUDY@", $study),
                ("@CACHE@", $cache),
                ("@OUT@", $out),
                ("@HASH@", $hash),
                ("@OUTPUTS@", $outputs),
            ],
            args: &["run-job", "plan.json", "ground_truth", "-q"],
            error: $error,
            ..BASE
        }
    };
    ($name:expr, $cache:expr, $out:expr, $hash:expr, $outputs:expr, $error:expr) => {
        plan!(
            study = "study-control.toml",
            $name,
            $cache,
            $out,
            $hash,
            $outputs,
            $error
        )
    };
}

/// The corrupted checkpoint cases: `--resume` must refuse them (exit 1, naming the file).
macro_rules! checkpoint {
    ($name:expr, $corrupt:expr) => {
        Case {
            name: $name,
            builtins: &["cornell-box.toml"],
            make: &[Make::Checkpoint($corrupt)],
            args: &[
                "render",
                "cornell-box.toml",
                "--resolution",
                "2x2",
                "-q",
                "--out",
                "k.exr",
                "--time",
                "0.001",
                "--resume",
            ],
            status: 1,
            error: &["k.exr.checkpoint"],
            ..BASE
        }
    };
}

/// Every reproducer.
pub const CASES: &[Case] = &[
    // --- Controls: valid inputs give exit 0 (the harness would pass anything otherwise).
    Case {
        name: "control-scene",
        files: &["control.toml"],
        args: render!("control.toml"),
        status: 0,
        stdout: &["rendered"],
        ..BASE
    },
    Case {
        name: "control-study",
        files: &["study-control.toml"],
        builtins: &["soft-shadow.toml"],
        args: dry_run!("study-control.toml"),
        status: 0,
        ..BASE
    },
    Case {
        name: "control-checkpoint-resumes",
        builtins: &["cornell-box.toml"],
        make: &[Make::Checkpoint(Corrupt::Intact)],
        args: &[
            "render",
            "cornell-box.toml",
            "--resolution",
            "2x2",
            "-q",
            "--out",
            "k.exr",
            "--time",
            "0.001",
            "--resume",
        ],
        status: 0,
        ..BASE
    },
    // --- A 33 KB EXR whose header declares 65536×65536 pixels (48 GiB of float RGB).
    Case {
        name: "exr-65536-diff",
        make: &[Make::HugeExr],
        args: &["diff", "big.exr", "big.exr"],
        status: 4,
        error: &["big.exr", "memory limit"],
        ..BASE
    },
    Case {
        name: "exr-65536-diff-mask",
        make: &[Make::HugeExr, Make::Exr4x4("a.exr", 0.5)],
        args: &["diff", "a.exr", "a.exr", "--mask", "file:big.exr"],
        error: &["big.exr", "memory limit"],
        ..BASE
    },
    Case {
        name: "exr-65536-environment",
        files: &["environment-big.toml"],
        make: &[Make::HugeExr],
        args: render!("environment-big.toml"),
        error: &[
            "environment-big.toml:24: field `environment.file`",
            "big.exr",
            "memory limit",
        ],
        ..BASE
    },
    Case {
        name: "exr-65536-texture",
        files: &["texture-big.toml"],
        make: &[Make::HugeExr],
        args: render!("texture-big.toml"),
        error: &[
            "texture-big.toml:19: field `material \"t\".albedo",
            "big.exr",
            "memory limit",
        ],
        ..BASE
    },
    Case {
        name: "exr-65536-height-map",
        files: &["displacement-big.toml"],
        make: &[Make::HugeExr],
        args: render!("displacement-big.toml"),
        error: &[
            "displacement-big.toml:23: field `shape \"patch\".displacement",
            "big.exr",
            "memory limit",
        ],
        ..BASE
    },
    // --- Films over the budget (1 GiB here, so that the answer is the same on any machine).
    Case {
        name: "resolution-16384-flag",
        files: &["control.toml"],
        args: &[
            "render",
            "control.toml",
            "--resolution",
            "16384x16384",
            "--spp",
            "1",
            "--checkpoint-every",
            "0",
            "-q",
            "--out",
            "out/x.exr",
        ],
        error: &["--resolution", "16384", "memory limit"],
        ..BASE
    },
    Case {
        name: "resolution-16384-film",
        files: &["film-16384.toml"],
        args: &[
            "render",
            "film-16384.toml",
            "--spp",
            "1",
            "--checkpoint-every",
            "0",
            "-q",
            "--out",
            "out/x.exr",
        ],
        error: &["film-16384.toml", "16384", "memory limit"],
        ..BASE
    },
    // --- Sixteen displacements that fit one by one but not together.
    Case {
        name: "displacements-16-together",
        files: &["displacements-16.toml"],
        args: render!("displacements-16.toml", "--memory-limit", "100M"),
        error: &[
            "displacements-16.toml",
            "displacement",
            "memory limit",
            "already loaded",
        ],
        ..BASE
    },
    // --- Study sizes: 64 × 1000 × 64 variants; 1000 scene-sweep values.
    Case {
        name: "study-grid-64x1000x64",
        builtins: &["soft-shadow.toml"],
        make: &[Make::GridStudy],
        args: dry_run!("grid.toml"),
        error: &["grid.toml", "method[0].sweep"],
        ..BASE
    },
    Case {
        name: "study-scene-sweep-1000",
        builtins: &["soft-shadow.toml"],
        make: &[Make::SceneSweep1000],
        args: dry_run!("sweep.toml"),
        error: &["sweep.toml", "scene_sweep"],
        ..BASE
    },
    // --- Comparisons: a reference pixel of 1e20 (its square overflows f32) never yields NaN.
    Case {
        name: "diff-reference-1e20-fails",
        make: &[Make::Exr4x4("a.exr", 0.5), Make::Exr4x4("ref.exr", 1e20)],
        args: &[
            "diff", "ref.exr", "a.exr", "--metric", "relmse", "--metric", "mse", "--metric", "smape",
            "--metric", "psnr", "--fail", "1e-3",
        ],
        stdout: &["FAIL"],
        // A value column that is not finite would read `   inf` or `NaN`; PSNR's noise floor
        // of a noise-free reference is `floor inf)`, its exact value.
        absent: &["NaN", "   inf", "-inf"],
        ..BASE
    },
    Case {
        name: "diff-reference-1e20-figures",
        make: &[Make::Exr4x4("a.exr", 0.5), Make::Exr4x4("ref.exr", 1e20)],
        args: &[
            "diff", "ref.exr", "a.exr", "--metric", "relmse", "--metric", "mse", "--metric", "ssim",
            "--metric", "flip_hdr",
        ],
        // Every figure finite; relMSE 1/16 fails the default bound (1e-3), as it should.
        status: 2,
        stdout: &[
            "relmse     6.250000e-2",
            "FAIL: relmse 6.250000e-2 is above the fail bound 1.000e-3 (default)",
        ],
        absent: &["NaN", "inf"],
        ..BASE
    },
    // --- Threshold flags that cannot mean anything.
    Case {
        name: "diff-fail-nan",
        make: &[Make::Exr4x4("a.exr", 0.5)],
        args: &["diff", "a.exr", "a.exr", "--fail", "nan"],
        error: &["--fail"],
        ..BASE
    },
    Case {
        name: "diff-fail-inf",
        make: &[Make::Exr4x4("a.exr", 0.5)],
        args: &["diff", "a.exr", "a.exr", "--fail", "inf"],
        error: &["--fail"],
        ..BASE
    },
    Case {
        name: "diff-warn-nan",
        make: &[Make::Exr4x4("a.exr", 0.5)],
        args: &["diff", "a.exr", "a.exr", "--warn", "nan"],
        error: &["--warn"],
        ..BASE
    },
    Case {
        name: "diff-fail-percent-nan",
        make: &[Make::Exr4x4("a.exr", 0.5)],
        args: &["diff", "a.exr", "a.exr", "--fail", "1", "--fail-percent", "nan"],
        error: &["--fail-percent"],
        ..BASE
    },
    Case {
        name: "diff-fail-percent-200",
        make: &[Make::Exr4x4("a.exr", 0.5)],
        args: &["diff", "a.exr", "a.exr", "--fail", "1", "--fail-percent", "200"],
        error: &["--fail-percent"],
        ..BASE
    },
    Case {
        name: "diff-fail-percent-negative",
        make: &[Make::Exr4x4("a.exr", 0.5)],
        args: &["diff", "a.exr", "a.exr", "--fail", "1", "--fail-percent=-1"],
        error: &["--fail-percent"],
        ..BASE
    },
    // --- glTF buffer URIs outside the asset's folder, and files that are not regular.
    buffer_uri!("gltf-uri-etc-passwd", "/etc/passwd", "--allow-paths-outside"),
    buffer_uri!(
        "gltf-uri-file-scheme",
        "file:///etc/passwd",
        "--allow-paths-outside"
    ),
    buffer_uri!(
        "gltf-uri-dotdot-4",
        "../../../../etc/passwd",
        "--allow-paths-outside"
    ),
    buffer_uri!(
        "gltf-uri-dotdot-to-root",
        "{UP}etc/passwd",
        "--allow-paths-outside"
    ),
    buffer_uri!(
        "gltf-uri-percent-dotdot",
        "%2e%2e/%2e%2e/etc/passwd",
        "--allow-paths-outside"
    ),
    buffer_uri!(
        "gltf-uri-percent-dotdot-to-root",
        "{UPENC}etc/passwd",
        "--allow-paths-outside"
    ),
    buffer_uri!(
        "gltf-uri-percent-slash",
        "%2Fetc%2Fpasswd",
        "--allow-paths-outside"
    ),
    buffer_uri!(
        "gltf-uri-proc-environ",
        "/proc/self/environ",
        "--allow-paths-outside"
    ),
    buffer_uri!("gltf-uri-dev-zero", "/dev/zero", "--allow-paths-outside"),
    buffer_uri!("gltf-uri-fifo", "fifo", "regular file"),
    buffer_uri!("gltf-uri-fifo-absolute", "{DIR}/fifo", "is an absolute path"),
    buffer_uri!("gltf-uri-directory", ".", "regular file"),
    Case {
        name: "gltf-uri-dev-zero-allowed-outside",
        files: &["buffer-uri.gltf"],
        subst: &[("@URI@", "/dev/zero")],
        args: render!("buffer-uri.gltf", "--allow-paths-outside"),
        error: &["buffer-uri.gltf", "buffers[0].uri", "regular file"],
        ..BASE
    },
    Case {
        name: "gltf-uri-proc-allowed-outside",
        files: &["buffer-uri.gltf"],
        subst: &[("@URI@", "/proc/self/environ")],
        args: render!("buffer-uri.gltf", "--allow-paths-outside"),
        error: &["buffer-uri.gltf", "buffers[0]"],
        ..BASE
    },
    Case {
        name: "gltf-image-uri-etc-passwd",
        files: &["image-uri.gltf"],
        subst: &[("@URI@", "/etc/passwd")],
        args: render!("image-uri.gltf"),
        error: &["image-uri.gltf", "images[0].uri", "--allow-paths-outside"],
        ..BASE
    },
    // --- issue 43: readers that opened a FIFO (blocking forever) or read a device unbounded.
    Case {
        name: "merge-part-fifo",
        make: &[Make::Fifo],
        args: &["merge", "fifo", "--out", "{DIR}/x.exr"],
        error: &["fifo", "regular file", "FIFO"],
        ..BASE
    },
    Case {
        name: "study-fifo",
        make: &[Make::Fifo],
        args: dry_run!("fifo"),
        error: &["fifo", "study file", "FIFO"],
        ..BASE
    },
    Case {
        name: "study-dev-zero",
        args: dry_run!("/dev/zero"),
        error: &["/dev/zero", "study file", "device"],
        ..BASE
    },
    Case {
        name: "run-job-plan-fifo",
        make: &[Make::Fifo],
        args: &["run-job", "fifo", "ground_truth"],
        error: &["fifo", "plan", "FIFO"],
        ..BASE
    },
    Case {
        name: "run-job-plan-dev-zero",
        args: &["run-job", "/dev/zero", "ground_truth"],
        error: &["/dev/zero", "plan", "device"],
        ..BASE
    },
    // A plan decides nothing about where files go (issue 43): its `cache` and `out` stay
    // below its folder or the current one, a ground truth's hash is a hex digest (it names
    // the cache files) and a job's outputs are the files it writes. The control passes the
    // check and fails later, on the hash its study does not have.
    plan!(
        "plan-cache-root",
        "/",
        "out",
        zeros!(),
        concat!("\"/", zeros!(), ".exr\", \"/", zeros!(), ".exr.sha256\""),
        &["plan.json", "field `cache` (/)", "outside"]
    ),
    plan!(
        "plan-out-up",
        "cache",
        "{UP}verity-hostile-out",
        zeros!(),
        cached_zeros!(),
        &["plan.json", "field `out`", "outside"]
    ),
    plan!(
        "plan-hash-path",
        "cache",
        "out",
        "../../../x",
        "",
        &["plan.json", "jobs[0].hash", "SHA-256"]
    ),
    plan!(
        "plan-outputs-elsewhere",
        "cache",
        "out",
        zeros!(),
        "\"/tmp/verity-hostile.exr\"",
        &["plan.json", "jobs[0].outputs", "not the files this job writes"]
    ),
    plan!(
        study = "/dev/zero",
        "plan-study-dev-zero",
        "cache",
        "out",
        zeros!(),
        cached_zeros!(),
        &["/dev/zero", "study file", "device"]
    ),
    plan!(
        "plan-control",
        "cache",
        "out",
        zeros!(),
        cached_zeros!(),
        &["no ground truth", "hash the plan recorded"]
    ),
    Case {
        name: "report-from-plan-fifo",
        make: &[Make::Fifo],
        args: &["report", "--from", "fifo"],
        error: &["fifo", "plan", "FIFO"],
        ..BASE
    },
    Case {
        name: "gltf-image-uri-fifo",
        files: &["image-uri.gltf"],
        make: &[Make::Fifo],
        subst: &[("@URI@", "fifo")],
        args: render!("image-uri.gltf"),
        error: &["image-uri.gltf", "images[0].uri", "regular file"],
        ..BASE
    },
    // --- glTF indices beyond u32 (they wrap modulo 2³²: 2³² reads as accessor 0, 2³² + 1 as the
    // valid index accessor 1). The message names the value as written.
    Case {
        name: "gltf-indices-2-32",
        files: &["index-2-32.gltf"],
        subst: &[("@MESH@", "0"), ("@INDICES@", "4294967296")],
        args: render!("index-2-32.gltf"),
        error: &["index-2-32.gltf", "meshes[0].primitives[0].indices", "4294967296"],
        ..BASE
    },
    Case {
        name: "gltf-indices-2-32-plus-1",
        files: &["index-2-32.gltf"],
        subst: &[("@MESH@", "0"), ("@INDICES@", "4294967297")],
        args: render!("index-2-32.gltf"),
        error: &["index-2-32.gltf", "meshes[0].primitives[0].indices", "4294967297"],
        ..BASE
    },
    Case {
        name: "gltf-node-mesh-2-32",
        files: &["index-2-32.gltf"],
        subst: &[("@MESH@", "4294967296"), ("@INDICES@", "1")],
        args: render!("index-2-32.gltf"),
        error: &["index-2-32.gltf", "nodes[0].mesh", "4294967296"],
        ..BASE
    },
    // --- 20,000 one-triangle primitives load (the timeout only detects a hang).
    Case {
        name: "gltf-20000-primitives",
        make: &[Make::Primitives(20_000)],
        args: render!("prims.gltf"),
        status: 0,
        stdout: &["rendered"],
        timeout_s: 120,
        ..BASE
    },
    // --- Values finite in f32 whose products are not: refused at load with file:line:field.
    Case {
        name: "sphere-center-1e30",
        files: &["sphere-center-1e30.toml"],
        args: render!("sphere-center-1e30.toml"),
        error: &["sphere-center-1e30.toml:20: field `shape \"ball\".center`"],
        ..BASE
    },
    Case {
        name: "sphere-radius-3e38",
        files: &["sphere-radius-3e38.toml"],
        args: render!("sphere-radius-3e38.toml"),
        error: &["sphere-radius-3e38.toml:21: field `shape \"ball\".radius`"],
        ..BASE
    },
    Case {
        name: "box-size-3e38",
        files: &["box-3e38.toml"],
        args: render!("box-3e38.toml"),
        error: &["box-3e38.toml:21: field `shape \"crate\".size`"],
        ..BASE
    },
    Case {
        name: "displacement-scale-3e38",
        files: &["displacement-scale-3e38.toml"],
        args: render!("displacement-scale-3e38.toml"),
        error: &["displacement-scale-3e38.toml:23: field `shape \"patch\".displacement.scale`"],
        ..BASE
    },
    Case {
        name: "gltf-light-intensity-3e38",
        files: &["light-intensity.gltf"],
        args: render!("light-intensity.gltf"),
        error: &[
            "light-intensity.gltf",
            "extensions.KHR_lights_punctual.lights[0].intensity",
        ],
        ..BASE
    },
    // --- Wrong diagnoses of overflow.
    Case {
        name: "camera-eye-3e38",
        files: &["eye-3e38.toml"],
        args: render!("eye-3e38.toml"),
        error: &["eye-3e38.toml:3: field `camera.eye`"],
        absent: &["parallel"],
        ..BASE
    },
    Case {
        name: "rectangle-half-u-3e38",
        files: &["half-u-3e38.toml"],
        args: render!("half-u-3e38.toml"),
        error: &["half-u-3e38.toml:21: field `shape \"panel\".half_u`"],
        absent: &["zero area"],
        ..BASE
    },
    // --- Study references checked before anything renders.
    Case {
        name: "study-visibility-of-nolight",
        files: &["visibility-nolight.toml"],
        builtins: &["soft-shadow.toml"],
        args: dry_run!("visibility-nolight.toml"),
        error: &[
            "visibility-nolight.toml:8: field `ground_truth.visibility_of`",
            "nolight",
        ],
        ..BASE
    },
    Case {
        name: "study-mask-objects-match-nothing",
        files: &["mask-objects.toml"],
        builtins: &["soft-shadow.toml"],
        subst: &[("@OBJECTS@", "[\"nothing\"]")],
        args: dry_run!("mask-objects.toml"),
        error: &["mask-objects.toml:21: field `mask[0].objects[0]`", "nothing"],
        ..BASE
    },
    Case {
        name: "study-mask-objects-empty",
        files: &["mask-objects.toml"],
        builtins: &["soft-shadow.toml"],
        subst: &[("@OBJECTS@", "[]")],
        args: dry_run!("mask-objects.toml"),
        error: &["mask-objects.toml:21: field `mask[0].objects`"],
        ..BASE
    },
    Case {
        name: "study-mask-duplicate-name",
        files: &["mask-duplicate.toml"],
        builtins: &["soft-shadow.toml"],
        args: dry_run!("mask-duplicate.toml"),
        error: &["mask-duplicate.toml:24: field `mask[1].name`"],
        ..BASE
    },
    Case {
        name: "study-metric-twice",
        files: &["metrics-duplicate.toml"],
        builtins: &["soft-shadow.toml"],
        args: dry_run!("metrics-duplicate.toml"),
        error: &["metrics-duplicate.toml:2: field `metrics", "relmse"],
        ..BASE
    },
    Case {
        name: "study-threshold-max-negative",
        files: &["threshold-max-negative.toml"],
        builtins: &["soft-shadow.toml"],
        args: dry_run!("threshold-max-negative.toml"),
        error: &["threshold-max-negative.toml:16: field `threshold[0].max`"],
        ..BASE
    },
    // --- Study names that escape the report folder.
    Case {
        name: "study-name-dotdot",
        files: &["study-name.toml"],
        builtins: &["soft-shadow.toml"],
        subst: &[("@NAME@", "../../esc")],
        args: dry_run!("study-name.toml"),
        error: &["study-name.toml:2: field `name`"],
        ..BASE
    },
    Case {
        name: "study-name-absolute",
        files: &["study-name.toml"],
        builtins: &["soft-shadow.toml"],
        subst: &[("@NAME@", "/tmp/verity-hostile-esc")],
        args: dry_run!("study-name.toml"),
        error: &["study-name.toml:2: field `name`"],
        ..BASE
    },
    Case {
        name: "study-name-empty",
        files: &["study-name.toml"],
        builtins: &["soft-shadow.toml"],
        subst: &[("@NAME@", "")],
        args: dry_run!("study-name.toml"),
        error: &["study-name.toml:2: field `name`"],
        ..BASE
    },
    Case {
        name: "study-name-dot",
        files: &["study-name.toml"],
        builtins: &["soft-shadow.toml"],
        subst: &[("@NAME@", ".")],
        args: dry_run!("study-name.toml"),
        error: &["study-name.toml:2: field `name`"],
        ..BASE
    },
    // --- glTF values outside the specification's ranges.
    Case {
        name: "gltf-version-1",
        files: &["version.gltf"],
        subst: &[("@VERSION@", "1.0")],
        args: render!("version.gltf"),
        error: &["version.gltf", "asset.version"],
        ..BASE
    },
    Case {
        name: "gltf-version-3",
        files: &["version.gltf"],
        subst: &[("@VERSION@", "3.0")],
        args: render!("version.gltf"),
        error: &["version.gltf", "asset.version"],
        ..BASE
    },
    Case {
        name: "gltf-spot-inner-above-outer",
        files: &["spot.gltf"],
        subst: &[("@INNER@", "0.8"), ("@OUTER@", "0.5")],
        args: render!("spot.gltf"),
        error: &["spot.gltf", "lights[0].spot", "ConeAngle"],
        ..BASE
    },
    Case {
        name: "gltf-spot-outer-3",
        files: &["spot.gltf"],
        subst: &[("@INNER@", "0.2"), ("@OUTER@", "3")],
        args: render!("spot.gltf"),
        error: &["spot.gltf", "lights[0].spot.outerConeAngle"],
        ..BASE
    },
    Case {
        name: "gltf-projective-matrix",
        files: &["projective-matrix.gltf"],
        args: render!("projective-matrix.gltf"),
        error: &["projective-matrix.gltf", "nodes[0].matrix"],
        ..BASE
    },
    // --- Names that cannot become channel or file names.
    bad_name!(
        "shape-name-slash",
        "shape-name.toml",
        "shape-name.toml:17:",
        "a/b"
    ),
    bad_name!(
        "shape-name-colon",
        "shape-name.toml",
        "shape-name.toml:17:",
        "a:b"
    ),
    bad_name!("shape-name-star", "shape-name.toml", "shape-name.toml:17:", "a*b"),
    bad_name!(
        "shape-name-emoji",
        "shape-name.toml",
        "shape-name.toml:17:",
        "\u{1F642}"
    ),
    bad_name!(
        "shape-name-rtl-override",
        "shape-name.toml",
        "shape-name.toml:17:",
        "\\u202Egnp.exe"
    ),
    bad_name!(
        "shape-name-newline",
        "shape-name.toml",
        "shape-name.toml:17:",
        "a\\nb"
    ),
    bad_name!(
        "light-name-slash",
        "light-name.toml",
        "light-name.toml:24:",
        "a/b"
    ),
    bad_name!(
        "light-name-colon",
        "light-name.toml",
        "light-name.toml:24:",
        "a:b"
    ),
    bad_name!("light-name-star", "light-name.toml", "light-name.toml:24:", "a*b"),
    bad_name!(
        "light-name-emoji",
        "light-name.toml",
        "light-name.toml:24:",
        "\u{1F642}"
    ),
    bad_name!(
        "light-name-rtl-override",
        "light-name.toml",
        "light-name.toml:24:",
        "\\u202Egnp.exe"
    ),
    bad_name!(
        "light-name-newline",
        "light-name.toml",
        "light-name.toml:24:",
        "a\\nb"
    ),
    // --- A TOML table given twice: one line that says so.
    Case {
        name: "toml-duplicate-table",
        files: &["duplicate-table.toml"],
        args: render!("duplicate-table.toml"),
        error: &["duplicate-table.toml:7", "duplicate table"],
        absent: &["invalid table header"],
        ..BASE
    },
    // --- Corrupted checkpoints are refused by --resume (exit 1, naming the checkpoint).
    checkpoint!("checkpoint-flip-first-byte", Corrupt::Flip(0, 1)),
    checkpoint!("checkpoint-flip-byte-8", Corrupt::FlipByte(8)),
    checkpoint!("checkpoint-flip-quarter", Corrupt::Flip(1, 4)),
    checkpoint!("checkpoint-flip-middle", Corrupt::Flip(1, 2)),
    checkpoint!("checkpoint-flip-three-quarters", Corrupt::Flip(3, 4)),
    checkpoint!("checkpoint-flip-last-byte", Corrupt::Flip(1, 1)),
    checkpoint!("checkpoint-truncated", Corrupt::Truncate),
];

/// The render the checkpoint cases resume is the one [`CHECKPOINTED`] starts.
#[test]
fn checkpoint_cases_resume_the_checkpointed_render() {
    for case in CASES
        .iter()
        .filter(|c| c.make.iter().any(|m| matches!(m, Make::Checkpoint(_))))
    {
        assert_eq!(&case.args[..CHECKPOINTED.len()], CHECKPOINTED, "{}", case.name);
    }
}
