//! Bad scene files: every class of mistake gives an error naming the file, the field and
//! the line, and loading never panics.

mod toml_support;

use toml_support::{append, expect_error, load_text, replace_line, scratch, write, BASE};

#[test]
fn base_scene_is_valid() {
    let dir = scratch("base");
    let scene = load_text(&dir, BASE).unwrap_or_else(|e| panic!("the base scene must load: {e}"));
    assert_eq!((scene.shapes.len(), scene.materials.len()), (1, 1));
}

#[test]
fn syntax_errors_name_the_line() {
    let dir = scratch("syntax");
    expect_error(
        load_text(&dir, &replace_line(4, "fov = = 40")),
        &["bad.toml:4:", "TOML syntax"],
    );
    // A key given twice is a TOML error too.
    expect_error(
        load_text(&dir, &replace_line(15, "radius = 1\nradius = 2")),
        &["bad.toml:16:", "TOML syntax"],
    );
}

#[test]
fn unknown_fields_and_sections() {
    let dir = scratch("unknown");
    expect_error(
        load_text(&dir, &replace_line(15, "radus = 1")),
        &[
            "bad.toml:15:",
            "field `shape \"s\".radus`",
            "unknown field `radus` for a sphere",
            "did you mean `radius`?",
        ],
    );
    expect_error(
        load_text(&dir, &append("[[shapes]]\nname = \"x\"\n")),
        &[
            "bad.toml:17:",
            "field `shapes`",
            "unknown field `shapes` for a scene file",
            "did you mean `shape`?",
        ],
    );
    // A field that belongs to another shape type is unknown for this one.
    expect_error(
        load_text(&dir, &replace_line(15, "radius = 1\nsize = [1, 1]")),
        &[
            "bad.toml:16:",
            "`shape \"s\".size`",
            "unknown field `size` for a sphere",
        ],
    );
    expect_error(
        load_text(&dir, &replace_line(4, "fov = 40\nfocus = 2")),
        &["bad.toml:5:", "`camera.focus`", "unknown field"],
    );
    expect_error(
        load_text(&dir, &replace_line(8, "type = \"diffuse\"\nroughness = 0.5")),
        &[
            "bad.toml:9:",
            "`material \"m\".roughness`",
            "unknown field `roughness` for a diffuse material",
        ],
    );
}

#[test]
fn wrong_types() {
    let dir = scratch("types");
    expect_error(
        load_text(&dir, &replace_line(15, "radius = \"one\"")),
        &[
            "bad.toml:15:",
            "`shape \"s\".radius`",
            "expected a number, found a string",
        ],
    );
    expect_error(
        load_text(&dir, &replace_line(14, "center = [0, 0]")),
        &[
            "bad.toml:14:",
            "`shape \"s\".center`",
            "expected an array of 3 numbers, found 2",
        ],
    );
    expect_error(
        load_text(&dir, &replace_line(14, "center = [0, \"a\", 0]")),
        &["bad.toml:14:", "`shape \"s\".center[1]`", "expected a number"],
    );
    expect_error(
        load_text(&dir, &replace_line(14, "center = 1979-05-27")),
        &["bad.toml:14:", "`shape \"s\".center`", "found a date-time"],
    );
    // A single [material] table where an array of tables is expected.
    let text = BASE.replace("[[material]]", "[material]");
    expect_error(
        load_text(&dir, &text),
        &["bad.toml:6:", "`material`", "[[material]]"],
    );
    expect_error(
        load_text(&dir, &append("[render]\nspp = 64.5\n")),
        &["bad.toml:18:", "`render.spp`", "expected an integer"],
    );
}

#[test]
fn non_finite_numbers() {
    let dir = scratch("nan");
    expect_error(
        load_text(&dir, &replace_line(15, "radius = nan")),
        &["bad.toml:15:", "`shape \"s\".radius`", "NaN"],
    );
    expect_error(
        load_text(&dir, &replace_line(14, "center = [0, inf, 0]")),
        &["bad.toml:14:", "`shape \"s\".center[1]`", "not a finite"],
    );
    expect_error(
        load_text(&dir, &replace_line(4, "fov = -inf")),
        &["bad.toml:4:", "`camera.fov`", "not a finite"],
    );
    // Finite in TOML (f64) but not in f32.
    expect_error(
        load_text(&dir, &replace_line(15, "radius = 1e300")),
        &["bad.toml:15:", "not a finite 32-bit"],
    );
    expect_error(
        load_text(
            &dir,
            &append(
                "[[light]]\nname = \"p\"\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = [1, nan, 1]\n",
            ),
        ),
        &["bad.toml:21:", "`light \"p\".intensity[1]`", "NaN"],
    );
}

