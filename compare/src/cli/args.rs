//! Argument helpers the subcommands share: scene loading, `--resolution`, `--out FILE.exr`.

use std::path::{Path, PathBuf};

use oracle::memory::Over;
use scenes::budget::Ledger;
use scenes::{Film, Scene};

use super::CliError;

/// Largest width or height `--resolution` accepts.
pub const MAX_RESOLUTION: u32 = 16384;

/// Loads a scene file; a missing or malformed file is bad input (exit 2).
pub fn load_scene(path: &Path) -> Result<Scene, CliError> {
    load_scene_in(path, &Ledger::new())
}

/// [`load_scene`], charging the scene's memory to `ledger`.
pub fn load_scene_in(path: &Path, ledger: &Ledger) -> Result<Scene, CliError> {
    scenes::access::regular_file(path).map_err(|why| CliError::input(format!("{} {why}", path.display())))?;
    scenes::load_in(path, ledger).map_err(|e| CliError::input(e.to_string()))
}

/// The error for a render of `scene` whose memory does not fit the budget (exit 2): a film
/// too large names the `--resolution` flag when it set the film, else the scene file's `film`
/// (with its line); geometry too large names the scene's shapes.
pub fn over_budget(scene_path: &Path, resolution_flag: bool, over: &Over) -> CliError {
    let (key, e) = match over {
        Over::Film(e) if resolution_flag => return CliError::input(format!("--resolution: {e}")),
        Over::Film(e) => ("film", e),
        Over::Geometry(e) => ("shape", e),
    };
    let line = scenes::toml::line_of(scene_path, key)
        .map(|l| format!(":{l}"))
        .unwrap_or_default();
    CliError::input(format!("{}{line}: field `{key}`: {e}", scene_path.display()))
}

/// `WxH` (also `W×H`), each side in 1..=[`MAX_RESOLUTION`].
pub fn parse_resolution(s: &str) -> Result<Film, String> {
    let usage = || format!("expected WIDTHxHEIGHT such as 640x480, each in 1..={MAX_RESOLUTION}");
    let (w, h) = s.split_once(['x', 'X', '×']).ok_or_else(usage)?;
    let side = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=MAX_RESOLUTION).contains(n))
    };
    match (side(w), side(h)) {
        (Some(width), Some(height)) => Ok(Film { width, height }),
        _ => Err(usage()),
    }
}

/// The film of a render: `--resolution` (`flag`) when given, else the scene's. A
/// `--resolution` whose aspect ratio is not the one the scene's camera was made for (a glTF
/// camera's `aspectRatio`) is rendered as asked, and a note on standard error says so.
pub fn film_from_flag(scene: &Scene, flag: Option<Film>) -> Film {
    let Some(film) = flag else {
        return scene.film;
    };
    if let Some(note) = aspect_note(scene, film) {
        eprintln!("{note}");
    }
    film
}

/// The one-line note for a `film` whose aspect ratio differs from the camera's
/// ([`scenes::Provenance::camera_aspect`], up to rounding: [`Film::fits_aspect`]), or `None`.
pub fn aspect_note(scene: &Scene, film: Film) -> Option<String> {
    let camera = scene.provenance.camera_aspect?;
    let used = f64::from(film.width) / f64::from(film.height);
    (!film.fits_aspect(camera)).then(|| {
        format!(
            "{}: note: --resolution {}x{} has the aspect ratio {used:.4}, not the glTF camera's aspectRatio {camera}; \
             rendering at {used:.4} with the camera's vertical field of view",
            scene.source.display(),
            film.width,
            film.height,
        )
    })
}

/// Checks that `--out` `out` is not a directory, creates its directory, and checks that it
/// can be written ([`writable_output`]).
pub fn output_file(out: &Path) -> Result<(), CliError> {
    if out.is_dir() {
        return Err(CliError::input(format!(
            "--out {}: is a directory",
            out.display()
        )));
    }
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            CliError::input(format!(
                "--out {}: cannot create directory {}: {e}",
                out.display(),
                dir.display()
            ))
        })?;
    }
    writable_output(out, &format!("--out {}", out.display()))
}

/// Checks an `--out` EXR path (a `.exr` file, not a directory), creates its directory, and
/// checks that both outputs, the EXR and the PNG preview beside it, can be written
/// ([`writable_output`]), so that a command never renders only to fail at the end or leaves
/// one of them replaced and the other not.
pub fn exr_output(out: PathBuf) -> Result<PathBuf, CliError> {
    let is_exr = out.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if !is_exr || out.file_stem().is_none() {
        return Err(CliError::input(format!(
            "--out {}: the output must be a .exr file (the PNG preview is written beside it)",
            out.display()
        )));
    }
    output_file(&out)?;
    writable_output(
        &out.with_extension("png"),
        &format!("the PNG preview beside --out {}", out.display()),
    )?;
    Ok(out)
}

