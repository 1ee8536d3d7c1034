//! `[[include]]`: glTF assets in a scene file (format: scenes/README.md, "[[include]]").
//!
//! | field | what it does | where |
//! |---|---|---|
//! | `file` | the asset; read once per scene load however often it is included | [`Includes::place`] |
//! | `transform` | the shape transform steps ([`super::transform`]) placed above the asset's root nodes: meshes (normals by the inverse transpose, tangents, winding under a mirroring map), lights and cameras move as under a glTF node transform | [`crate::gltf::Parsed::place`] |
//! | `materials` | primitives' glTF materials replaced by the scene file's own | [`replace_materials`] |
//! | `camera` | the scene's camera (and its film's shape) taken from the asset | [`pick_camera`] |
//! | `displacement` | every mesh displaced | [`super::displacement::include`] |
//!
//! Sharing: a file is read once per scene load (keyed by its canonical path and its
//! `allow_paths_outside`), so its bytes, buffers, materials and decoded textures are read and
//! charged to the memory budget once; the scene holds its textures once
//! ([`crate::Scene::merge`]). Meshes live in world space, so each transform builds its own;
//! includes with the same transform share their meshes (`Arc`) and charge them once.

use std::collections::hash_map::Entry;
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};

use glam::Mat4;

use super::read::{Field, Table};
use super::{displacement, shapes, transform, Names};
use crate::budget::Ledger;
use crate::error::echo;
use crate::glob;
use crate::gltf::{AssetCamera, Loaded, Options, Parsed, Part};
use crate::{Scene, SceneError, Shape};

const FIELDS: &[&str] = &[
    "file",
    "transform",
    "materials",
    "camera",
    "displacement",
    "enabled",
    "allow_paths_outside",
];

/// Most names of each kind (material, mesh, node) an error lists.
const LISTED_NAMES: usize = 8;

/// Whether an include of the document sets `camera` (then `[camera]` may be left out).
pub(super) fn asks_for_camera(doc: &Table) -> Result<bool, SceneError> {
    let Some(list) = doc.get("include") else {
        return Ok(false);
    };
    Ok(list.tables()?.iter().any(|t| t.has("camera")))
}

/// The includes of one scene file, in order: the assets read so far and the camera taken.
pub(super) struct Includes<'a> {
    ledger: &'a Ledger,
    /// The scene file's materials by name (what `materials` values name).
    materials: &'a HashMap<String, usize>,
    /// The scene file's `[camera]` table, if it has one.
    camera_table: Option<&'a Table<'a>>,
    /// Assets by (canonical path, `allow_paths_outside`).
    files: HashMap<(PathBuf, bool), File<'a>>,
    /// The camera an include took, with that include's `camera` field path.
    camera: Option<(String, AssetCamera)>,
}

/// One asset file, read, with its placements so far.
struct File<'a> {
    parsed: Parsed<'a>,
    /// Placements by the bits of their column-major matrix.
    placed: Vec<([u32; 16], Loaded)>,
    /// Notes printed already.
    printed: BTreeSet<String>,
}

impl<'a> Includes<'a> {
    /// No includes yet; assets charge `ledger`, `materials` are the scene file's.
    pub fn new(
        ledger: &'a Ledger,
        materials: &'a HashMap<String, usize>,
        camera_table: Option<&'a Table<'a>>,
    ) -> Self {
        Includes {
            ledger,
            materials,
            camera_table,
            files: HashMap::new(),
            camera: None,
        }
    }

    /// The camera an include took (`camera = true` or a name).
    pub fn camera(&self) -> Option<&AssetCamera> {
        self.camera.as_ref().map(|(_, c)| c)
    }