#[test]
fn negative_and_zero_sizes() {
    let dir = scratch("sizes");
    expect_error(
        load_text(&dir, &replace_line(15, "radius = -1")),
        &["bad.toml:15:", "`shape \"s\".radius`", "must be > 0, got -1"],
    );
    let rect = |extent: &str| {
        append(&format!(
            "[[shape]]\nname = \"r\"\ntype = \"rectangle\"\nmaterial = \"m\"\ncenter = [0, 2, 0]\n{extent}\n"
        ))
    };
    expect_error(
        load_text(&dir, &rect("size = [1, -2]\nnormal = [0, -1, 0]")),
        &["bad.toml:22:", "`shape \"r\".size`", "must be > 0"],
    );
    expect_error(
        load_text(&dir, &rect("half_u = [1, 0, 0]\nhalf_v = [2, 0, 0]")),
        &["bad.toml:22:", "`shape \"r\".half_u`", "zero area"],
    );
    expect_error(
        load_text(
            &dir,
            &append("[[shape]]\ntype = \"box\"\nmaterial = \"m\"\ncenter = [0, 0, 0]\nsize = [1, 0, 1]\n"),
        ),
        &["bad.toml:21:", "`shape[1].size`", "every side must be > 0"],
    );
}

#[test]
fn zero_area_lights() {
    let dir = scratch("zero-area");
    let emitting = |geometry: &str| {
        append(&format!(
            "[[shape]]\nname = \"lamp\"\nmaterial = \"m\"\n\
             emission = {{ radiance = [1, 1, 1] }}\n{geometry}\n"
        ))
    };
    expect_error(
        load_text(
            &dir,
            &emitting("type = \"sphere\"\ncenter = [0, 2, 0]\nradius = 0"),
        ),
        &[
            "bad.toml:23:",
            "`shape \"lamp\".radius`",
            "must be > 0",
            "positive area",
        ],
    );
    expect_error(
        load_text(
            &dir,
            &emitting("type = \"rectangle\"\ncenter = [0, 2, 0]\nsize = [0, 1]\nnormal = [0, -1, 0]"),
        ),
        &["bad.toml:23:", "`shape \"lamp\".size`", "must be > 0"],
    );
    expect_error(
        load_text(
            &dir,
            &emitting("type = \"disk\"\ncenter = [0, 2, 0]\nhalf_u = [0, 0, 0]\nhalf_v = [0, 0, 1]"),
        ),
        &[
            "bad.toml:23:",
            "`shape \"lamp\".half_u`",
            "the disk has zero area",
        ],
    );
    // A transform that squashes the light flat.
    expect_error(
        load_text(
            &dir,
            &emitting(
                "type = \"disk\"\ncenter = [0, 2, 0]\nradius = 1\nnormal = [0, -1, 0]\n\
                 transform = [{ scale = [1, 1, 0] }]",
            ),
        ),
        &["bad.toml:25:", "`shape \"lamp\".transform`", "singular"],
    );
    expect_error(
        load_text(
            &dir,
            &emitting("type = \"rectangle\"\ncenter = [0, 2, 0]\nsize = [1, 1]\nnormal = [0, -1, 0]")
                .replace("[1, 1, 1] }", "[1, -1, 1] }"),
        ),
        &[
            "bad.toml:20:",
            "`shape \"lamp\".emission.radiance`",
            "must lie in [0, 1e20]",
        ],
    );
}

