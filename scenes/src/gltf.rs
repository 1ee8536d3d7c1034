//! glTF 2.0 assets (`.gltf` with external, embedded or `data:` buffers and images; `.glb`)
//! as a whole [`Scene`] in world space.
//!
//! What is read, and how (details in each submodule's header):
//!
//! | glTF | model | module |
//! |---|---|---|
//! | default scene (else scene 0, else every root node), node TRS/matrix chains | baked into world space | here |
//! | mesh primitive (TRIANGLES; indexed or not; sparse accessors; KHR_mesh_quantization) | one [`Shape`] with [`Geometry::Mesh`], named `<node or mesh name>/<primitive>` (the file's name reduced to `[A-Za-z0-9_-]`) | `mesh`, `accessor`, `names` |
//! | material | [`crate::Material::MetalRough`], normal map, emission | `material` |
//! | KHR_lights_punctual | [`crate::Light`] (units taken as is) | `light` |
//! | first perspective camera in the hierarchy | [`crate::Camera`], [`crate::Film`] | `camera` |
//!
//! Not applied, and said so in the notes ([`Loaded::notes`]): alpha modes (rendered opaque),
//! vertex colours, morph targets, skins and animations (the static pose is rendered),
//! `KHR_texture_transform` and other optional extensions (the core fallback is rendered),
//! light `range`. A file that *requires* an extension this loader lacks (Draco, meshopt,
//! BasisU textures, …) is an error that says how to convert it. A file without lights
//! leaves [`Scene::lights`] empty: the TOML scene or the CLI adds lighting around it.
//!
//! Errors name the file and the JSON path of the offending field, e.g.
//! `meshes[0].primitives[1].indices`; nothing in a malformed file makes the loader panic.
//!
//! Hostile input ([`Options`]): the asset reads files only inside its folder (and, included
//! from a scene file, the scene's folder) unless allowed otherwise, every large allocation is
//! charged to the load's memory ledger first, and names from the file are reduced to
//! `[A-Za-z0-9_-]` before they become shape and light names (module `names`).

mod accessor;
mod camera;
mod indices;
mod light;
mod material;
mod mesh;
mod names;
mod source;
mod uri;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};

use self::names::Names;
use self::source::Asset;
use crate::access::Confinement;
use crate::budget::Ledger;
use crate::model::{Camera, Film, Geometry, RenderSettings, Scene, Shape};
use crate::SceneError;

/// A loaded asset with the loader's notes about what it ignored or approximated.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The scene.
    pub scene: Scene,
    /// One line per ignored or approximated feature, each naming its JSON field.
    pub notes: Vec<String>,
}

/// Loads a glTF 2.0 asset as a whole scene, printing the loader's notes (ignored features)
/// to standard error. [`load_with_notes`] returns them instead.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let loaded = load_with_notes(path)?;
    loaded.print_notes();
    Ok(loaded.scene)
}

/// Loads a glTF 2.0 asset as a whole scene, returning the notes about ignored features.
pub fn load_with_notes(path: &Path) -> Result<Loaded, SceneError> {
    load_transformed(path, Mat4::IDENTITY)
}

/// Loads a glTF 2.0 asset placed by `to_world` (applied above its root nodes, so meshes,
/// lights and cameras move together, with winding and tangent handedness handled as for
/// any node transform). For scene files that include an asset with a transform.
pub fn load_transformed(path: &Path, to_world: Mat4) -> Result<Loaded, SceneError> {
    let ledger = Ledger::new();
    let options = Options {
        to_world,
        ..Options::new(&ledger)
    };
    load_with_options(path, &options)
}

/// How an asset is loaded: where it is placed, the memory ledger its allocations are
/// charged to, and where it may read files.
#[derive(Clone, Debug)]
pub struct Options<'a> {
    /// Placement above the asset's root nodes ([`load_transformed`]).
    pub to_world: Mat4,
    /// The job's memory ledger (a scene file passes the one its other inputs are charged to).
    pub ledger: &'a Ledger,
    /// A folder the asset may read from besides its own: the including scene file's.
    pub also_inside: Option<PathBuf>,
    /// Lifts the confinement for this asset (`[[include]] allow_paths_outside = true`); the
    /// `--allow-paths-outside` flag ([`crate::access::outside_allowed`]) lifts it for all.
    pub allow_paths_outside: bool,
}

impl<'a> Options<'a> {
    /// Unplaced, confined to the asset's folder, charging `ledger`.
    pub fn new(ledger: &'a Ledger) -> Self {
        Options {
            to_world: Mat4::IDENTITY,
            ledger,
            also_inside: None,
            allow_paths_outside: false,
        }
    }

    /// Where the asset at `path` may read.
    fn confinement(&self, path: &Path) -> Confinement {
        if self.allow_paths_outside || crate::access::outside_allowed() {
            return Confinement::anywhere();
        }
        let own = Confinement::within(path.parent().unwrap_or(Path::new(".")));
        match &self.also_inside {
            Some(dir) => own.and(dir),
            None => own,
        }
    }
}