    /// One `[[include]]` table: places the asset, appends its materials, textures, shapes and
    /// lights to `scene` (names claimed in `names`), then replaces materials, takes the camera
    /// and displaces meshes as the table says.
    pub fn include(&mut self, t: &Table, scene: &mut Scene, names: &mut Names) -> Result<(), SceneError> {
        t.only(FIELDS, "an include")?;
        if !t.bool_or("enabled", true)? {
            return Ok(());
        }
        let file = t.req("file")?;
        let path = file.ctx.resolve(file.str()?);
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("gltf" | "glb")) {
            return Err(file
                .err(format!("cannot include {}", path.display()))
                .hint("includes are glTF 2.0 assets (.gltf or .glb)"));
        }
        file.input_file(&path)?;
        let to_world = match t.get("transform") {
            Some(f) => Mat4::from(transform::read(&f)?),
            None => Mat4::IDENTITY,
        };
        let camera = match t.get("camera") {
            Some(f) => self.camera_wanted(&f)?.then_some(f),
            None => None,
        };
        let outside = t.bool_or("allow_paths_outside", false)?;
        let mut loaded = self.place(&file, &path, outside, to_world)?;
        let shape_names = loaded.scene.shapes.iter_mut().map(|s| ("shape", &mut s.name));
        let light_names = loaded.scene.lights.iter_mut().map(|l| ("light", l.name_mut()));
        for (what, name) in shape_names.chain(light_names) {
            let here = format!("{what} from {}", path.display());
            *name = names.included(what, name, here).map_err(|message| {
                file.err(message)
                    .hint("shapes and lights share one namespace; rename one of them")
            })?;
        }
        let first_new = scene.shapes.len();
        let cameras = std::mem::take(&mut loaded.cameras);
        scene.merge(loaded.scene);
        if let Some(f) = t.get("materials") {
            replace_materials(
                &f,
                &path,
                &loaded.parts,
                &mut scene.shapes[first_new..],
                self.materials,
            )?;
        }
        if let Some(f) = camera {
            self.camera = Some((f.path.clone(), pick_camera(&f, &path, &cameras)?));
        }
        if let Some(d) = t.get("displacement") {
            displacement::include(&d, scene, first_new, self.ledger)?;
        }
        Ok(())
    }

    /// Reads `camera = true | false | "name"`: whether the include asks for the asset's
    /// camera. Asking is an error when the scene file has a `[camera]` table or an earlier
    /// include took the camera.
    fn camera_wanted(&self, f: &Field) -> Result<bool, SceneError> {
        let wanted = match f.bool() {
            Ok(b) => b,
            Err(_) => {
                f.str().map_err(|_| {
                    f.err(format!(
                        "expected true, false or a camera name, found {}",
                        f.node.value.kind()
                    ))
                })?;
                true
            }
        };
        if !wanted {
            return Ok(false);
        }
        if let Some(table) = self.camera_table {
            let at = table.line.map(|l| format!(" on line {l}")).unwrap_or_default();
            return Err(f
                .err(format!("the scene file has a [camera] table{at} as well"))
                .hint("keep one camera: remove [camera] to use the asset's, or remove `camera` here"));
        }
        if let Some((first, _)) = &self.camera {
            return Err(f
                .err(format!("`{first}` already takes the asset camera"))
                .hint("a scene has one camera; ask for it on one include"));
        }
        Ok(true)
    }

    /// The asset at `path` placed by `to_world`: read on its first include (reading only
    /// inside its own folder or the scene file's, unless `outside`), placed once per
    /// transform. Notes are printed once per file.
    fn place(
        &mut self,
        file: &Field,
        path: &Path,
        outside: bool,
        to_world: Mat4,
    ) -> Result<Loaded, SceneError> {
        let origin = |e: SceneError| {
            if e.hint.is_some() {
                return e;
            }
            let line = file.line.map(|l| format!(":{l}")).unwrap_or_default();
            e.hint(format!(
                "included from {}{line} ({})",
                file.ctx.file.display(),
                file.path
            ))
        };
        let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        let entry = match self.files.entry((canonical, outside)) {
            Entry::Occupied(o) => o.into_mut(),
            Entry::Vacant(v) => {
                let options = Options {
                    also_inside: file.ctx.file.parent().map(Path::to_path_buf),
                    allow_paths_outside: outside,
                    ..Options::new(self.ledger)
                };
                v.insert(File {
                    parsed: Parsed::read(path, &options).map_err(origin)?,
                    placed: Vec::new(),
                    printed: BTreeSet::new(),
                })
            }
        };
        let bits = to_world.to_cols_array().map(f32::to_bits);
        let loaded = match entry.placed.iter().find(|(b, _)| *b == bits) {
            Some((_, loaded)) => loaded.clone(),
            None => {
                let loaded = entry.parsed.place(to_world).map_err(origin)?;
                entry.placed.push((bits, loaded.clone()));
                loaded
            }
        };
        loaded.print_new_notes(&mut entry.printed);
        Ok(loaded)
    }
}

/// One `materials` entry: a name or pattern and the scene material it gives.
struct Rule<'f> {
    key: &'f str,
    pattern: bool,
    material: usize,
    field: Field<'f>,
}