#[test]
fn camera_errors() {
    let dir = scratch("camera");
    for fov in ["0", "180", "-10", "200"] {
        expect_error(
            load_text(&dir, &replace_line(4, &format!("fov = {fov}"))),
            &["bad.toml:4:", "field `camera.fov`", "must be in (0, 180) degrees"],
        );
    }
    expect_error(
        load_text(&dir, &replace_line(3, "target = [0, 1, 5]")),
        &["bad.toml:3:", "`camera.target`", "equals the eye"],
    );
    expect_error(
        load_text(&dir, &replace_line(4, "fov = 40\nup = [0, -2, -10]")),
        &["bad.toml:5:", "`camera.up`", "parallel to the view direction"],
    );
    // Looking straight down with the default up (+Y).
    expect_error(
        load_text(&dir, &replace_line(2, "eye = [0, 5, 0]")),
        &["bad.toml:3:", "`camera.target`", "parallel to the view direction"],
    );
    expect_error(
        load_text(&dir, &replace_line(4, "up = [0, 0, 0]")),
        &["`camera.up`", "non-zero direction"],
    );
    expect_error(
        load_text(&dir, &replace_line(3, "target = [0, 0, 0]\nazimuth = 30")),
        &["bad.toml:4:", "`camera.azimuth`", "both `eye` and an orbit field"],
    );
    expect_error(
        load_text(&dir, &replace_line(2, "azimuth = 30")),
        &["the camera needs `eye`, or `distance`"],
    );
    for (line, field, message) in [
        ("distance = 0", "`camera.distance`", "finite distance > 0"),
        ("distance = 2\nelevation = 90", "`camera.elevation`", "(−90, 90)"),
        ("distance = 2\nazimuth = nan", "`camera.azimuth`", ""),
    ] {
        expect_error(load_text(&dir, &replace_line(2, line)), &[field, message]);
    }
    let no_camera: String = BASE.lines().skip(5).collect::<Vec<_>>().join("\n");
    expect_error(
        load_text(&dir, &no_camera),
        &[
            "bad.toml:1:",
            "field `camera`",
            "missing required field",
            "add a [camera] section",
        ],
    );
}

#[test]
fn names_and_references() {
    let dir = scratch("names");
    expect_error(
        load_text(&dir, &replace_line(13, "material = \"mm\"")),
        &[
            "bad.toml:13:",
            "`shape \"s\".material`",
            "unknown material \"mm\"",
            "did you mean `m`?",
        ],
    );
    expect_error(
        load_text(&dir, &append("[[material]]\nname = \"m\"\ntype = \"mirror\"\n")),
        &[
            "bad.toml:18:",
            "`material[1].name`",
            "duplicate material name \"m\" (first defined on line 6)",
        ],
    );
    expect_error(
        load_text(
            &dir,
            &append(
                "[[shape]]\nname = \"s\"\ntype = \"sphere\"\nmaterial = \"m\"\n\
                 center = [3, 0, 0]\nradius = 1\n",
            ),
        ),
        &[
            "bad.toml:18:",
            "`shape \"s\".name`",
            "duplicate name \"s\" (first used by shape on line 11)",
        ],
    );
    // Shapes and lights share one namespace (both name visibility AOVs).
    expect_error(
        load_text(
            &dir,
            &append("[[light]]\nname = \"s\"\ntype = \"point\"\nposition = [0, 3, 0]\nintensity = 1\n"),
        ),
        &["bad.toml:18:", "`light \"s\".name`", "duplicate name"],
    );
    expect_error(
        load_text(&dir, &replace_line(11, "name = \"a.b\"")),
        &["bad.toml:11:", "invalid shape name \"a.b\""],
    );
    expect_error(
        load_text(
            &dir,
            &replace_line(15, "radius = 1\ntype = \"mesh\"").replace("type = \"sphere\"\n", ""),
        ),
        &[
            "`shape \"s\".type`",
            "triangle meshes cannot be written",
            "[[include]]",
        ],
    );
    expect_error(
        load_text(&dir, &replace_line(12, "type = \"spehre\"")),
        &[
            "bad.toml:12:",
            "`shape \"s\".type`",
            "unknown value \"spehre\"",
            "did you mean `sphere`?",
        ],
    );
    expect_error(
        load_text(&dir, &replace_line(15, "")),
        &[
            "bad.toml:10:",
            "field `shape \"s\".radius`",
            "missing required field",
        ],
    );
}

#[test]
fn generated_names_are_unique() {
    let dir = scratch("generated");
    let text = append(
        "[[shape]]\ntype = \"sphere\"\nmaterial = \"m\"\ncenter = [3, 0, 0]\nradius = 1\n\n\
         [[shape]]\nname = \"sphere_1\"\ntype = \"sphere\"\nmaterial = \"m\"\n\
         center = [6, 0, 0]\nradius = 1\n",
    );
    let scene = load_text(&dir, &text).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = scene.shapes.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, vec!["s", "sphere_1_", "sphere_1"]);
}

