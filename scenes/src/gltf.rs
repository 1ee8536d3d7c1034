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
//! | first perspective camera in the hierarchy (every placed one in [`Loaded::cameras`]) | [`crate::Camera`], [`crate::Film`] | `camera` |
//!
//! Reading and placing are apart ([`Parsed`]): the bytes, buffers, checks, materials and
//! decoded textures do not depend on where the asset is placed, so a scene file that includes
//! one file several times reads it once and places it once per transform.
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

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};

use self::names::Names;
use self::source::Asset;
use crate::access::Confinement;
use crate::budget::Ledger;
use crate::model::{Camera, Film, Geometry, Material, Provenance, RenderSettings, Scene, Shape};
use crate::texture::Texture;
use crate::SceneError;

/// A loaded asset with the loader's notes about what it ignored or approximated.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The scene.
    pub scene: Scene,
    /// One line per ignored or approximated feature, each naming its JSON field.
    pub notes: Vec<String>,
    /// Where each shape of `scene` came from, in the same order (what a scene file's
    /// `[[include]] materials` matches).
    pub parts: Vec<Part>,
    /// Every perspective camera placed in the asset, in walk order; `scene.camera` and
    /// `scene.film` are the first's, or a framing of the bounds when there is none.
    pub cameras: Vec<AssetCamera>,
}

/// The glTF names behind one shape (one mesh primitive), as written in the file: the node
/// that places it, its mesh and its material; `None` where the file gives no name (and for
/// the glTF default material).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Part {
    /// `nodes[i].name` of the node holding the mesh.
    pub node: Option<String>,
    /// `meshes[i].name`.
    pub mesh: Option<String>,
    /// `materials[i].name` of the primitive's material.
    pub material: Option<String>,
}

/// A perspective camera of the asset, placed.
#[derive(Clone, Debug, PartialEq)]
pub struct AssetCamera {
    /// `cameras[i].name` and the `name` of the node that places it, where given.
    pub names: [Option<String>; 2],
    /// The camera in world space.
    pub camera: Camera,
    /// Its film: 512 pixels high, as wide as `aspectRatio` makes it (square without one).
    pub film: Film,
    /// `aspectRatio` (width / height), if the file gives one.
    pub aspect: Option<f32>,
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
        self.print_new_notes(&mut BTreeSet::new());
    }

    /// Prints the notes not in `printed` yet and adds them to it (an asset placed several
    /// times says each thing once).
    pub fn print_new_notes(&self, printed: &mut BTreeSet<String>) {
        for note in &self.notes {
            if printed.insert(note.clone()) {
                eprintln!("{}: note: {note}", self.scene.source.display());
            }
        }
    }
}

/// Loads a glTF 2.0 asset as [`load_transformed`] does, with the given [`Options`].
pub fn load_with_options(path: &Path, options: &Options) -> Result<Loaded, SceneError> {
    Parsed::read(path, options)?.place(options.to_world)
}

/// A glTF asset read once and placed any number of times ([`Parsed::place`]): its bytes and
/// buffers, the checks of its lights and cameras, and its materials with their decoded
/// textures (shared by every placement through `Arc`) do not depend on the placement.
pub struct Parsed<'l> {
    asset: Asset<'l>,
    /// Notes of the reading (ignored extensions, animations, material features).
    notes: BTreeSet<String>,
    textures: Vec<Arc<Texture>>,
    materials: Vec<Material>,
    /// The conversion of each glTF material a placed primitive uses.
    resolved: HashMap<Option<usize>, material::Resolved>,
}

