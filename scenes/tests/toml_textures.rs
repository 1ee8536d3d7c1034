//! Texture loading: formats, sRGB decoding, bit depths, orientation, wrap modes, and their
//! use from scene files.

mod toml_support;

use std::path::Path;

use exr::prelude::WritableImage;
use glam::{Vec2, Vec3, Vec4};
use image::{ImageFormat, Luma, LumaA, Rgb, Rgba};
use scenes::srgb::srgb_to_linear;
use scenes::texture::{load_texture, ColorSpace};
use scenes::{Material, TexRgb, TexScalar, WrapMode};
use toml_support::{expect_error, scratch, write, BASE};

const REPEAT: [WrapMode; 2] = [WrapMode::Repeat; 2];

fn assert_texel(what: &str, actual: Vec4, expected: Vec4, tol: f32) {
    assert!(
        (actual - expected).abs().max_element() <= tol,
        "{what}: expected {expected}, got {actual} (tolerance {tol})"
    );
}

fn load(path: &Path, space: ColorSpace) -> scenes::texture::Texture {
    load_texture(path, space, REPEAT).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn png_8bit_srgb_and_linear() {
    let dir = scratch("png8");
    let path = dir.join("ramp.png");
    let codes = [0u8, 10, 11, 128, 200, 255];
    image::RgbaImage::from_fn(codes.len() as u32, 1, |x, _| {
        let c = codes[x as usize];
        Rgba([c, 255 - c, c / 2, c])
    })
    .save(&path)
    .unwrap();
    let srgb = load(&path, ColorSpace::Srgb);
    let linear = load(&path, ColorSpace::Linear);
    assert_eq!((srgb.width, srgb.height), (codes.len() as u32, 1));
    for (i, &c) in codes.iter().enumerate() {
        let v = |c: u8| f32::from(c) / 255.0;
        let alpha = v(c); // alpha is never sRGB-decoded
        let want_srgb = Vec4::new(
            srgb_to_linear(v(c)),
            srgb_to_linear(v(255 - c)),
            srgb_to_linear(v(c / 2)),
            alpha,
        );
        assert_texel(&format!("sRGB code {c}"), srgb.texels[i], want_srgb, 1e-7);
        let want_linear = Vec4::new(v(c), v(255 - c), v(c / 2), alpha);
        assert_texel(&format!("linear code {c}"), linear.texels[i], want_linear, 1e-7);
    }
    // Spot values of the IEC 61966-2-1 curve: code 128 → 0.21586, code 10 is on the linear toe.
    assert_texel(
        "code 128",
        Vec4::splat(srgb.texels[3].x),
        Vec4::splat(0.215_861),
        1e-5,
    );
    assert_texel(
        "code 10",
        Vec4::splat(srgb.texels[1].x),
        Vec4::splat(10.0 / 255.0 / 12.92),
        1e-8,
    );
}

#[test]
fn png_16bit_grey_and_alpha() {
    let dir = scratch("png16");
    let path = dir.join("grey16.png");
    image::ImageBuffer::<Luma<u16>, Vec<u16>>::from_fn(2, 1, |x, _| Luma([[0u16, 32768][x as usize]]))
        .save(&path)
        .unwrap();
    let t = load(&path, ColorSpace::Srgb);
    let g = srgb_to_linear(32768.0 / 65535.0);
    assert_texel("16-bit grey", t.texels[1], Vec4::new(g, g, g, 1.0), 1e-7);
    assert_texel("16-bit black", t.texels[0], Vec4::new(0.0, 0.0, 0.0, 1.0), 0.0);

    let path = dir.join("greya8.png");
    image::ImageBuffer::<LumaA<u8>, Vec<u8>>::from_pixel(1, 1, LumaA([255, 51]))
        .save(&path)
        .unwrap();
    let t = load(&path, ColorSpace::Srgb);
    assert_texel("grey + alpha", t.texels[0], Vec4::new(1.0, 1.0, 1.0, 0.2), 1e-7);

    let path = dir.join("rgb16.png");
    image::ImageBuffer::<Rgb<u16>, Vec<u16>>::from_pixel(1, 1, Rgb([65535, 0, 13107]))
        .save(&path)
        .unwrap();
    let t = load(&path, ColorSpace::Linear);
    assert_texel(
        "16-bit linear RGB",
        t.texels[0],
        Vec4::new(1.0, 0.0, 0.2, 1.0),
        1e-7,
    );
}

#[test]
fn rows_start_at_the_top() {
    let dir = scratch("rows");
    let path = dir.join("rows.png");
    image::RgbImage::from_fn(1, 2, |_, y| {
        if y == 0 {
            Rgb([255, 0, 0])
        } else {
            Rgb([0, 0, 255])
        }
    })
    .save(&path)
    .unwrap();
    let t = load(&path, ColorSpace::Linear);
    assert_texel("row 0 (top)", t.texels[0], Vec4::new(1.0, 0.0, 0.0, 1.0), 0.0);
    assert_texel(
        "v = 0.25 samples the top row",
        t.sample(Vec2::new(0.5, 0.25)),
        Vec4::new(1.0, 0.0, 0.0, 1.0),
        0.0,
    );
}

#[test]
fn jpeg_decodes_with_srgb() {
    let dir = scratch("jpeg");
    let path = dir.join("flat.jpg");
    image::RgbImage::from_pixel(16, 16, Rgb([128, 128, 128]))
        .save_with_format(&path, ImageFormat::Jpeg)
        .unwrap();
    let t = load(&path, ColorSpace::Srgb);
    // A flat grey JPEG is lossless up to rounding: within one code of 128.
    let (lo, hi) = (srgb_to_linear(127.0 / 255.0), srgb_to_linear(129.0 / 255.0));
    for texel in &t.texels {
        assert!(
            texel.x >= lo && texel.x <= hi,
            "JPEG grey 128: expected {lo}..{hi}, got {}",
            texel.x
        );
        assert_eq!(texel.w, 1.0);
    }
}

#[test]
fn exr_rgb_rgba_and_luminance_stay_linear() {
    let dir = scratch("exr");
    let rgb = dir.join("rgb.exr");
    exr::prelude::write_rgb_file(&rgb, 2, 1, |x, _| [(2.5f32, 0.5, -0.25), (0.0, 1000.0, 0.125)][x]).unwrap();
    // ColorSpace::Srgb must not touch float data.
    let t = load(&rgb, ColorSpace::Srgb);
    assert_texel("EXR texel 0", t.texels[0], Vec4::new(2.5, 0.5, -0.25, 1.0), 0.0);
    assert_texel(
        "EXR texel 1",
        t.texels[1],
        Vec4::new(0.0, 1000.0, 0.125, 1.0),
        0.0,
    );

    let rgba = dir.join("rgba.exr");
    exr::prelude::write_rgba_file(&rgba, 1, 1, |_, _| (0.25f32, 0.5f32, 0.75f32, 0.5f32)).unwrap();
    assert_texel(
        "EXR RGBA",
        load(&rgba, ColorSpace::Linear).texels[0],
        Vec4::new(0.25, 0.5, 0.75, 0.5),
        0.0,
    );

    let y = dir.join("y.exr");
    let channels = exr::prelude::SpecificChannels::build()
        .with_channel("Y")
        .with_pixel_fn(|pos: exr::prelude::Vec2<usize>| (0.5f32 + pos.x() as f32,));
    exr::prelude::Image::from_channels((2, 1), channels)
        .write()
        .to_file(&y)
        .unwrap();
    let t = load(&y, ColorSpace::Linear);
    assert_texel("EXR Y", t.texels[1], Vec4::new(1.5, 1.5, 1.5, 1.0), 0.0);

    let nan = dir.join("nan.exr");
    exr::prelude::write_rgb_file(&nan, 2, 2, |x, y| {
        if (x, y) == (1, 1) {
            (f32::NAN, 0.0, 0.0)
        } else {
            (1.0, 1.0, 1.0)
        }
    })
    .unwrap();
    expect_scene_error(
        load_texture(&nan, ColorSpace::Linear, REPEAT),
        &["nan.exr", "texel (1, 1) is NaN or infinite"],
    );

    let depth = dir.join("depth.exr");
    let channels = exr::prelude::SpecificChannels::build()
        .with_channel("Z")
        .with_pixel_fn(|_| (1.0f32,));
    exr::prelude::Image::from_channels((1, 1), channels)
        .write()
        .to_file(&depth)
        .unwrap();
    expect_scene_error(
        load_texture(&depth, ColorSpace::Linear, REPEAT),
        &["depth.exr", "expected R, G, B", "\"Z\""],
    );
}

#[test]
fn radiance_hdr_is_linear() {
    let dir = scratch("hdr");
    let path = dir.join("sky.hdr");
    let pixels = [Rgb([4.0f32, 0.5, 0.125]), Rgb([0.0, 1.0, 100.0])];
    let file = std::fs::File::create(&path).unwrap();
    image::codecs::hdr::HdrEncoder::new(file)
        .encode(&pixels, 2, 1)
        .unwrap();
    let t = load(&path, ColorSpace::Srgb);
    // RGBE keeps an 8-bit mantissa per pixel: relative error below 2^-7 of the largest channel.
    for (i, p) in pixels.iter().enumerate() {
        let want = Vec4::new(p.0[0], p.0[1], p.0[2], 1.0);
        let tol = Vec3::from(p.0).max_element() / 128.0;
        assert_texel(&format!("HDR texel {i}"), t.texels[i], want, tol);
    }
}

#[test]
fn format_is_sniffed_and_errors_name_the_file() {
    let dir = scratch("sniff");
    let path = dir.join("actually_png.dat");
    image::RgbImage::from_pixel(1, 1, Rgb([255, 255, 255]))
        .save_with_format(&path, ImageFormat::Png)
        .unwrap();
    assert_eq!(load(&path, ColorSpace::Srgb).texels[0], Vec4::ONE);
    let text = write(&dir, "notes.txt", "hello");
    expect_scene_error(
        load_texture(&text, ColorSpace::Srgb, REPEAT),
        &["notes.txt", "not a PNG, JPEG, OpenEXR or Radiance HDR"],
    );
    let missing = dir.join("missing.png");
    expect_scene_error(
        load_texture(&missing, ColorSpace::Srgb, REPEAT),
        &["missing.png", "cannot read the image: it does not exist"],
    );
    // What exists but is not a regular file is said so, and a FIFO is never opened (opening
    // one for reading blocks until a writer comes).
    expect_scene_error(
        load_texture(&dir, ColorSpace::Srgb, REPEAT),
        &["cannot read the image: it is not a regular file (it is a directory)"],
    );
    let fifo = dir.join("fifo.png");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    expect_scene_error(
        load_texture(&fifo, ColorSpace::Srgb, REPEAT),
        &[
            "fifo.png",
            "cannot read the image: it is not a regular file (it is a FIFO)",
        ],
    );
}

/// Sizes declared by an image header are checked against the memory budget before the
/// decoder allocates them: a 4096² PNG (a few KB of zeros) under a 64 MiB ledger is refused
/// naming the size needed, and loads under a larger one; the ledger adds textures up.
#[test]
fn declared_sizes_are_checked_against_the_budget_before_decoding() {
    use scenes::budget::{Ledger, Limit, Source};
    use scenes::texture::load_texture_in;
    let dir = scratch("budget");
    let path = dir.join("big.png");
    image::GrayImage::new(4096, 4096)
        .save_with_format(&path, ImageFormat::Png)
        .unwrap();
    assert!(std::fs::metadata(&path).unwrap().len() < 200_000);
    let ledger = |mib: u64| {
        Ledger::with_limit(Limit {
            bytes: mib << 20,
            source: Source::Flag,
        })
    };
    let small = ledger(64);
    expect_scene_error(
        load_texture_in(&path, ColorSpace::Linear, REPEAT, &small),
        &[
            "big.png",
            "4096×4096 texels and their decoding: 768.0 MiB (805306368 bytes) needed",
            "--memory-limit",
        ],
    );
    assert_eq!(small.used(), 0, "nothing was charged");
    let large = ledger(1000);
    let t = load_texture_in(&path, ColorSpace::Linear, REPEAT, &large).unwrap();
    assert_eq!((t.width, t.height), (4096, 4096));
    assert_eq!(large.used(), 4096 * 4096 * 16, "the texels stay charged");
    // A second one would need the decoder's buffers on top of the first's texels.
    expect_scene_error(
        load_texture_in(&path, ColorSpace::Linear, REPEAT, &large),
        &["on top of 256.0 MiB already loaded"],
    );
}

fn expect_scene_error<T>(result: Result<T, scenes::SceneError>, parts: &[&str]) {
    let Err(e) = result else {
        panic!("expected an error containing {parts:?}")
    };
    let shown = e.to_string();
    for part in parts {
        assert!(shown.contains(part), "error message lacks {part:?}:\n  {shown}");
    }
}

#[test]
fn wrap_modes_are_applied() {
    let dir = scratch("wrap");
    let path = dir.join("ramp.png");
    // Four texels 0, 1, 2, 3 (in units of 1/255, linear).
    image::RgbImage::from_fn(4, 1, |x, _| Rgb([x as u8, 0, 0]))
        .save(&path)
        .unwrap();
    let at = |t: &scenes::texture::Texture, i: i64| (t.texel(i, 0).x * 255.0).round() as i64;
    let cases = [
        (WrapMode::Repeat, [(-1, 3), (4, 0), (5, 1), (-5, 3)]),
        (WrapMode::Clamp, [(-1, 0), (4, 3), (9, 3), (-7, 0)]),
        (WrapMode::Mirror, [(-1, 0), (4, 3), (5, 2), (-5, 3)]),
    ];
    for (mode, expected) in cases {
        let t = load_texture(&path, ColorSpace::Linear, [mode, WrapMode::Clamp]).unwrap();
        assert_eq!(t.wrap, [mode, WrapMode::Clamp]);
        for (i, want) in expected {
            assert_eq!(at(&t, i), want, "{mode:?}: texel {i} should read texel {want}");
        }
    }
}

#[test]
fn scene_texture_inputs() {
    let dir = scratch("scene-textures");
    std::fs::create_dir_all(dir.join("tex")).unwrap();
    image::RgbImage::from_pixel(2, 2, Rgb([128, 64, 32]))
        .save(dir.join("tex/wood.png"))
        .unwrap();
    image::RgbImage::from_pixel(2, 2, Rgb([0, 128, 255]))
        .save(dir.join("tex/orm.png"))
        .unwrap();
    let extra = r#"
[[material]]
name = "wood"
type = "diffuse"
albedo = { texture = "tex/wood.png", factor = [0.5, 1, 1], wrap = ["clamp", "mirror"] }

[[material]]
name = "wood2"
type = "diffuse"
albedo = { texture = "tex/wood.png", factor = 0.5, wrap = ["clamp", "mirror"] }

[[material]]
name = "wood_linear"
type = "phong"
reflectance = { texture = "tex/wood.png", color_space = "linear" }
exponent = 20

[[material]]
name = "rough"
type = "metal_rough"
base_color = 0.9
metallic = { texture = "tex/orm.png" }
roughness = { texture = "tex/orm.png", factor = 0.5 }

[[shape]]
name = "panel"
type = "rectangle"
material = "wood"
center = [0, 0, -2]
size = [1, 1]
normal = [0, 0, 1]
normal_map = { texture = "tex/orm.png", scale = 0.5 }
emission = { radiance = { texture = "tex/wood.png", factor = 3 } }
"#;
    let path = write(&dir, "scene.toml", &format!("{BASE}{extra}"));
    let s = scenes::load(&path).unwrap_or_else(|e| panic!("{e}"));
    // wood.png: sRGB + [clamp, mirror] (shared by two materials), sRGB + repeat (emission),
    // linear + repeat; orm.png: linear + repeat (metallic, roughness and the normal map).
    assert_eq!(
        s.textures.len(),
        4,
        "textures: {:?}",
        s.textures.iter().map(|t| (&t.source, t.wrap)).collect::<Vec<_>>()
    );
    let [wood, wood2, wood_linear, rough] = [1, 2, 3, 4].map(|i| &s.materials[i]);
    let Material::Diffuse {
        albedo: TexRgb::Image { texture, factor },
    } = wood
    else {
        panic!("{wood:?}")
    };
    assert_eq!(*factor, Vec3::new(0.5, 1.0, 1.0));
    assert_eq!(s.textures[*texture].wrap, [WrapMode::Clamp, WrapMode::Mirror]);
    let srgb_128 = srgb_to_linear(128.0 / 255.0);
    assert_texel(
        "sRGB albedo texel",
        s.textures[*texture].texels[0],
        Vec4::new(
            srgb_128,
            srgb_to_linear(64.0 / 255.0),
            srgb_to_linear(32.0 / 255.0),
            1.0,
        ),
        1e-7,
    );
    let Material::Diffuse {
        albedo: TexRgb::Image {
            texture: t2,
            factor: f2,
        },
    } = wood2
    else {
        panic!("{wood2:?}")
    };
    assert_eq!(
        (*t2, *f2),
        (*texture, Vec3::splat(0.5)),
        "the same file and settings load once"
    );
    let Material::Phong {
        reflectance: TexRgb::Image { texture: t3, .. },
        ..
    } = wood_linear
    else {
        panic!("{wood_linear:?}")
    };
    assert_ne!(*t3, *texture);
    assert_texel(
        "linear texel",
        s.textures[*t3].texels[0],
        Vec4::new(128.0 / 255.0, 64.0 / 255.0, 32.0 / 255.0, 1.0),
        1e-7,
    );
    let Material::MetalRough {
        metallic,
        roughness,
        base_color,
        ..
    } = rough
    else {
        panic!("{rough:?}")
    };
    assert_eq!(*base_color, TexRgb::Constant(Vec3::splat(0.9)));
    let (
        TexScalar::Image {
            texture: tm,
            channel: cm,
            factor: fm,
        },
        TexScalar::Image {
            texture: tr,
            channel: cr,
            factor: fr,
        },
    ) = (metallic, roughness)
    else {
        panic!("{metallic:?} {roughness:?}")
    };
    assert_eq!(
        (*cm, *fm, *cr, *fr),
        (2, 1.0, 1, 0.5),
        "glTF channels: metallic B, roughness G"
    );
    assert_eq!(tm, tr);
    // Scalar inputs are linear: G = 128/255 exactly.
    assert_texel(
        "roughness texel",
        s.textures[*tr].texels[0],
        Vec4::new(0.0, 128.0 / 255.0, 1.0, 1.0),
        1e-7,
    );
    let panel = s.shapes.iter().find(|sh| sh.name == "panel").unwrap();
    let nm = panel.normal_map.as_ref().unwrap();
    assert_eq!((nm.texture, nm.scale), (*tr, 0.5));
    let e = panel.emission.as_ref().unwrap();
    let TexRgb::Image {
        texture: te,
        factor: fe,
    } = e.radiance
    else {
        panic!("{e:?}")
    };
    assert_eq!((s.textures[te].wrap, fe), (REPEAT, Vec3::splat(3.0)));
    assert_eq!(s.textures[te].source, dir.join("tex/wood.png"));
}

#[test]
fn texture_inputs_check_their_fields() {
    let dir = scratch("texture-fields");
    image::RgbImage::from_pixel(1, 1, Rgb([1, 2, 3]))
        .save(dir.join("t.png"))
        .unwrap();
    let with = |albedo: &str| {
        BASE.replace(
            "type = \"diffuse\"",
            &format!("type = \"diffuse\"\nalbedo = {albedo}"),
        )
    };
    let run = |text: String| scenes::toml::load_str(&text, &dir.join("bad.toml"));
    expect_error(
        run(with("{ texture = \"t.png\", channel = 1 }")),
        &[
            "bad.toml:9:",
            "`material \"m\".albedo.channel`",
            "unknown field `channel`",
        ],
    );
    expect_error(
        run(with("{ factor = 0.5 }")),
        &["`material \"m\".albedo.texture`", "missing required field"],
    );
    expect_error(
        run(with("{ texture = \"t.png\", factor = 2 }")),
        &["`material \"m\".albedo.factor`", "must lie in [0, 1]"],
    );
    expect_error(
        run(with("{ texture = \"t.png\", color_space = \"rec2020\" }")),
        &[
            "`material \"m\".albedo.color_space`",
            "unknown value \"rec2020\"",
            "`srgb`, `linear`",
        ],
    );
    expect_error(
        run(with("{ texture = 3 }")),
        &[
            "`material \"m\".albedo.texture`",
            "expected a string, found an integer",
        ],
    );
    expect_error(
        run(with("{ texture = \"t.png\", wrap = [\"clamp\"] }")),
        &["`material \"m\".albedo.wrap`", "expected 2 wrap modes"],
    );
}

/// `[environment] negative = "clamp"` sets negative components to 0 and counts the texels it
/// changed, exactly; the default (`"error"`) refuses them in one line; non-finite texels are
/// an error either way.
#[test]
fn environment_negative_texels_are_clamped_and_counted() {
    let dir = scratch("env-negative");
    // 3×2 texels; three have a negative component (one has two, one only just below 0).
    let texels = [
        (0.5f32, 0.5f32, 0.5f32),
        (-0.25, 0.5, 0.5),
        (0.5, -1.0, -2.0),
        (1.0, 1.0, 1.0),
        (0.0, 0.0, -0.001),
        (2.0, 3.0, 4.0),
    ];
    exr::prelude::write_rgb_file(dir.join("neg.exr"), 3, 2, |x, y| texels[3 * y + x]).unwrap();
    let env = |extra: &str| format!("{BASE}\n[environment]\nfile = \"neg.exr\"\n{extra}\n");
    let load = |text: &str| scenes::toml::load_str(text, &dir.join("bad.toml"));

    let s = load(&env("negative = \"clamp\"")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.provenance.clamped_environment_texels, 3);
    let Some(scenes::Environment::Map { texture, .. }) = &s.environment else {
        panic!("{:?}", s.environment)
    };
    let got: Vec<Vec3> = s.textures[*texture].texels.iter().map(|t| t.truncate()).collect();
    let want = [
        Vec3::splat(0.5),
        Vec3::new(0.0, 0.5, 0.5),
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::ONE,
        Vec3::ZERO,
        Vec3::new(2.0, 3.0, 4.0),
    ];
    assert_eq!(got, want);

    for mode in ["", "negative = \"error\""] {
        let e = expect_error(
            load(&env(mode)),
            &[
                "bad.toml:18:",
                "`environment.file`",
                "negative radiance (first at texel (1, 0))",
                "negative = \"clamp\"",
            ],
        );
        assert!(!e.to_string().contains('\n'), "{e}");
    }
    expect_error(
        load(&env("negative = \"zero\"")),
        &["bad.toml:19:", "`environment.negative`", "unknown value \"zero\""],
    );
    expect_error(
        load(&format!(
            "{BASE}\n[environment]\nradiance = 1\nnegative = \"clamp\"\n"
        )),
        &["`environment.negative`", "applies to an environment `file`"],
    );

    // A texture a material also reads (same file, colour space and wrap) is copied before
    // clamping: the material keeps the file's texels.
    let shared = format!(
        "{}\nnegative = \"clamp\"\n\n[[material]]\nname = \"sky\"\ntype = \"diffuse\"\n\
         albedo = {{ texture = \"neg.exr\", wrap = [\"repeat\", \"clamp\"] }}\n",
        env("").trim_end()
    );
    let s = load(&shared).unwrap_or_else(|e| panic!("{e}\n{shared}"));
    let Some(Material::Diffuse {
        albedo: TexRgb::Image { texture: albedo, .. },
    }) = s.materials.last()
    else {
        panic!("{:?}", s.materials)
    };
    let Some(scenes::Environment::Map { texture, .. }) = &s.environment else {
        panic!("{:?}", s.environment)
    };
    assert_ne!(albedo, texture);
    assert_eq!(
        s.textures[*albedo].texels[1].x, -0.25,
        "the material's texels are the file's"
    );
    assert_eq!(s.textures[*texture].texels[1].x, 0.0);
    assert_eq!(s.provenance.clamped_environment_texels, 3);

    // NaN stays an error with clamping.
    exr::prelude::write_rgb_file(dir.join("nan.exr"), 2, 1, |x, _| {
        [(0.5, 0.5, 0.5), (f32::NAN, -1.0, 0.5)][x]
    })
    .unwrap();
    expect_error(
        load(&format!(
            "{BASE}\n[environment]\nfile = \"nan.exr\"\nnegative = \"clamp\"\n"
        )),
        &["`environment.file`", "NaN or infinite"],
    );
}
