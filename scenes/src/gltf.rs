//! glTF 2.0 assets (`.gltf` with external, embedded or `data:` buffers and images; `.glb`)
//! as a whole [`Scene`] in world space.
//!
//! What is read, and how (details in each submodule's header):
//!
//! | glTF | model | module |
//! |---|---|---|
//! | default scene (else scene 0, else every root node), node TRS/matrix chains | baked into world space | here |
//! | mesh primitive (TRIANGLES; indexed or not; sparse accessors; KHR_mesh_quantization) | one [`Shape`] with [`Geometry::Mesh`], named `<node or mesh name>/<primitive>` | `mesh`, `accessor` |
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

mod accessor;
mod camera;
mod light;
mod material;
mod mesh;
mod source;

use std::collections::{BTreeSet, HashSet};
use std::path::Path;
use std::sync::Arc;

use glam::{Mat3, Mat4, Quat, Vec3};

use self::source::Asset;
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
    for note in &loaded.notes {
        eprintln!("{}: note: {note}", path.display());
    }
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
    if !to_world.is_finite() {
        return Err(SceneError::new(path, "the placement transform is not finite"));
    }
    let mut asset = Asset::read(path)?;
    let mut notes = std::mem::take(&mut asset.notes);
    if asset.doc.animations().next().is_some() {
        notes.insert("animations: ignored; the static pose is rendered".to_string());
    }
    let placed = walk(&asset, to_world)?;
    let mut names = Names::default();
    let mut table = material::Materials::new(&asset);
    let mut shapes = Vec::new();
    let mut lights = Vec::new();
    for p in &placed {
        shapes.extend(node_shapes(&asset, p, &mut table, &mut names, &mut notes)?);
        if let Some(light) = p.node.light() {
            let base = light.name().or(p.node.name()).map(str::to_string);
            let name = names.unique(base.unwrap_or_else(|| format!("light{}", light.index())));
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
fn walk(asset: &Asset, root: Mat4) -> Result<Vec<Placed<'_>>, SceneError> {
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
            if !m.is_finite() {
                return Err(asset.err(format!("{at}.matrix"), "has a non-finite entry"));
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
    let base = p.node.name().or(gmesh.name()).map(str::to_string);
    let base = base.unwrap_or_else(|| format!("node{}", p.node.index()));
    let mut shapes = Vec::new();
    for prim in gmesh.primitives() {
        let r = table.resolve(&prim.material(), notes)?;
        let needs = mesh::Needs {
            uv_set: r.uv_set,
            normal_map: r.normal_map.is_some(),
        };
        let built = mesh::build(asset, gmesh.index(), &prim, &p.world, &needs, notes)?;
        if built.indices.is_empty() {
            notes.insert(format!(
                "meshes[{}].primitives[{}]: no triangles; skipped",
                gmesh.index(),
                prim.index()
            ));
            continue;
        }
        shapes.push(Shape {
            name: names.unique(format!("{base}/{}", prim.index())),
            geometry: Geometry::Mesh(Arc::new(built)),
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

/// Hands out names unique within the scene (shapes and lights share the AOV namespace).
#[derive(Default)]
struct Names {
    used: HashSet<String>,
}

impl Names {
    /// `base`, or `base#2`, `base#3`, … if taken.
    fn unique(&mut self, base: String) -> String {
        let mut name = base.clone();
        let mut k = 2;
        while self.used.contains(&name) {
            name = format!("{base}#{k}");
            k += 1;
        }
        self.used.insert(name.clone());
        name
    }
}
