//! Atomic writes: a failed write leaves the old file as it was and no temporary file behind.

use std::io::Write;
use std::path::{Path, PathBuf};

use scenes::atomic::check_writable;
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

/// A writer killed mid-write (SIGKILL runs no clean-up) leaves its hidden temporary file; the
/// next write of the same file removes it once its process is gone, and leaves alone the
/// temporary files of live writers and of other files.
#[cfg(target_os = "linux")]
#[test]
fn layered_atomic_write_removes_leftovers_of_killed_writers() {
    let dir = test_dir("leftover");
    // Linux process ids stay below 2^22 (proc(5), /proc/sys/kernel/pid_max): 99999999 is
    // never running; process 1 always is.
    let dead = ".img.exr.99999999.0.tmp";
    let live = ".img.exr.1.0.tmp";
    let other_file = ".other.exr.99999999.0.tmp";
    let not_ours = ".img.exr.99999999.tmp";
    for name in [dead, live, other_file, not_ours] {
        std::fs::write(dir.join(name), b"half a file").unwrap();
    }
    image(0.5).write_exr(dir.join("img.exr")).unwrap();
    assert_eq!(
        entries(&dir),
        [live, not_ours, other_file, "img.exr"],
        "only the dead writer's temporary file of img.exr goes"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A symbolic link is written through: its target is replaced, the link stays a link.
#[cfg(unix)]
#[test]
fn layered_atomic_write_through_symbolic_links() {
    use std::os::unix::fs::symlink;
    let dir = test_dir("symlink");
    std::fs::create_dir(dir.join("real")).unwrap();
    let target = dir.join("real").join("a.bin");
    write_atomic(&target, b"old").unwrap();
    symlink("real/a.bin", dir.join("link.bin")).unwrap();
    symlink("link.bin", dir.join("link2.bin")).unwrap();
    write_atomic(dir.join("link2.bin"), b"new").unwrap();
    assert_eq!(std::fs::read(&target).unwrap(), b"new");
    for link in ["link.bin", "link2.bin"] {
        let meta = std::fs::symlink_metadata(dir.join(link)).unwrap();
        assert!(meta.file_type().is_symlink(), "{link} was replaced by a file");
    }
    assert_eq!(entries(&dir.join("real")), ["a.bin"], "temporary file left");

    // A dangling link: the write creates its target.
    symlink("real/b.bin", dir.join("dangling.bin")).unwrap();
    write_atomic(dir.join("dangling.bin"), b"created").unwrap();
    assert_eq!(std::fs::read(dir.join("real/b.bin")).unwrap(), b"created");
    assert!(std::fs::symlink_metadata(dir.join("dangling.bin"))
        .unwrap()
        .file_type()
        .is_symlink());

    // A loop of links is an error naming the file, not a hang.
    symlink("loop2.bin", dir.join("loop1.bin")).unwrap();
    symlink("loop1.bin", dir.join("loop2.bin")).unwrap();
    let err = write_atomic(dir.join("loop1.bin"), b"x").unwrap_err().to_string();
    assert!(
        err.contains("loop1.bin") && err.contains("more than 40 symbolic links"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `check_writable` refuses, before any work, what a write could not replace, naming the
/// file, and writes nothing.
#[test]
fn layered_atomic_check_writable_refuses_before_anything_is_written() {
    let dir = test_dir("check");
    std::fs::create_dir(dir.join("a.png")).unwrap();
    write_atomic(dir.join("old.exr"), b"old").unwrap();
    check_writable(dir.join("old.exr")).unwrap();
    check_writable(dir.join("new.exr")).unwrap();
    let err = check_writable(dir.join("a.png")).unwrap_err().to_string();
    assert_eq!(err, format!("{}: is a directory", dir.join("a.png").display()));
    let missing = dir.join("nowhere").join("x.exr");
    let err = check_writable(&missing).unwrap_err().to_string();
    assert_eq!(
        err,
        format!(
            "{}: directory {} does not exist",
            missing.display(),
            dir.join("nowhere").display()
        )
    );
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("a.png", dir.join("b.png")).unwrap();
        let err = check_writable(dir.join("b.png")).unwrap_err().to_string();
        assert_eq!(
            err,
            format!(
                "{}: is a directory (the target of the link, {})",
                dir.join("b.png").display(),
                dir.join("a.png").display()
            )
        );
    }
    let mut expected = vec!["a.png", "old.exr"];
    if cfg!(unix) {
        expected.push("b.png");
    }
    expected.sort();
    assert_eq!(entries(&dir), expected, "a check writes nothing");
    assert_eq!(std::fs::read(dir.join("old.exr")).unwrap(), b"old");
    std::fs::remove_dir_all(&dir).unwrap();
}
