//! TOML scene files (format reference: `scenes/README.md`).
//!
//! Loading reads the document into a tree of values that remember their lines
//! ([`tree`]), then reads each section with typed, located accessors ([`read`]), so that
//! every error names the file, the dotted field (`shape "blocker".radius`,
//! `material[2].type`) and the line, and says what to do. Unknown fields, wrong types,
//! non-finite numbers, out-of-range values, degenerate geometry, duplicate names, unknown
//! material names and missing or unreadable files are all errors; nothing panics.

mod displacement;
mod include;
mod inputs;
mod lights;
mod materials;
pub mod overrides;
pub mod read;
mod settings;
mod shapes;
mod transform;
pub mod tree;

use std::collections::{HashMap, HashSet};
use std::path::Path;

use glam::Vec3;
use read::{Ctx, Field};

use crate::budget::Ledger;
use crate::{Camera, Provenance, Scene, SceneError};

/// Top-level sections of a scene file.
const SECTIONS: &[&str] = &[
    "camera",
    "film",
    "render",
    "environment",
    "material",
    "shape",
    "light",
    "include",
];

/// Loads a TOML scene file; relative paths in it are relative to its directory.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_in(path, &Ledger::new())
}

/// [`load`], charging what the scene allocates (textures, displacement heights, included
/// meshes) to `ledger`: over its limit, an error names the field, before the allocation.
pub fn load_in(path: &Path, ledger: &Ledger) -> Result<Scene, SceneError> {
    let text = read_text(path)?;
    let ctx = Ctx::new(path, &text);
    let root = parse_document(&ctx, &text)?;
    from_tree(&ctx, &root, ledger)
}

/// Loads a TOML scene file with some of its fields changed first ([`overrides`]): a bad path
/// is an error naming it (as the `field`), a bad value fails as it would in the file.
pub fn load_with(path: &Path, changes: &[overrides::Override]) -> Result<Scene, SceneError> {
    let text = read_text(path)?;
    let ctx = Ctx::new(path, &text);
    let mut root = parse_document(&ctx, &text)?;
    for o in changes {
        overrides::apply(&mut root, o).map_err(|e| SceneError::new(path, e).field(o.path.clone()))?;
    }
    from_tree(&ctx, &root, &Ledger::new())
}

/// Largest scene file read, bytes: a scene file is text written by people or scripts (the
/// built-in ones are under 20 KB); meshes and images live in their own files.
const MAX_SCENE_FILE_BYTES: u64 = 64 << 20;

/// The 1-based line of the top-level table or field `key` (`film`, `camera`) in the scene
/// file at `path`, for errors found after loading (a film too large for the memory budget);
/// `None` when the file cannot be read or has no such key.
pub fn line_of(path: &Path, key: &str) -> Option<usize> {
    let text = read_text(path).ok()?;
    let ctx = Ctx::new(path, &text);
    let root = parse_document(&ctx, &text).ok()?;
    Field::root(&ctx, &root).table().ok()?.get(key)?.line
}