impl Loaded {
    /// Prints the notes to standard error, each prefixed with the asset's file.
    pub fn print_notes(&self) {
        for note in &self.notes {
            eprintln!("{}: note: {note}", self.scene.source.display());
        }
    }
}

/// Loads a glTF 2.0 asset as [`load_transformed`] does, with the given [`Options`].
pub fn load_with_options(path: &Path, options: &Options) -> Result<Loaded, SceneError> {
    if !options.to_world.is_finite() {
        return Err(SceneError::new(path, "the placement transform is not finite"));
    }
    let mut asset = Asset::read(path, options.ledger, options.confinement(path))?;
    let mut notes = std::mem::take(&mut asset.notes);
    if asset.doc.animations().next().is_some() {
        notes.insert("animations: ignored; the static pose is rendered".to_string());
    }
    light::check_all(&asset)?;
    camera::check_all(&asset)?;
    let placed = walk(&asset, options.to_world)?;
    let mut names = Names::default();
    let mut table = material::Materials::new(&asset);
    let mut shapes = Vec::new();
    let mut lights = Vec::new();
    for p in &placed {
        shapes.extend(node_shapes(&asset, p, &mut table, &mut names, &mut notes)?);
        if let Some(light) = p.node.light() {
            let name = match light.name().or(p.node.name()) {
                Some(given) => names.named(given),
                None => names.unique(&format!("light{}", light.index())),
            };
            lights.push(light::convert(
                &asset,
                &light,
                p.node.index(),
                &p.world,
                name,
                &mut notes,
            )?);
        }
    }
    notes.extend(names.note());
    let mut scene = Scene {
        source: path.to_path_buf(),
        // Replaced by `place_camera` once the shapes (and so the bounds) are known.
        camera: Camera::look_at(Vec3::Z, Vec3::ZERO, Vec3::Y, camera::DEFAULT_FOV_DEG),
        film: Film {
            width: camera::FILM_HEIGHT,
            height: camera::FILM_HEIGHT,
        },
        render: RenderSettings::default(),
        textures: table.textures,
        materials: table.materials,
        shapes,
        lights,
        environment: None,
    };
    place_camera(&asset, &placed, &mut scene, &mut notes)?;
    Ok(Loaded {
        scene,
        notes: notes.into_iter().collect(),
    })
}

/// A node with its world matrix, in depth-first document order.
struct Placed<'a> {
    node: ::gltf::Node<'a>,
    world: Mat4,
}

/// Depth-first walk of the scene's node trees, composing world = parent · local from `root`.
fn walk<'a>(asset: &'a Asset, root: Mat4) -> Result<Vec<Placed<'a>>, SceneError> {
    let doc = &asset.doc;
    let roots: Vec<::gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for node in doc.nodes() {
                for child in node.children() {
                    is_child[child.index()] = true;
                }
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut seen = vec![false; doc.nodes().len()];
    let mut stack: Vec<(::gltf::Node, Mat4)> = roots.into_iter().rev().map(|n| (n, root)).collect();
    let mut out = Vec::new();
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(asset.err(
                format!("nodes[{}]", node.index()),
                "the node is reached twice: the hierarchy has a cycle or a node with two parents \
                 (glTF 2.0 requires disjoint trees)",
            ));
        }
        let world = parent * local_matrix(asset, &node)?;
        let children: Vec<::gltf::Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
        out.push(Placed { node, world });
    }
    Ok(out)
}

/// The node's local matrix: `matrix`, or T·R·S with the rotation quaternion normalised.
fn local_matrix(asset: &Asset, node: &::gltf::Node) -> Result<Mat4, SceneError> {
    let at = format!("nodes[{}]", node.index());
    match node.transform() {
        ::gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            let field = format!("{at}.matrix");
            if !m.is_finite() {
                return Err(asset.err(field, "has a non-finite entry"));
            }
            // glTF 2.0 §3.5.3 "Transformations": a matrix must be decomposable to TRS, so
            // affine (last row 0, 0, 0, 1) and, to have a scale, invertible.
            if m.row(3) != Vec4::W {
                return Err(asset.err(
                    field,
                    format!(
                        "is projective: its last row is {} (elements 3, 7, 11, 15), not 0, 0, 0, 1; \
                         glTF 2.0 §3.5.3 requires a TRS-decomposable matrix",
                        m.row(3)
                    ),
                ));
            }
            let det = Mat3::from_mat4(m).determinant();
            if !det.is_finite() {
                return Err(asset.err(field, format!("its determinant overflows f32 ({det})")));
            }
            if det.abs() <= f32::MIN_POSITIVE {
                return Err(asset
                    .err(
                        field,
                        format!("is singular (determinant {det}); glTF 2.0 §3.5.3 requires a TRS-decomposable matrix"),
                    )
                    .hint("to hide a node, remove its mesh"));
            }
            Ok(m)
        }
        ::gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let (t, s) = (Vec3::from(translation), Vec3::from(scale));
            let q = Quat::from_array(rotation);
            if !t.is_finite() {
                return Err(asset.err(format!("{at}.translation"), format!("is not finite: {t}")));
            }
            if !s.is_finite() {
                return Err(asset.err(format!("{at}.scale"), format!("is not finite: {s}")));
            }
            let len = q.length();
            if !(len.is_finite() && len > 1e-6) {
                return Err(asset.err(format!("{at}.rotation"), format!("is not a unit quaternion: {q}")));
            }
            Ok(Mat4::from_scale_rotation_translation(s, q / len, t))
        }
    }
}