#[test]
fn render_and_film_ranges() {
    let dir = scratch("render");
    expect_error(
        load_text(&dir, &append("[film]\nwidth = 100000\nheight = 100\n")),
        &[
            "bad.toml:18:",
            "`film.width`",
            "must be in 1..=16384 pixels, got 100000",
        ],
    );
    expect_error(
        load_text(&dir, &append("[film]\nheight = 0\n")),
        &["bad.toml:18:", "`film.height`"],
    );
    expect_error(
        load_text(&dir, &append("[render]\nmax_depth = 0\n")),
        &["bad.toml:18:", "`render.max_depth`", "-1 (unbounded) or >= 1"],
    );
    expect_error(
        load_text(&dir, &append("[render]\nintegrator = \"paht\"\n")),
        &["bad.toml:18:", "`render.integrator`", "did you mean `path`?"],
    );
    expect_error(
        load_text(&dir, &append("[render]\nspp = 0\n")),
        &["bad.toml:18:", "`render.spp`"],
    );
    expect_error(
        load_text(&dir, &append("[render]\nseed = -1\n")),
        &["bad.toml:18:", "`render.seed`"],
    );
    expect_error(
        load_text(&dir, &append("[render]\nao_radius = 0\n")),
        &["bad.toml:18:", "`render.ao_radius`"],
    );
}

/// An unknown pixel filter is one line naming the file, line and field, with the spellings.
#[test]
fn unknown_pixel_filter_names_its_line() {
    let dir = scratch("render-pixel-filter");
    let e = expect_error(
        load_text(&dir, &append("[render]\nspp = 4\npixel_filter = \"gauss\"\n")),
        &[
            "bad.toml:19:",
            "`render.pixel_filter`",
            "unknown value \"gauss\"",
            "`box`, `centre`, `center`",
        ],
    );
    assert_eq!(e.to_string().lines().count(), 1, "{e}");
    expect_error(
        load_text(&dir, &append("[render]\npixel_filter = 1\n")),
        &["bad.toml:18:", "`render.pixel_filter`", "expected a string"],
    );
}

#[test]
fn light_errors() {
    let dir = scratch("lights");
    let spot = |extra: &str| {
        append(&format!(
            "[[light]]\nname = \"spot\"\ntype = \"spot\"\nposition = [0, 3, 0]\nintensity = 10\n{extra}\n"
        ))
    };
    expect_error(
        load_text(&dir, &spot("target = [0, 0, 0]\ncutoff_angle = 95")),
        &["bad.toml:23:", "`light \"spot\".cutoff_angle`", "(0, 90]"],
    );
    expect_error(
        load_text(
            &dir,
            &spot("target = [0, 0, 0]\ncutoff_angle = 20\nbeam_width = 30"),
        ),
        &["bad.toml:24:", "`light \"spot\".beam_width`"],
    );
    expect_error(
        load_text(&dir, &spot("target = [0, 0, 0]\ndirection = [0, -1, 0]")),
        &[
            "bad.toml:22:",
            "`light \"spot\".target`",
            "`direction` and `target` cannot be given together",
        ],
    );
    expect_error(
        load_text(&dir, &spot("direction = [0, 0, 0]")),
        &["bad.toml:22:", "non-zero direction"],
    );
    // A projected texture (scenes::projection): an image, oriented by an `up` across the axis.
    std::fs::copy(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/checker_3x3.png"),
        dir.join("cookie.png"),
    )
    .unwrap();
    expect_error(
        load_text(&dir, &spot("target = [0, 0, -1]\ntexture = 0.5")),
        &["bad.toml:23:", "`light \"spot\".texture`", "must be an image"],
    );
    expect_error(
        load_text(&dir, &spot("target = [0, 0, -1]\nup = [1, 0, 0]")),
        &[
            "bad.toml:23:",
            "`light \"spot\".up`",
            "orients a projected `texture`",
        ],
    );
    expect_error(
        load_text(
            &dir,
            &spot("target = [0, 0, 0]\ntexture = { texture = \"cookie.png\" }"),
        ),
        &["bad.toml:", "light \"spot\"", "the default `up`"],
    );
    expect_error(
        load_text(
            &dir,
            &spot("target = [0, 0, 0]\ntexture = { texture = \"cookie.png\" }\nup = [0, 2, 0]"),
        ),
        &["bad.toml:24:", "`light \"spot\".up`", "along the spot's axis"],
    );
    expect_error(
        load_text(
            &dir,
            &spot("target = [0, 0, -1]\ntexture = { texture = \"missing.png\" }"),
        ),
        &["bad.toml:23:", "missing.png"],
    );
    let ok = load_text(
        &dir,
        &spot("target = [0, 0, -1]\ntexture = { texture = \"cookie.png\", factor = [1, 0.5, 0.5] }"),
    )
    .unwrap();
    let scenes::Light::Spot {
        projection: Some(p), ..
    } = &ok.lights[0]
    else {
        panic!("{:?}", ok.lights[0]);
    };
    assert_eq!(p.up, glam::Vec3::Y);
    assert!(matches!(p.texture, scenes::TexRgb::Image { .. }));
    expect_error(
        load_text(
            &dir,
            &append("[[light]]\ntype = \"point\"\nposition = [0, 3, 0]\nintensity = 1\n"),
        ),
        &["bad.toml:17:", "`light[0].name`", "missing required field"],
    );
    expect_error(
        load_text(
            &dir,
            &append(
                "[[light]]\nname = \"sun\"\ntype = \"directional\"\ndirection = [0, -1, 0]\n\
                 irradiance = 1\nangular_diameter = 180\n",
            ),
        ),
        &["bad.toml:22:", "`light \"sun\".angular_diameter`", "[0, 180)"],
    );
}

