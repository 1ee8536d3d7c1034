//! EXR round trip of `LayeredImage`: exact float32 values, attributes, foreign files, and
//! clear errors (never a panic) on malformed input.

use std::path::PathBuf;

use glam::Vec3;
use scenes::layered::LayeredImage;

/// A fresh, empty directory for one test.
fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("verity-layered-exr-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Values that a lossy or sloppy writer would change: NaN payloads, signed zero, infinities,
/// subnormals, extremes, and ordinary numbers with all mantissa bits used.
fn tricky_values(n: usize, seed: u32) -> Vec<f32> {
    let specials = [
        f32::from_bits(0x7fc0_1234),
        -0.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::from_bits(1),
        f32::MIN_POSITIVE,
        f32::MAX,
        -f32::MAX,
        1.0 / 3.0,
    ];
    (0..n)
        .map(|i| match specials.get(i) {
            Some(&v) => v,
            None => {
                // A hash of (i, seed) reinterpreted as a finite float: every bit pattern differs.
                let h = (i as u32 ^ seed).wrapping_mul(0x9e37_79b9).rotate_left(13) ^ seed;
                let v = f32::from_bits(h & 0x7f7f_ffff);
                if i % 2 == 0 {
                    v
                } else {
                    -v
                }
            }
        })
        .collect()
}

fn sample_image() -> LayeredImage {
    let (w, h) = (7u32, 5u32);
    let n = (w * h) as usize;
    let mut img = LayeredImage::new(w, h);
    let rgb: Vec<Vec3> = (0..n).map(|i| Vec3::new(i as f32, 0.5, -2.25)).collect();
    img.push_rgb("", &rgb);
    img.push_channel("R", tricky_values(n, 1));
    img.push_rgb("variance", &rgb);
    img.push_rgb("albedo", &rgb);
    img.push_xyz("normal", &rgb);
    img.push_channel("depth.Z", tricky_values(n, 2));
    img.push_channel("object_id.Y", (0..n).map(|i| (i % 3) as f32).collect());
    img.push_channel("visibility.sun lamp.Y", tricky_values(n, 3));
    img.push_channel(
        "visibility.a_light_with_a_name_longer_than_31_bytes.Y",
        vec![0.25; n],
    );
    img.set_attribute("scene", "scenes/cornell-box.toml");
    img.set_attribute("integrator", "path");
    img.set_attribute("software", "verity 0.1.0");
    img.set_attribute("comments", "made by a test");
    img.set_attribute("command_line", "verity render 'my scene.toml' --spp 4");
    img.set_attribute("an_attribute_name_longer_than_31_bytes", "Ünïcode ✓");
    img.set_attribute("empty", "");
    img
}

fn assert_bitwise_equal(expected: &LayeredImage, actual: &LayeredImage) {
    assert_eq!(
        (expected.width, expected.height),
        (actual.width, actual.height),
        "size"
    );
    let mut names_e: Vec<&str> = expected.channels.iter().map(|(n, _)| n.as_str()).collect();
    let mut names_a: Vec<&str> = actual.channels.iter().map(|(n, _)| n.as_str()).collect();
    names_e.sort_unstable();
    names_a.sort_unstable();
    assert_eq!(names_e, names_a, "channel names");
    for (name, data) in &expected.channels {
        let got = actual.channel(name).unwrap();
        for (i, (e, a)) in data.iter().zip(got).enumerate() {
            assert_eq!(
                e.to_bits(),
                a.to_bits(),
                "channel {name} value {i}: expected {e:e} ({:#010x}), got {a:e} ({:#010x})",
                e.to_bits(),
                a.to_bits()
            );
        }
    }
    let mut attrs = expected.attributes.clone();
    attrs.sort();
    assert_eq!(attrs, actual.attributes, "attributes (read back sorted by name)");
}

#[test]
fn layered_exr_round_trip_is_bit_exact_with_attributes() {
    let dir = test_dir("round-trip");
    let path = dir.join("image.exr");
    let img = sample_image();
    img.write_exr(&path).unwrap();
    let back = LayeredImage::read_exr(&path).unwrap();
    assert_bitwise_equal(&img, &back);
    // Channels come back sorted by name, as OpenEXR stores them.
    let names: Vec<&str> = back.channels.iter().map(|(n, _)| n.as_str()).collect();
    let mut sorted = names.clone();
    sorted.sort_unstable();
    assert_eq!(names, sorted);
    // A second round trip reproduces the first read exactly.
    let path2 = dir.join("image2.exr");
    back.write_exr(&path2).unwrap();
    assert_bitwise_equal(&back, &LayeredImage::read_exr(&path2).unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn layered_exr_accessors() {
    let img = sample_image();
    let rgb = img.rgb("albedo").unwrap();
    assert_eq!(rgb[3], Vec3::new(3.0, 0.5, -2.25));
    assert_eq!(img.xyz("normal").unwrap()[4], Vec3::new(4.0, 0.5, -2.25));
    assert!(img.rgb("normal").is_none(), "normal has X/Y/Z, not R/G/B");
    assert!(img.xyz("missing").is_none());
    assert_eq!(img.attribute("integrator"), Some("path"));
    // Pushing an existing name replaces the data in place.
    let mut img2 = img.clone();
    let before: Vec<String> = img2.channels.iter().map(|(n, _)| n.clone()).collect();
    img2.push_channel("G", vec![9.0; img.pixel_count()]);
    img2.set_attribute("integrator", "ao");
    let after: Vec<String> = img2.channels.iter().map(|(n, _)| n.clone()).collect();
    assert_eq!(before, after);
    assert_eq!(img2.channel("G").unwrap()[0], 9.0);
    assert_eq!(img2.attribute("integrator"), Some("ao"));
    assert_eq!(img2.attributes.len(), img.attributes.len());
}

#[test]
#[should_panic(expected = "channel `R` has 3 values, the 2x2 image needs 4")]
fn layered_exr_push_channel_checks_length() {
    LayeredImage::new(2, 2).push_channel("R", vec![0.0; 3]);
}

#[test]
fn layered_exr_reads_half_and_uint_channels_and_named_parts() {
    use exr::prelude::*;
    let dir = test_dir("foreign");
    let path = dir.join("foreign.exr");
    let size = Vec2(3, 2);
    let half: Vec<f16> = [0.5f32, 1.0, -2.0, 65504.0, 0.0, 0.25]
        .iter()
        .map(|&v| f16::from_f32(v))
        .collect();
    let beauty = Layer::new(
        size,
        LayerAttributes::named("beauty"),
        Encoding::SMALL_FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(vec![
            AnyChannel::new("R", FlatSamples::F16(half.clone())),
            AnyChannel::new("id", FlatSamples::U32(vec![0, 1, 2, 3, 4, 4_000_000])),
        ])),
    );
    let mut attrs = LayerAttributes::named("aov");
    attrs.owner = Some(Text::from("someone"));
    attrs
        .other
        .insert(Text::from("note"), AttributeValue::Text(Text::from("hi")));
    attrs.other.insert(Text::from("number"), AttributeValue::F32(1.5));
    let aov = Layer::new(
        size,
        attrs,
        Encoding::UNCOMPRESSED,
        AnyChannels::sort(SmallVec::from_vec(vec![AnyChannel::new(
            "Z",
            FlatSamples::F32(vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
        )])),
    );
    Image::from_layers(
        ImageAttributes::new(IntegerBounds::from_dimensions(size)),
        vec![beauty, aov],
    )
    .write()
    .to_file(&path)
    .unwrap();

    let img = LayeredImage::read_exr(&path).unwrap();
    assert_eq!((img.width, img.height), (3, 2));
    assert_eq!(
        img.channel("beauty.R").unwrap(),
        &[0.5, 1.0, -2.0, 65504.0, 0.0, 0.25]
    );
    assert_eq!(
        img.channel("beauty.id").unwrap(),
        &[0.0, 1.0, 2.0, 3.0, 4.0, 4_000_000.0]
    );
    assert_eq!(img.channel("aov.Z").unwrap(), &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    assert_eq!(img.attribute("owner"), Some("someone"));
    assert_eq!(img.attribute("note"), Some("hi"));
    assert_eq!(img.attribute("number"), None, "only text attributes are kept");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn layered_exr_malformed_files_give_errors_naming_the_file() {
    let dir = test_dir("malformed");
    let good = dir.join("good.exr");
    sample_image().write_exr(&good).unwrap();
    let bytes = std::fs::read(&good).unwrap();

    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("empty.exr", Vec::new()),
        ("text.exr", b"this is not an EXR file at all".to_vec()),
        ("magic-only.exr", bytes[..4].to_vec()),
        ("header-cut.exr", bytes[..bytes.len() / 8].to_vec()),
        ("pixels-cut.exr", bytes[..bytes.len() - 16].to_vec()),
    ];
    for (name, data) in cases {
        let path = dir.join(name);
        std::fs::write(&path, &data).unwrap();
        let err = LayeredImage::read_exr(&path).expect_err(name);
        assert!(
            err.contains(name),
            "error for {name} does not name the file: {err}"
        );
    }

    // Every truncation and many single-byte corruptions: an error or an image, never a panic.
    let cut = dir.join("cut.exr");
    for len in (0..bytes.len()).step_by(7) {
        std::fs::write(&cut, &bytes[..len]).unwrap();
        assert!(
            LayeredImage::read_exr(&cut).is_err(),
            "file cut at {len} bytes was accepted"
        );
    }
    for pos in (0..bytes.len()).step_by(5) {
        let mut corrupt = bytes.clone();
        corrupt[pos] ^= 0xa5;
        std::fs::write(&cut, &corrupt).unwrap();
        let _ = LayeredImage::read_exr(&cut);
    }

    let missing = dir.join("missing.exr");
    let err = LayeredImage::read_exr(&missing).unwrap_err();
    assert!(err.contains("missing.exr"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Files written by the reference implementation (Python `OpenEXR` 3.5.3, i.e. OpenEXR 3.x):
///
/// ```python
/// R = (np.arange(12, dtype=np.float16).reshape(3, 4) - 4) / 8
/// h = {"compression": OpenEXR.PIZ_COMPRESSION, "type": OpenEXR.scanlineimage,
///      "note": "written by OpenEXR 3.5.3"}
/// OpenEXR.File(h, {"R": R, "G": R * 2, "B": R * 3,
///     "depth.Z": np.full((3, 4), 2.5, dtype=np.float32),
///     "id.Y": np.arange(12, dtype=np.uint32).reshape(3, 4)}).write("layered_openexr_piz.exr")
/// # and two ZIP parts "left" (Y = 1) and "right" (Y = 0), 3x2: layered_openexr_parts.exr
/// ```
#[test]
fn layered_exr_reads_files_written_by_openexr() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests");
    let img = LayeredImage::read_exr(dir.join("layered_openexr_piz.exr")).unwrap();
    assert_eq!((img.width, img.height), (4, 3));
    let expected_r: Vec<f32> = (0..12).map(|i| (i as f32 - 4.0) / 8.0).collect();
    assert_eq!(img.channel("R").unwrap(), expected_r.as_slice());
    let expected_b: Vec<f32> = expected_r.iter().map(|r| r * 3.0).collect();
    assert_eq!(img.channel("B").unwrap(), expected_b.as_slice());
    assert_eq!(img.channel("depth.Z").unwrap(), &[2.5; 12]);
    let ids: Vec<f32> = (0..12).map(|i| i as f32).collect();
    assert_eq!(img.channel("id.Y").unwrap(), ids.as_slice());
    assert_eq!(img.attribute("note"), Some("written by OpenEXR 3.5.3"));

    let parts = LayeredImage::read_exr(dir.join("layered_openexr_parts.exr")).unwrap();
    assert_eq!((parts.width, parts.height), (3, 2));
    assert_eq!(parts.channel("left.Y").unwrap(), &[1.0; 6]);
    assert_eq!(parts.channel("right.Y").unwrap(), &[0.0; 6]);
}