/// The shapes of the mesh placed at `p` (none if it has no mesh or a singular transform).
fn node_shapes(
    asset: &Asset,
    p: &Placed,
    table: &mut material::Materials,
    names: &mut Names,
    notes: &mut BTreeSet<String>,
) -> Result<Vec<Shape>, SceneError> {
    let Some(gmesh) = p.node.mesh() else {
        return Ok(Vec::new());
    };
    let at = format!("nodes[{}]", p.node.index());
    if p.node.skin().is_some() {
        notes.insert(format!(
            "{at}.skin: skinning is ignored; the mesh is drawn in its bind pose"
        ));
    }
    let det = Mat3::from_mat4(p.world).determinant();
    if !(det.is_finite() && det.abs() > f32::MIN_POSITIVE) {
        notes.insert(format!(
            "{at}: singular world transform (zero scale); its mesh is skipped"
        ));
        return Ok(Vec::new());
    }
    let base = match p.node.name().or(gmesh.name()) {
        Some(given) => names.sanitized(given),
        None => format!("node{}", p.node.index()),
    };
    let mut shapes = Vec::new();
    for prim in gmesh.primitives() {
        let r = table.resolve(&prim.material(), notes)?;
        let needs = mesh::Needs {
            uv_set: r.uv_set,
            normal_map: r.normal_map.is_some(),
        };
        let built = mesh::build(asset, gmesh.index(), &prim, &p.world, &needs, notes)?;
        let field = format!("meshes[{}].primitives[{}]", gmesh.index(), prim.index());
        if built.indices.is_empty() {
            notes.insert(format!("{field}: no triangles; skipped"));
            continue;
        }
        let area: f64 = built
            .indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| built.positions[i as usize].as_dvec3());
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        let geometry = Geometry::Mesh(Arc::new(built));
        let (lo, hi) = geometry.bounds();
        if !crate::within_world(lo, hi) {
            return Err(asset.err(
                format!("{field}.attributes.POSITION"),
                format!(
                    "placed by {at}, the positions reach beyond ±{:e} m (bounds {lo} .. {hi})",
                    crate::MAX_COORD
                ),
            ));
        }
        if area == 0.0 {
            notes.insert(format!("{field}: every triangle has zero area; skipped"));
            continue;
        }
        shapes.push(Shape {
            name: names.unique(&format!("{base}/{}", prim.index())),
            geometry,
            material: r.material,
            emission: r.emission,
            normal_map: r.normal_map,
            displacement: None,
        });
    }
    Ok(shapes)
}

/// Sets the scene's camera and film: the file's first perspective camera, else a framing
/// of the scene's bounds.
fn place_camera(
    asset: &Asset,
    placed: &[Placed],
    scene: &mut Scene,
    notes: &mut BTreeSet<String>,
) -> Result<(), SceneError> {
    let (cam, film) = match find_camera(asset, placed, notes)? {
        Some(found) => found,
        None => {
            let (center, radius) = scene.bounding_sphere();
            if !(center.is_finite() && radius.is_finite()) {
                return Err(asset
                    .err("nodes", "the scene's extent overflows f32; cannot frame it")
                    .hint("scale the asset down or add a camera"));
            }
            camera::framing(center, radius)
        }
    };
    scene.camera = cam;
    scene.film = film;
    Ok(())
}

/// The first perspective camera in walk order; an error if only orthographic ones are placed.
fn find_camera(
    asset: &Asset,
    placed: &[Placed],
    notes: &mut BTreeSet<String>,
) -> Result<Option<(Camera, Film)>, SceneError> {
    let mut orthographic = None;
    for p in placed {
        let Some(cam) = p.node.camera() else { continue };
        match cam.projection() {
            ::gltf::camera::Projection::Perspective(persp) => {
                if Mat3::from_mat4(p.world).determinant() < 0.0 {
                    notes.insert(format!(
                        "nodes[{}]: the camera's mirroring transform is dropped",
                        p.node.index()
                    ));
                }
                return camera::from_node(asset, &persp, cam.index(), p.node.index(), &p.world).map(Some);
            }
            ::gltf::camera::Projection::Orthographic(_) => {
                orthographic.get_or_insert(cam.index());
            }
        }
    }
    match orthographic {
        Some(i) => Err(asset
            .err(
                format!("cameras[{i}].orthographic"),
                "orthographic cameras are not supported",
            )
            .hint("add a perspective camera, or remove the camera to get the default framing")),
        None => Ok(None),
    }
}