#[test]
fn transform_errors() {
    let dir = scratch("transform");
    expect_error(
        load_text(
            &dir,
            &replace_line(15, "radius = 1\ntransform = [{ scale = [1, 2, 1] }]"),
        ),
        &["bad.toml:16:", "`shape \"s\".transform`", "must keep it a sphere"],
    );
    expect_error(
        load_text(&dir, &replace_line(15, "radius = 1\ntransform = [{ shear = 1 }]")),
        &[
            "bad.toml:16:",
            "`shape \"s\".transform[0].shear`",
            "unknown field `shear` for a transform step",
        ],
    );
    expect_error(
        load_text(
            &dir,
            &replace_line(
                15,
                "radius = 1\ntransform = [{ translate = [1, 0, 0], scale = 2 }]",
            ),
        ),
        &["bad.toml:16:", "cannot be given together"],
    );
    expect_error(
        load_text(&dir, &replace_line(15, "radius = 1\ntransform = [\n  {},\n]")),
        &[
            "bad.toml:17:",
            "`shape \"s\".transform[0]`",
            "empty transform step",
        ],
    );
    expect_error(
        load_text(
            &dir,
            &replace_line(
                15,
                "radius = 1\n\
                 transform = [{ matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]] }]",
            ),
        ),
        &[
            "bad.toml:16:",
            "`shape \"s\".transform[0].matrix[3]`",
            "[0, 0, 0, 1]",
        ],
    );
    expect_error(
        load_text(
            &dir,
            &replace_line(
                15,
                "radius = 1\ntransform = [{ rotate = { axis = [0, 0, 0], angle = 10 } }]",
            ),
        ),
        &["`shape \"s\".transform[0].rotate.axis`", "non-zero direction"],
    );
}

#[test]
fn missing_files() {
    let dir = scratch("missing");
    expect_error(
        load_text(
            &dir,
            &replace_line(8, "type = \"diffuse\"\nalbedo = { texture = \"tex/wood.png\" }"),
        ),
        &[
            "bad.toml:9:",
            "`material \"m\".albedo.texture`",
            "file not found",
            "wood.png",
            "relative to the scene file",
        ],
    );
    expect_error(
        load_text(&dir, &append("[environment]\nfile = \"sky.exr\"\n")),
        &["bad.toml:18:", "`environment.file`", "file not found", "sky.exr"],
    );
    expect_error(
        load_text(&dir, &append("[[include]]\nfile = \"model.glb\"\n")),
        &["bad.toml:18:", "`include[0].file`", "file not found", "model.glb"],
    );
    expect_error(
        load_text(&dir, &append("[[include]]\nfile = \"other.toml\"\n")),
        &[
            "bad.toml:18:",
            "`include[0].file`",
            "cannot include",
            "glTF 2.0 assets",
        ],
    );
    let missing = dir.join("nowhere.toml");
    let err = expect_error(
        scenes::load(&missing),
        &["nowhere.toml", "cannot read the scene file"],
    );
    assert_eq!(err.file, missing);
}