impl<'l> Parsed<'l> {
    /// Reads, parses and checks the asset at `path` (charging `options.ledger`, reading only
    /// where `options` allows) and converts the materials of every primitive the default scene
    /// places; `options.to_world` is not used here.
    pub fn read(path: &Path, options: &Options<'l>) -> Result<Parsed<'l>, SceneError> {
        let mut asset = Asset::read(path, options.ledger, options.confinement(path))?;
        let mut notes = std::mem::take(&mut asset.notes);
        if asset.doc.animations().next().is_some() {
            notes.insert("animations: ignored; the static pose is rendered".to_string());
        }
        light::check_all(&asset)?;
        camera::check_all(&asset)?;
        let mut table = material::Materials::new(&asset);
        for p in walk(&asset, Mat4::IDENTITY)? {
            for prim in p.node.mesh().iter().flat_map(|m| m.primitives()) {
                table.resolve(&prim.material(), &mut notes)?;
            }
        }
        let material::Materials {
            textures,
            materials,
            resolved,
            ..
        } = table;
        Ok(Parsed {
            asset,
            notes,
            textures,
            materials,
            resolved,
        })
    }

    /// The asset placed by `to_world` (applied above its root nodes): its meshes built in
    /// world space, its lights and cameras placed. Every placement shares the textures.
    pub fn place(&self, to_world: Mat4) -> Result<Loaded, SceneError> {
        let asset = &self.asset;
        if !to_world.is_finite() {
            return Err(SceneError::new(
                &asset.file,
                "the placement transform is not finite",
            ));
        }
        let mut notes = self.notes.clone();
        let placed = walk(asset, to_world)?;
        let mut names = Names::default();
        let (mut shapes, mut parts, mut lights) = (Vec::new(), Vec::new(), Vec::new());
        for p in &placed {
            for (shape, part) in node_shapes(asset, p, &self.resolved, &mut names, &mut notes)? {
                shapes.push(shape);
                parts.push(part);
            }
            if let Some(light) = p.node.light() {
                let name = match light.name().or(p.node.name()) {
                    Some(given) => names.named(given),
                    None => names.unique(&format!("light{}", light.index())),
                };
                lights.push(light::convert(
                    asset,
                    &light,
                    p.node.index(),
                    &p.world,
                    name,
                    &mut notes,
                )?);
            }
        }
        notes.extend(names.note());
        let cameras = find_cameras(asset, &placed, &mut notes)?;
        let mut scene = Scene {
            source: asset.file.clone(),
            // Replaced by `place_camera` once the shapes (and so the bounds) are known.
            camera: Camera::look_at(Vec3::Z, Vec3::ZERO, Vec3::Y, camera::DEFAULT_FOV_DEG),
            film: Film {
                width: camera::FILM_HEIGHT,
                height: camera::FILM_HEIGHT,
            },
            render: RenderSettings::default(),
            textures: self.textures.clone(),
            materials: self.materials.clone(),
            shapes,
            lights,
            environment: None,
            provenance: Provenance {
                camera_aspect: cameras.first().and_then(|c| c.aspect),
                ..Provenance::default()
            },
        };
        place_camera(asset, cameras.first(), &mut scene)?;
        Ok(Loaded {
            scene,
            notes: notes.into_iter().collect(),
            parts,
            cameras,
        })
    }
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

/// The shapes of the mesh placed at `p` with the glTF names behind each (none if it has no
/// mesh or a singular transform); `resolved` holds the conversion of every material they use.
fn node_shapes(
    asset: &Asset,
    p: &Placed,
    resolved: &HashMap<Option<usize>, material::Resolved>,
    names: &mut Names,
    notes: &mut BTreeSet<String>,
) -> Result<Vec<(Shape, Part)>, SceneError> {
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
        let gmaterial = prim.material();
        let r = resolved.get(&gmaterial.index()).ok_or_else(|| {
            asset.err(
                format!("meshes[{}].primitives[{}].material", gmesh.index(), prim.index()),
                "the material was not converted when the asset was read (a loader bug; please report the file)",
            )
        })?;
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
        let shape = Shape {
            name: names.unique(&format!("{base}/{}", prim.index())),
            geometry,
            material: r.material,
            emission: r.emission.clone(),
            normal_map: r.normal_map.clone(),
            displacement: None,
        };
        let part = Part {
            node: p.node.name().map(str::to_string),
            mesh: gmesh.name().map(str::to_string),
            material: gmaterial.name().map(str::to_string),
        };
        shapes.push((shape, part));
    }
    Ok(shapes)
}

/// Sets the scene's camera and film: the file's first perspective camera, else a framing
/// of the scene's bounds.
fn place_camera(asset: &Asset, first: Option<&AssetCamera>, scene: &mut Scene) -> Result<(), SceneError> {
    let (cam, film) = match first {
        Some(c) => (c.camera, c.film),
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

/// Every placed perspective camera in walk order; an error if only orthographic ones are
/// placed.
fn find_cameras(
    asset: &Asset,
    placed: &[Placed],
    notes: &mut BTreeSet<String>,
) -> Result<Vec<AssetCamera>, SceneError> {
    let mut orthographic = None;
    let mut found = Vec::new();
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
                let (camera, film) = camera::from_node(asset, &persp, cam.index(), p.node.index(), &p.world)?;
                found.push(AssetCamera {
                    names: [cam.name(), p.node.name()].map(|n| n.map(str::to_string)),
                    camera,
                    film,
                    aspect: persp.aspect_ratio(),
                });
            }
            ::gltf::camera::Projection::Orthographic(_) => {
                orthographic.get_or_insert(cam.index());
            }
        }
    }
    match orthographic {
        Some(i) if found.is_empty() => Err(asset
            .err(
                format!("cameras[{i}].orthographic"),
                "orthographic cameras are not supported",
            )
            .hint("add a perspective camera, or remove the camera to get the default framing")),
        _ => Ok(found),
    }
}
