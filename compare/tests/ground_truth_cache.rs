//! The ground-truth cache (`compare::study::cache`, used by `run::ground_truth`): an entry is
//! used only when its SHA-256 matches its checksum file and it decodes; a truncated, altered
//! or unchecked entry is rendered again and replaced, never used. Tiny renders (8×8, 2 spp).

use std::path::{Path, PathBuf};

use compare::progress::ProgressMode;
use compare::study::cache::{corrupt_note, Entry, Lookup};
use compare::study::run::{ground_truth, ground_truth_hash, RunOptions};
use scenes::layered::LayeredImage;
use scenes::{Film, PixelFilter, RenderSettings, Scene};
use sha2::{Digest, Sha256};

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("verity-gt-cache-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("report")).unwrap();
    dir
}

/// The Cornell box at 8×8, 2 spp.
fn tiny_scene() -> (Scene, RenderSettings) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box.toml");
    let mut scene = scenes::load(&path).unwrap();
    scene.film = Film { width: 8, height: 8 };
    let settings = RenderSettings {
        spp: 2,
        ..scene.render
    };
    (scene, settings)
}

fn options(dir: &Path) -> RunOptions {
    RunOptions {
        quick: true,
        out_dir: dir.join("report"),
        cache_dir: dir.join("cache"),
        progress: ProgressMode::Quiet,
        only_bounded: false,
    }
}

fn bits(img: &LayeredImage) -> Vec<u32> {
    img.channel("R").unwrap().iter().map(|v| v.to_bits()).collect()
}

fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// Why `entry` is refused; panics if it is used or missing.
fn corruption(entry: &Entry) -> String {
    match entry.read() {
        Lookup::Corrupt(why) => why,
        Lookup::Hit(_) => panic!("a damaged entry was used"),
        Lookup::Missing => panic!("the entry is missing"),
    }
}

#[test]
fn ground_truth_cache_verifies_entries_and_replaces_damaged_ones() {
    let dir = test_dir("verify");
    let (scene, settings) = tiny_scene();
    let opts = options(&dir);

    let (first, info) = ground_truth(&scene, settings, &opts, "ground_truth").unwrap();
    assert!(!info.cached, "an empty cache renders");
    let entry = Entry::new(&opts.cache_dir, &info.hash);
    let exr_name = format!("{}.exr", info.hash);
    let sum_text = std::fs::read_to_string(entry.checksum_path()).unwrap();
    let exr_bytes = std::fs::read(entry.path()).unwrap();
    assert_eq!(
        sum_text,
        format!("{}  {exr_name}\n", sha256_hex(&exr_bytes)),
        "sha256sum format"
    );
    let mut listing: Vec<String> = std::fs::read_dir(&opts.cache_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    listing.sort();
    assert_eq!(listing, [exr_name.clone(), format!("{exr_name}.sha256")]);

    let (again, info) = ground_truth(&scene, settings, &opts, "ground_truth").unwrap();
    assert!(info.cached, "an intact entry is used");
    assert_eq!(bits(&again), bits(&first));

    // Each damage is refused with its reason, then rendered again: not from the cache, the
    // same pixels (the oracle is deterministic), and the entry replaced by a sound one.
    let sum_name = format!("{exr_name}.sha256");
    let mut altered = first.clone();
    altered.channels[0].1[5] += 1.0;
    let damages: [(&str, &dyn Fn(), String); 5] = [
        (
            "truncated",
            &|| std::fs::write(entry.path(), &exr_bytes[..exr_bytes.len() / 2]).unwrap(),
            format!("its SHA-256 does not match the one recorded in {sum_name}"),
        ),
        (
            "altered and still decodable",
            &|| altered.write_exr(entry.path()).unwrap(),
            format!("its SHA-256 does not match the one recorded in {sum_name}"),
        ),
        (
            "no checksum file",
            &|| std::fs::remove_file(entry.checksum_path()).unwrap(),
            format!("no checksum file {sum_name}"),
        ),
        (
            "checksum file of garbage",
            &|| std::fs::write(entry.checksum_path(), "not a digest\n").unwrap(),
            format!("checksum file {sum_name} holds no SHA-256"),
        ),
        (
            "undecodable with a matching checksum",
            &|| {
                std::fs::write(entry.path(), b"not an EXR").unwrap();
                let sum = format!("{}  {exr_name}\n", sha256_hex(b"not an EXR"));
                std::fs::write(entry.checksum_path(), sum).unwrap();
            },
            "it does not decode: not a valid EXR file".to_string(),
        ),
    ];
    for (what, damage, reason) in damages {
        damage();
        let why = corruption(&entry);
        assert!(why.starts_with(&reason), "{what}: expected `{reason}` in `{why}`");
        let (img, info) = ground_truth(&scene, settings, &opts, "ground_truth").unwrap();
        assert!(!info.cached, "{what}: a damaged entry must not count as cached");
        assert_eq!(bits(&img), bits(&first), "{what}: the ground truth changed");
        assert!(
            matches!(entry.read(), Lookup::Hit(_)),
            "{what}: the entry was not replaced"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn ground_truth_cache_note_names_the_entry_and_the_reason() {
    let entry = Entry::new(Path::new("out/cache"), "abc");
    assert_eq!(
        corrupt_note(&entry, "no checksum file abc.exr.sha256"),
        "note: cache entry out/cache/abc.exr is corrupt (no checksum file abc.exr.sha256); \
         rendering the ground truth again"
    );
    assert!(matches!(entry.read(), Lookup::Missing));
}

/// The pixel filter and its sub-pixel grid are part of the cache key: a box ground truth is
/// never reused for a centre one, nor a centre one for another K; each is rendered with its own
/// filter (the EXR header says which) and found again under its own key.
#[test]
fn ground_truth_cache_keys_the_pixel_filter() {
    let dir = test_dir("pixel-filter");
    let (scene, settings) = tiny_scene();
    let opts = options(&dir);
    let filters = [
        PixelFilter::Box,
        PixelFilter::Centre { ssaa: 1 },
        PixelFilter::Centre { ssaa: 2 },
    ];
    let mut hashes = Vec::new();
    for filter in filters {
        let s = RenderSettings {
            spp: 4,
            pixel_filter: filter,
            ..settings
        };
        let (img, info) = ground_truth(&scene, s, &opts, "ground_truth").unwrap();
        assert!(!info.cached, "{filter:?} was served another filter's entry");
        assert_eq!(info.hash, ground_truth_hash(&scene, &s));
        assert_eq!(info.pixel_filter, filter.describe());
        assert_eq!(img.attribute("pixel_filter"), Some(filter.name()));
        hashes.push(info.hash);
    }
    assert_eq!(filters.map(|f| f.describe()), ["box", "centre", "centre 2x2"]);
    for filter in filters {
        let s = RenderSettings {
            spp: 4,
            pixel_filter: filter,
            ..settings
        };
        let (_, info) = ground_truth(&scene, s, &opts, "ground_truth").unwrap();
        assert!(info.cached, "{filter:?} is found again");
    }
    hashes.sort();
    hashes.dedup();
    assert_eq!(hashes.len(), 3, "one key per filter");
    std::fs::remove_dir_all(&dir).unwrap();
}