/// Checks, before any work, that an output file (`role`: what it is, for the message) can be
/// written atomically ([`scenes::atomic::check_writable`]); bad input (exit 2) otherwise:
/// `PATH: is a directory (ROLE); nothing was written`.
pub fn writable_output(path: &Path, role: &str) -> Result<(), CliError> {
    scenes::atomic::check_writable(path)
        .map_err(|e| CliError::input(format!("{e} ({role}); nothing was written")))
}

/// `--spp`: a whole number ≥ 1.
pub fn parse_spp(s: &str) -> Result<u32, String> {
    let n: u32 = s.parse().map_err(|_| "expected a whole number ≥ 1".to_string())?;
    if n == 0 {
        return Err("samples per pixel must be ≥ 1".into());
    }
    Ok(n)
}

/// `--max-depth`: −1 (unbounded) or a depth ≥ 0, Mitsuba's meaning.
pub fn parse_max_depth(s: &str) -> Result<i32, String> {
    match s.parse::<i32>() {
        Ok(d) if d >= -1 => Ok(d),
        _ => Err("expected −1 (unbounded) or a depth ≥ 0".into()),
    }
}

/// `--exposure`: stops in −64..=64.
pub fn parse_exposure(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x.is_finite() && x.abs() <= 64.0 => Ok(x),
        _ => Err("expected a number of stops in −64..=64".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_flags_reject_nonsense() {
        assert_eq!(parse_spp("1"), Ok(1));
        assert!(parse_spp("0").is_err() && parse_spp("-3").is_err() && parse_spp("2.5").is_err());
        assert_eq!(parse_max_depth("-1"), Ok(-1));
        assert!(parse_max_depth("-2").is_err());
        assert!(parse_exposure("nan").is_err() && parse_exposure("-2.5") == Ok(-2.5));
        assert!(parse_exposure("65").is_err());
    }

    /// A `--resolution` of another shape than the glTF camera's `aspectRatio` is noted in one
    /// line naming the scene and the aspect used; one that rounds to it, or a scene whose
    /// camera has no aspect ratio, is not.
    #[test]
    fn a_resolution_of_another_aspect_than_the_camera_is_noted() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        let asset = scenes::load(&root.join("include-asset.toml")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(asset.provenance.camera_aspect, Some(1.5));
        let film = |width, height| Film { width, height };
        assert_eq!(aspect_note(&asset, film(240, 160)), None);
        assert_eq!(aspect_note(&asset, film(25, 17)), None, "25 = round(17 × 1.5)");
        let note = aspect_note(&asset, film(64, 64)).expect("a note");
        assert!(
            note.contains(
                "include-asset.toml: note: --resolution 64x64 has the aspect ratio 1.0000, not the glTF \
                 camera's aspectRatio 1.5; rendering at 1.0000 with the camera's vertical field of view"
            ) && !note.contains('\n'),
            "{note}"
        );
        let plain = scenes::load(&root.join("cornell-box.toml")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(aspect_note(&plain, film(64, 32)), None);
    }

    #[test]
    fn resolutions_parse_and_bad_ones_are_refused() {
        assert_eq!(
            parse_resolution("640x480"),
            Ok(Film {
                width: 640,
                height: 480
            })
        );
        assert_eq!(
            parse_resolution("16×16"),
            Ok(Film {
                width: 16,
                height: 16
            })
        );
        assert_eq!(
            parse_resolution("16384x1"),
            Ok(Film {
                width: 16384,
                height: 1
            })
        );
        for bad in ["", "64", "0x64", "64x0", "16385x1", "-1x4", "axb", "64x64x64"] {
            assert!(parse_resolution(bad).is_err(), "{bad} was accepted");
        }
    }

    #[test]
    fn exr_outputs_must_be_exr_files() {
        assert!(exr_output(PathBuf::from("a.png"))
            .unwrap_err()
            .message
            .contains("must be a .exr file"));
        let dir = std::env::temp_dir().join("verity-args-test.exr");
        std::fs::create_dir_all(&dir).unwrap();
        assert!(exr_output(dir).unwrap_err().message.contains("is a directory"));
    }
}
