//! Atomic writes: a failed write leaves the old file as it was and no temporary file behind.

use std::io::Write;
use std::path::{Path, PathBuf};

use scenes::layered::{write_atomic, write_atomic_with, LayeredImage};

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("verity-layered-atomic-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Names of every entry in `dir`, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn image(value: f32) -> LayeredImage {
    let mut img = LayeredImage::new(4, 3);
    for c in ["R", "G", "B"] {
        img.push_channel(c, vec![value; 12]);
    }
    img
}

#[test]
fn layered_atomic_write_replaces_whole_file() {
    let dir = test_dir("replace");
    let path = dir.join("a.txt");
    write_atomic(&path, b"first version, longer than the second").unwrap();
    write_atomic(&path, b"second").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"second");
    assert_eq!(entries(&dir), ["a.txt"], "no temporary file may remain");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn layered_atomic_failing_write_keeps_old_file() {
    let dir = test_dir("fail");
    let path = dir.join("a.bin");
    write_atomic(&path, b"old").unwrap();
    let err = write_atomic_with(&path, |w| {
        w.write_all(&[7u8; 100_000])?;
        Err(std::io::Error::other("disk on fire"))
    })
    .unwrap_err();
    assert!(err.to_string().contains("disk on fire"), "{err}");
    assert!(
        err.to_string().contains("a.bin"),
        "error must name the file: {err}"
    );
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    assert_eq!(entries(&dir), ["a.bin"], "the temporary file must be removed");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn layered_atomic_invalid_exr_write_keeps_old_exr() {
    let dir = test_dir("exr");
    let path = dir.join("img.exr");
    image(0.5).write_exr(&path).unwrap();
    let before = std::fs::read(&path).unwrap();

    let mut bad_length = image(1.0);
    bad_length.channels[1].1.pop();
    let mut reserved = image(1.0);
    reserved.set_attribute("channels", "R,G,B");
    let mut duplicate = image(1.0);
    duplicate.channels.push(("R".into(), vec![0.0; 12]));
    let cases = [
        ("short channel", bad_length, "channel `G` has 11 values"),
        ("reserved attribute", reserved, "attribute `channels` is reserved"),
        ("duplicate channel", duplicate, "channel `R` appears twice"),
        ("empty image", LayeredImage::new(0, 3), "is empty"),
        ("no channels", LayeredImage::new(2, 2), "no channels"),
    ];
    for (what, img, expected) in cases {
        let err = img.write_exr(&path).expect_err(what).to_string();
        assert!(err.contains(expected), "{what}: expected `{expected}` in `{err}`");
        assert!(err.contains("img.exr"), "{what}: error must name the file: {err}");
        assert_eq!(std::fs::read(&path).unwrap(), before, "{what}: old file changed");
        assert_eq!(entries(&dir), ["img.exr"], "{what}: temporary file left");
    }
    assert_eq!(
        LayeredImage::read_exr(&path).unwrap().channel("R").unwrap()[0],
        0.5
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn layered_atomic_missing_directory_is_an_error_naming_the_file() {
    let dir = test_dir("nodir");
    let path = dir.join("does-not-exist").join("img.exr");
    let err = image(0.5).write_exr(&path).unwrap_err().to_string();
    assert!(err.contains("img.exr"), "{err}");
    let err = image(0.5)
        .write_png_preview(path.with_extension("png"), 0.0)
        .unwrap_err();
    assert!(err.to_string().contains("img.png"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