#[test]
fn malformed_files() {
    let dir = scratch("malformed");
    write(&dir, "junk.png", "this is not an image");
    expect_error(
        load_text(
            &dir,
            &replace_line(8, "type = \"diffuse\"\nalbedo = { texture = \"junk.png\" }"),
        ),
        &[
            "bad.toml:9:",
            "`material \"m\".albedo.texture`",
            "cannot load the texture",
            "junk.png",
        ],
    );
    // A PNG cut off after its header.
    let mut png = Vec::new();
    image::RgbImage::from_pixel(8, 8, image::Rgb([200, 100, 50]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    std::fs::write(dir.join("cut.png"), &png[..40]).unwrap();
    expect_error(
        load_text(
            &dir,
            &replace_line(8, "type = \"diffuse\"\nalbedo = { texture = \"cut.png\" }"),
        ),
        &["bad.toml:9:", "cannot load the texture", "cut.png"],
    );
    // An EXR whose header is cut.
    std::fs::write(dir.join("cut.exr"), [0x76, 0x2f, 0x31, 0x01, 2, 0, 0]).unwrap();
    expect_error(
        load_text(&dir, &append("[environment]\nfile = \"cut.exr\"\n")),
        &[
            "bad.toml:18:",
            "`environment.file`",
            "cannot load the texture",
            "cut.exr",
            "OpenEXR",
        ],
    );
    // Not UTF-8.
    let path = dir.join("latin1.toml");
    std::fs::write(&path, b"[camera]\nname = \"caf\xe9\"\n").unwrap();
    expect_error(scenes::load(&path), &["latin1.toml", "not UTF-8"]);
}

#[test]
fn environment_errors() {
    let dir = scratch("environment");
    expect_error(
        load_text(
            &dir,
            &append("[environment]\nradiance = [1, 1, 1]\nfile = \"x.exr\"\n"),
        ),
        &["bad.toml:19:", "cannot be given together"],
    );
    expect_error(
        load_text(&dir, &append("[environment]\nscale = 2\n")),
        &["bad.toml:17:", "needs `radiance` or `file`"],
    );
    expect_error(
        load_text(&dir, &append("[environment]\nradiance = [1, -1, 1]\n")),
        &["bad.toml:18:", "`environment.radiance`", "must lie in [0, 1e20]"],
    );
    // An environment map with a negative texel (lossy EXR ringing) is refused.
    let pixels = [(0.5f32, 0.5f32, 0.5f32), (-0.25, 0.5, 0.5)];
    exr::prelude::write_rgb_file(dir.join("neg.exr"), 2, 1, |x, _| pixels[x]).unwrap();
    expect_error(
        load_text(&dir, &append("[environment]\nfile = \"neg.exr\"\n")),
        &[
            "bad.toml:18:",
            "`environment.file`",
            "negative radiance",
            "texel (1, 0)",
        ],
    );
}

#[test]
fn material_ranges() {
    let dir = scratch("materials");
    expect_error(
        load_text(
            &dir,
            &replace_line(8, "type = \"diffuse\"\nalbedo = [1.2, 0.5, 0.5]"),
        ),
        &[
            "bad.toml:9:",
            "`material \"m\".albedo`",
            "must lie in [0, 1]",
            "creates energy",
        ],
    );
    expect_error(
        load_text(&dir, &replace_line(8, "type = \"ggx\"\nroughness = 1.5")),
        &["bad.toml:9:", "`material \"m\".roughness`", "must lie in [0, 1]"],
    );
    expect_error(
        load_text(&dir, &replace_line(8, "type = \"ggx\"")),
        &[
            "bad.toml:6:",
            "`material \"m\".roughness`",
            "missing required field",
        ],
    );
    expect_error(
        load_text(
            &dir,
            &replace_line(8, "type = \"ggx\"\nroughness = 0.2\nmasking = \"smith\""),
        ),
        &["bad.toml:10:", "`material \"m\".masking`", "height_correlated"],
    );
    expect_error(
        load_text(&dir, &replace_line(8, "type = \"dielectric\"\nint_ior = 0")),
        &["bad.toml:9:", "`material \"m\".int_ior`", "must be > 0"],
    );
    expect_error(
        load_text(&dir, &replace_line(8, "type = \"phong\"\nexponent = -1")),
        &["bad.toml:9:", "`material \"m\".exponent`", "must be >= 0"],
    );
    expect_error(
        load_text(
            &dir,
            &replace_line(
                8,
                "type = \"diffuse\"\nalbedo = { texture = \"t.png\", wrap = \"tile\" }",
            ),
        ),
        &[
            "bad.toml:9:",
            "`material \"m\".albedo.wrap`",
            "unknown value \"tile\"",
        ],
    );
}

/// Coordinates and lengths beyond ±1e15 m are refused where they are written, with the
/// right diagnosis: before, a sphere at 1e30 or of radius 3e38 loaded and failed at render
/// time (exit 1, no line), `eye = [3e38, …]` was called "`up` is parallel to the view" and
/// `half_u = [3e38, 0, 0]` "zero area" (their products overflowed).
#[test]
fn coordinates_beyond_the_world_are_refused_at_load() {
    let dir = scratch("beyond");
    // BASE up to the shape's name (line 11), then `body`.
    let shape = |body: &str| {
        let head: Vec<&str> = BASE.lines().take(11).collect();
        format!("{}\nmaterial = \"m\"\n{body}\n", head.join("\n"))
    };
    let cases: &[(String, &[&str])] = &[
        (replace_line(14, "center = [1e30, 0, 0]"), &["bad.toml:14:", "`shape \"s\".center`", "[1e30, 0.0, 0.0] is beyond ±1e15 m"]),
        (replace_line(15, "radius = 3e38"), &["bad.toml:15:", "`shape \"s\".radius`", "3e38 is beyond ±1e15 m"]),
        (replace_line(2, "eye = [3e38, 3e38, 3e38]"), &["bad.toml:2:", "`camera.eye`", "is beyond ±1e15 m"]),
        (replace_line(3, "target = [0, -2e15, 0]"), &["bad.toml:3:", "`camera.target`", "is beyond ±1e15 m"]),
        (
            shape("type = \"box\"\ncenter = [0, 0, 0]\nsize = [3e38, 1, 1]"),
            &["`shape \"s\".size`", "[3e38, 1.0, 1.0] is beyond ±1e15 m"],
        ),
        (
            shape("type = \"rectangle\"\ncenter = [0, 0, 0]\nhalf_u = [3e38, 0, 0]\nhalf_v = [0, 0, 1]"),
            &["`shape \"s\".half_u`", "[3e38, 0.0, 0.0] is beyond ±1e15 m"],
        ),
        (
            replace_line(15, "radius = 1\ntransform = [{ scale = 1e20 }]"),
            &["`shape \"s\".transform[0].scale`", "the transform reaches beyond ±1e15"],
        ),
        (
            replace_line(15, "radius = 1e8\ntransform = [{ scale = 1e8 }]"),
            &["`shape \"s\".transform`", "the transform sends the shape beyond ±1e15 m"],
        ),
        (
            shape("type = \"rectangle\"\ncenter = [0, 0, 0]\nsize = [1, 1]\nnormal = [0, 1, 0]\ndisplacement = { procedural = \"bumps\", resolution = 4, scale = 3e38 }"),
            &["`shape \"s\".displacement.scale`", "3e38 is beyond ±1e15 m"],
        ),
        (
            shape("type = \"rectangle\"\ncenter = [0, 0, 0]\nsize = [1, 1]\nnormal = [0, 1, 0]\ndisplacement = { procedural = \"bumps\", resolution = 4, scale = 9e14 }\ntransform = [{ translate = [9e14, 0, 0] }]"),
            &["`shape \"s\".displacement`", "the displaced surface reaches beyond ±1e15 m"],
        ),
    ];
    for (text, parts) in cases {
        expect_error(load_text(&dir, text), parts);
    }
}

/// Radiometric values that would overflow f32 once multiplied by a BSDF and a pdf, and Phong
/// exponents whose lobe normalization overflows (3e38 dropped 64 of 1024 samples as NaN,
/// reported only in the EXR header), are refused at load.
#[test]
fn overflowing_radiance_and_exponents_are_refused() {
    let dir = scratch("overflow");
    expect_error(
        load_text(
            &dir,
            &append("[[light]]\nname = \"l\"\ntype = \"point\"\nposition = [0, 3, 0]\nintensity = 3e38\n"),
        ),
        &[
            "`light \"l\".intensity`",
            "must lie in [0, 1e20]",
            "overflows f32",
        ],
    );
    expect_error(
        load_text(&dir, &replace_line(8, "type = \"phong\"\nexponent = 3e38")),
        &[
            "bad.toml:9:",
            "`material \"m\".exponent`",
            "must be at most 1e6, got 3e38",
            "mirror",
        ],
    );
    let ok = load_text(&dir, &replace_line(8, "type = \"phong\"\nexponent = 1e6"));
    assert!(ok.is_ok(), "{:?}", ok.err());
}

/// Names become AOV channels and file names: only ASCII letters, digits, `_` and `-`, and a
/// bad one is echoed escaped and cut, so the error stays one readable line.
#[test]
fn names_are_identifiers_and_are_echoed_safely() {
    let dir = scratch("names");
    for (name, shown) in [
        ("a/b", "\"a/b\""),
        ("c:d", "\"c:d\""),
        ("star*", "\"star*\""),
        ("lamp.1", "\"lamp.1\""),
        ("emoji\u{1f4a1}", "\"emoji\u{1f4a1}\""),
        ("rtl\u{202e}txt", "\"rtl\\u{202e}txt\""),
        ("line\\nbreak", "\"line\\nbreak\""),
    ] {
        let e = expect_error(
            load_text(&dir, &replace_line(11, &format!("name = \"{name}\""))),
            &[
                "bad.toml:11:",
                &format!("invalid shape name {shown}"),
                "ASCII letters, digits, '_' and '-'",
            ],
        );
        assert!(!e.to_string().contains('\n'), "{e}");
    }
    let long = "x".repeat(100_000);
    let e = expect_error(
        load_text(&dir, &replace_line(11, &format!("name = \"{long}\""))),
        &["invalid shape name \"xxxx", "\"…"],
    );
    assert!(e.to_string().len() < 600, "the message echoes the whole name");
    assert!(load_text(&dir, &replace_line(11, "name = \"Lamp_2-b\"")).is_ok());
}

/// TOML syntax errors are one line; a table written twice says so and where it first was
/// (the `toml` crate says "invalid table header" and "duplicate key" on two lines).
#[test]
fn syntax_errors_are_one_line() {
    let dir = scratch("syntax-one-line");
    let e = expect_error(
        load_text(&dir, &append("[camera]\nfov = 3\n")),
        &[
            "bad.toml:17:",
            "TOML syntax: duplicate table [camera] (first on line 1)",
        ],
    );
    assert!(!e.to_string().contains('\n'), "{e}");
    let e = expect_error(
        load_text(&dir, &replace_line(2, "eye = [0, 1, 5")),
        &["bad.toml:", "TOML syntax: "],
    );
    assert!(!e.to_string().contains('\n'), "{e}");
}

/// A scene path that exists but is not a regular file is said to be what it is (it was
/// "file not found", and a FIFO would block the reader forever).
#[test]
fn scene_paths_that_are_not_regular_files() {
    let dir = scratch("not-regular");
    let e = scenes::load(&dir.join(".")).unwrap_err().to_string();
    assert!(
        e.contains("unknown scene file type") || e.contains("is a directory"),
        "{e}"
    );
    let folder = dir.join("folder.toml");
    std::fs::create_dir_all(&folder).unwrap();
    let e = scenes::load(&folder).unwrap_err().to_string();
    assert!(
        e.contains("cannot read the scene file: it is not a regular file (it is a directory)"),
        "{e}"
    );
    let fifo = dir.join("fifo.toml");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let e = scenes::load(&fifo).unwrap_err().to_string();
    assert!(e.contains("it is not a regular file (it is a FIFO)"), "{e}");
    let e = scenes::load(&dir.join("missing.toml")).unwrap_err().to_string();
    assert!(e.contains("cannot read the scene file: it does not exist"), "{e}");
}