/// `materials = { "<name or pattern>" = "<scene material>", … }` on the shapes an include
/// added (`parts` says where each came from). A primitive takes the entry naming, in this
/// order, its node, its mesh, its glTF material; failing those, the first pattern (`*`, `?`:
/// [`glob`]) in the order written that matches one of those names (an unnamed one is "").
/// The replaced primitive renders with the scene material alone: the emission and normal
/// map its glTF material gave are dropped with it. Primitives no entry matches keep their
/// own material. Every entry must match some primitive, and name a scene material.
fn replace_materials(
    f: &Field,
    asset: &Path,
    parts: &[Part],
    shapes: &mut [Shape],
    known: &HashMap<String, usize>,
) -> Result<(), SceneError> {
    let t = f.table()?;
    let mut rules = Vec::new();
    for (key, field) in t.fields() {
        if key.is_empty() {
            return Err(field
                .err("an empty key names no material, mesh or node")
                .hint("write \"*\" for every primitive"));
        }
        rules.push(Rule {
            key,
            pattern: glob::is_pattern(key),
            material: shapes::material_index(&field, known)?,
            field,
        });
    }
    let mut matched = vec![false; rules.len()];
    for (shape, part) in shapes.iter_mut().zip(parts) {
        let names = [&part.node, &part.mesh, &part.material].map(|n| n.as_deref().unwrap_or(""));
        let hits = |r: &Rule| {
            if r.pattern {
                names.iter().any(|n| glob::matches(r.key, n))
            } else {
                names.contains(&r.key)
            }
        };
        for (m, r) in matched.iter_mut().zip(&rules) {
            *m = *m || hits(r);
        }
        let exact = names
            .iter()
            .find_map(|n| rules.iter().find(|r| !r.pattern && r.key == *n));
        let chosen = exact.or_else(|| rules.iter().find(|r| r.pattern && hits(r)));
        if let Some(r) = chosen {
            shape.material = r.material;
            shape.emission = None;
            shape.normal_map = None;
        }
    }
    match rules.iter().zip(&matched).find(|(_, m)| !**m) {
        Some((r, _)) => Err(r
            .field
            .err(format!(
                "{} matches no material, mesh or node of {}",
                echo(r.key),
                asset.display()
            ))
            .hint(available(parts))),
        None => Ok(()),
    }
}

/// The names an asset's primitives offer, for an error: up to [`LISTED_NAMES`] of each kind.
fn available(parts: &[Part]) -> String {
    // (kind, the name's position in [node, mesh, material])
    let lists: Vec<String> = [("materials", 2), ("meshes", 1), ("nodes", 0)]
        .into_iter()
        .filter_map(|(kind, k)| {
            let distinct: BTreeSet<&str> = parts
                .iter()
                .filter_map(|p| [&p.node, &p.mesh, &p.material][k].as_deref())
                .collect();
            let shown: Vec<String> = distinct.iter().take(LISTED_NAMES).map(|n| echo(n)).collect();
            let more = distinct.len().saturating_sub(LISTED_NAMES);
            let more = if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            };
            (!shown.is_empty()).then(|| format!("{kind} {}{more}", shown.join(", ")))
        })
        .collect();
    if lists.is_empty() {
        "the asset's primitives have no names; \"*\" matches them all".to_string()
    } else {
        format!("the asset has {}", lists.join("; "))
    }
}

/// `camera = true` (the asset's first perspective camera) or `camera = "name"` (the one whose
/// camera or node has that name), placed with the include's transform; an error when the
/// asset has none or none of that name.
fn pick_camera(f: &Field, asset: &Path, cameras: &[AssetCamera]) -> Result<AssetCamera, SceneError> {
    let name = f.str().ok();
    let found = match name {
        None => cameras.first(),
        Some(n) => cameras
            .iter()
            .find(|c| c.names.iter().any(|g| g.as_deref() == Some(n))),
    };
    if let Some(c) = found {
        return Ok(c.clone());
    }
    if cameras.is_empty() {
        return Err(f
            .err(format!("{} has no perspective camera", asset.display()))
            .hint("add a [camera] table instead of `camera` here"));
    }
    let named: BTreeSet<String> = cameras
        .iter()
        .flat_map(|c| c.names.iter().flatten())
        .map(|n| echo(n))
        .collect();
    let offered: Vec<String> = named.into_iter().take(LISTED_NAMES).collect();
    Err(f
        .err(format!(
            "{} has no camera named {}",
            asset.display(),
            echo(name.unwrap_or_default())
        ))
        .hint(if offered.is_empty() {
            "its cameras have no names; write `camera = true` for the first".to_string()
        } else {
            format!("its cameras and their nodes are named {}", offered.join(", "))
        }))
}