/// The UTF-8 text of a scene file (a regular file of at most [`MAX_SCENE_FILE_BYTES`]).
fn read_text(path: &Path) -> Result<String, SceneError> {
    let bytes = crate::access::read_regular(path, MAX_SCENE_FILE_BYTES).map_err(|why| {
        let e = SceneError::new(path, format!("cannot read the scene file: it {why}"));
        if path.exists() {
            e
        } else {
            e.hint("check the path")
        }
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        SceneError::new(
            path,
            format!(
                "not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
        .hint("TOML files are UTF-8")
    })?;
    Ok(text)
}

/// Parses TOML `text` (the file of `ctx`) into a located tree; a syntax error names the file
/// and line. Other TOML formats of the project (study files) read their fields through
/// [`read`] like scene files do.
pub fn parse_document(ctx: &Ctx, text: &str) -> Result<tree::Node, SceneError> {
    tree::parse(text).map_err(|e| {
        let mut err = SceneError::new(&ctx.file, syntax_message(e.message(), text));
        if let Some(span) = e.span() {
            err = err.line(ctx.line_of(span.start));
        }
        err
    })
}

/// The parser's message as one line. The `toml` crate reports a table written twice as
/// "invalid table header" with "duplicate key `K`" on a second line: that becomes
/// "duplicate table [K] (first on line N)".
fn syntax_message(message: &str, text: &str) -> String {
    let lines: Vec<&str> = message.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
    let duplicate = lines
        .iter()
        .find_map(|l| l.strip_prefix("duplicate key `"))
        .and_then(|rest| rest.split_once('`'))
        .map(|(key, _)| key);
    if let (Some(key), true) = (duplicate, lines.first() == Some(&"invalid table header")) {
        let header = format!("[{key}]");
        let first = text.lines().position(|l| l.trim() == header).map(|i| i + 1);
        return match first {
            Some(n) => format!("TOML syntax: duplicate table {header} (first on line {n})"),
            None => format!("TOML syntax: duplicate table {header}"),
        };
    }
    format!("TOML syntax: {}", lines.join("; "))
}

/// Loads a scene from TOML text; `path` names it in messages and anchors relative paths
/// (files it references are read from `path`'s directory).
pub fn load_str(text: &str, path: &Path) -> Result<Scene, SceneError> {
    let ctx = Ctx::new(path, text);
    let root = parse_document(&ctx, text)?;
    from_tree(&ctx, &root, &Ledger::new())
}

/// Reads a parsed document (the file of `ctx`).
fn from_tree(ctx: &Ctx, root: &tree::Node, ledger: &Ledger) -> Result<Scene, SceneError> {
    let path = ctx.file.as_path();
    let doc = Field::root(ctx, root).table()?;
    doc.only(SECTIONS, "a scene file")?;
    let section = |key: &str| doc.get(key).map(|f| f.table()).transpose();

    let camera_table = section("camera")?;
    let camera = match &camera_table {
        Some(t) => Some(settings::camera(t)?),
        // An include may give the camera (`camera = true`); else the table is missing.
        None if include::asks_for_camera(&doc)? => None,
        None => Some(settings::camera(&doc.req("camera")?.table()?)?),
    };
    let film = settings::film(section("film")?)?;
    let render = settings::render(section("render")?)?;
    let mut textures = inputs::Textures::new(ledger);
    let (materials, material_names) = materials::read_all(&doc, &mut textures)?;
    let drafts = shapes::read_all(&doc, &material_names, &mut textures)?;
    let lights = lights::read_all(&doc, &mut textures)?;
    let (environment, clamped) = match section("environment")? {
        Some(t) => {
            let (environment, clamped) = settings::environment(&t, &mut textures)?;
            (Some(environment), clamped)
        }
        None => (None, 0),
    };

    let mut names = Names::default();
    let shapes = names.assign(ctx, drafts, &lights)?;
    let mut scene = Scene {
        source: path.to_path_buf(),
        // Until an include gives the camera (`camera` is `None` only when one asks to).
        camera: camera.unwrap_or(Camera::look_at(Vec3::Z, Vec3::ZERO, Vec3::Y, 45.0)),
        film: film.resolve(None)?,
        render,
        textures: textures.list,
        materials,
        shapes,
        lights: lights.into_iter().map(|(l, _)| l).collect(),
        environment,
        provenance: Provenance {
            clamped_environment_texels: clamped,
            ..Provenance::default()
        },
    };
    let mut includes = include::Includes::new(ledger, &material_names, camera_table.as_ref());
    if let Some(list) = doc.get("include") {
        for t in list.tables()? {
            includes.include(&t, &mut scene, &mut names)?;
        }
    }
    if let Some(asset) = includes.camera() {
        scene.camera = asset.camera;
        scene.film = film.resolve(Some(asset))?;
        scene.provenance.camera_aspect = asset.aspect;
    } else if camera.is_none() {
        // Every include that asked for the camera is disabled or says `camera = false`.
        doc.req("camera")?;
    }
    Ok(scene)
}

/// Shape and light names: one namespace, because both name `visibility.<name>` AOVs.
#[derive(Default)]
struct Names {
    /// Name → where it was defined ("shape on line 12").
    used: HashMap<String, String>,
    /// The names included assets brought, which a later include may share (see
    /// [`Names::included`]).
    included: HashSet<String>,
    /// Per included name, the next `#k` suffix to try.
    next: HashMap<String, u64>,
}

impl Names {
    /// Checks the given names (unique, usable as AOV names) and generates `<type>_<index>`
    /// for unnamed shapes, avoiding every given name.
    fn assign(
        &mut self,
        ctx: &Ctx,
        drafts: Vec<shapes::Draft>,
        lights: &[(crate::Light, Option<usize>)],
    ) -> Result<Vec<crate::Shape>, SceneError> {
        let given = drafts
            .iter()
            .filter_map(|d| d.name.as_ref().map(|(n, l)| ("shape", n.as_str(), *l)))
            .chain(lights.iter().map(|(l, line)| ("light", l.name(), *line)));
        for (what, name, line) in given {
            self.claim(ctx, what, name, line)?;
        }
        let mut shapes = Vec::with_capacity(drafts.len());
        for (i, mut d) in drafts.into_iter().enumerate() {
            d.shape.name = match d.name {
                Some((name, _)) => name,
                None => {
                    let mut name = format!("{}_{i}", d.kind);
                    while self.used.contains_key(&name) {
                        name.push('_');
                    }
                    self.used
                        .insert(name.clone(), format!("shape[{i}] (generated name)"));
                    name
                }
            };
            shapes.push(d.shape);
        }
        Ok(shapes)
    }

    /// Registers one given name.
    fn claim(&mut self, ctx: &Ctx, what: &str, name: &str, line: Option<usize>) -> Result<(), SceneError> {
        let at = |e: SceneError| match line {
            Some(l) => e.line(l),
            None => e,
        };
        if !crate::is_identifier(name) {
            let shown = crate::error::echo(name);
            return Err(at(SceneError::new(&ctx.file, format!("invalid {what} name {shown}"))
                .field(format!("{what} {shown}.name"))
                .hint(format!(
                    "names label AOV channels (visibility.<name>) and files: use 1 to {} ASCII letters, digits, '_' and '-'",
                    crate::MAX_NAME_CHARS
                ))));
        }
        let here = match line {
            Some(l) => format!("{what} on line {l}"),
            None => what.to_string(),
        };
        if let Some(first) = self.used.insert(name.to_string(), here) {
            return Err(at(SceneError::new(
                &ctx.file,
                format!("duplicate name \"{name}\" (first used by {first})"),
            )
            .field(format!("{what} \"{name}\".name"))
            .hint("shapes and lights share one namespace; give each its own name")));
        }
        Ok(())
    }

    /// Claims the name of a shape or light (`what`) an included asset brings, described by
    /// `here` ("shape from model.glb"): the name itself or, when an earlier include brought it
    /// (the same asset included twice), `name#2`, `name#3`, … as the glTF loader makes names
    /// unique within one file. A name the scene file itself gives is not shared: the message
    /// says whose it is.
    fn included(&mut self, what: &str, name: &str, here: String) -> Result<String, String> {
        let mut unique = name.to_string();
        if let Some(first) = self.used.get(name) {
            if !self.included.contains(name) {
                return Err(format!(
                    "the included {what} \"{name}\" has the same name as {first}"
                ));
            }
            let next = self.next.entry(name.to_string()).or_insert(2);
            while self.used.contains_key(&unique) {
                unique = format!("{name}#{next}");
                *next += 1;
            }
        }
        self.used.insert(unique.clone(), here);
        self.included.insert(unique.clone());
        Ok(unique)
    }
}
