//! `[[include]]` with `materials`, `transform` and `camera`, and several includes of one file
//! (scenes/README.md, "[[include]]"), on a small generated asset: a chassis cube with two
//! primitives (materials "Metal_A" and the textured "Paint"), a wheel cube (emissive
//! "Metal_B"), a camera "main" on node "cam_node" and a point light "bulb".

mod gltf_support;
mod toml_support;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3};
use gltf_support::{data_uri, document, png, write, Bin};
use scenes::budget::Ledger;
use scenes::gltf::{Options, Parsed};
use scenes::{Geometry, Light, Mesh, Scene, SceneError};
use toml_support::{expect_error, scratch};

/// The six faces of a cube as (outward normal, u, v) with u × v = n.
const FACES: [[Vec3; 3]; 6] = [
    [Vec3::X, Vec3::NEG_Z, Vec3::Y],
    [Vec3::NEG_X, Vec3::Z, Vec3::Y],
    [Vec3::Y, Vec3::X, Vec3::NEG_Z],
    [Vec3::NEG_Y, Vec3::X, Vec3::Z],
    [Vec3::Z, Vec3::X, Vec3::Y],
    [Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y],
];

/// The attributes and indices of a unit cube at the origin (4 vertices a face with its
/// outward normal, triangles counter-clockwise seen from outside), as a primitive's JSON
/// without its material.
fn cube(bin: &mut Bin) -> String {
    let (mut p, mut n, mut uv, mut idx) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for [normal, u, v] in FACES {
        let base = p.len() as u16;
        for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            p.push(((normal + u * s + v * t) * 0.5).to_array());
            n.push(normal.to_array());
            uv.push([(s + 1.0) / 2.0, (t + 1.0) / 2.0]);
        }
        idx.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    let (p, n, uv, idx) = (bin.vec3(&p), bin.vec3(&n), bin.vec2(&uv), bin.indices(&idx));
    format!("\"attributes\":{{\"POSITION\":{p},\"NORMAL\":{n},\"TEXCOORD_0\":{uv}}},\"indices\":{idx}")
}

/// Writes `kit.gltf` (module header) into `dir`.
fn kit(dir: &Path) -> PathBuf {
    let mut bin = Bin::new();
    let prim = cube(&mut bin);
    let image = data_uri("image/png", &png(2, 2, &[[200, 100, 50, 255]; 4]));
    let rest = format!(
        r#""materials":[{{"name":"Metal_A"}},
            {{"name":"Paint","pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}},
            {{"name":"Metal_B","emissiveFactor":[1,1,1]}}],
        "textures":[{{"source":0}}],"images":[{{"uri":"{image}"}}],
        "meshes":[{{"name":"Body","primitives":[{{{prim},"material":0}},{{{prim},"material":1}}]}},
                  {{"name":"Wheel","primitives":[{{{prim},"material":2}}]}}],
        "cameras":[{{"name":"main","type":"perspective","perspective":{{"yfov":0.5,"aspectRatio":1.5,"znear":0.1}}}}],
        "extensionsUsed":["KHR_lights_punctual"],
        "extensions":{{"KHR_lights_punctual":{{"lights":[{{"type":"point","name":"bulb","intensity":1}}]}}}},
        "nodes":[{{"name":"chassis","mesh":0}},{{"name":"wheel_L","mesh":1,"translation":[2,0,0]}},
                 {{"name":"cam_node","camera":0,"translation":[0,0,5]}},
                 {{"name":"lamp","translation":[0,2,0],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}}],
        "scenes":[{{"nodes":[0,1,2,3]}}],"scene":0"#
    );
    write(dir, "kit.gltf", document(&bin.parts(), &rest))
}

/// Writes `bare.gltf`, one cube without a camera, into `dir`.
fn bare(dir: &Path) -> PathBuf {
    let mut bin = Bin::new();
    let prim = cube(&mut bin);
    let rest = format!(
        r#""meshes":[{{"name":"Box","primitives":[{{{prim}}}]}}],"nodes":[{{"name":"box","mesh":0}}]"#
    );
    write(dir, "bare.gltf", document(&bin.parts(), &rest))
}

/// The scene file's materials: red = 0, blue = 1, green = 2 (the asset's come after).
const MATERIALS: &str = "[[material]]\nname = \"red\"\ntype = \"diffuse\"\n\n\
    [[material]]\nname = \"blue\"\ntype = \"diffuse\"\n\n\
    [[material]]\nname = \"green\"\ntype = \"diffuse\"\n";
const CAMERA: &str = "[camera]\neye = [0, 1, 9]\ntarget = [0, 0, 0]\nfov = 40\n";

/// A scene file: `[camera]` when `camera`, the materials, then `rest` (includes, film).
fn text(camera: bool, rest: &str) -> String {
    let camera = if camera { CAMERA } else { "" };
    format!("{camera}\n{MATERIALS}\n{rest}")
}

/// `[[include]] file = "kit.gltf"` with more fields.
fn include(fields: &str) -> String {
    format!("[[include]]\nfile = \"kit.gltf\"\n{fields}\n")
}

/// Loads `text` as `dir/scene.toml`.
fn load(dir: &Path, text: &str) -> Result<Scene, SceneError> {
    scenes::toml::load_str(text, &dir.join("scene.toml"))
}

/// `scene.toml:N:` for the line of `text` that contains `needle`.
fn at(text: &str, needle: &str) -> String {
    let n = text
        .lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("no line with {needle:?}"));
    format!("scene.toml:{}:", n + 1)
}

fn shape<'a>(s: &'a Scene, name: &str) -> &'a scenes::Shape {
    s.shapes.iter().find(|sh| sh.name == name).unwrap_or_else(|| {
        panic!(
            "no shape {name}: {:?}",
            s.shapes.iter().map(|s| &s.name).collect::<Vec<_>>()
        )
    })
}

fn mesh<'a>(s: &'a Scene, name: &str) -> &'a Arc<Mesh> {
    match &shape(s, name).geometry {
        Geometry::Mesh(m) => m,
        other => panic!("{name} is not a mesh: {other:?}"),
    }
}

/// The material of each included shape, by name.
fn materials(s: &Scene) -> [usize; 3] {
    ["chassis/0", "chassis/1", "wheel_L/0"].map(|n| shape(s, n).material)
}

const RED: usize = 0;
const BLUE: usize = 1;
const GREEN: usize = 2;

#[test]
fn materials_are_replaced_by_material_mesh_or_node_name() {
    let dir = scratch("include-names");
    kit(&dir);
    let plain = load(&dir, &text(true, &include(""))).unwrap_or_else(|e| panic!("{e}"));
    let own = materials(&plain);
    assert!(
        own.iter().all(|&m| m > GREEN),
        "the asset's own materials: {own:?}"
    );
    assert!(shape(&plain, "wheel_L/0").emission.is_some(), "Metal_B emits");

    let with = |entries: &str| {
        let t = text(true, &include(&format!("materials = {{ {entries} }}")));
        load(&dir, &t).unwrap_or_else(|e| panic!("{e}\n{t}"))
    };
    // A glTF material name.
    assert_eq!(materials(&with("\"Paint\" = \"red\"")), [own[0], RED, own[2]]);
    // A mesh name: both primitives of Body.
    assert_eq!(materials(&with("\"Body\" = \"blue\"")), [BLUE, BLUE, own[2]]);
    // A node name.
    let s = with("\"wheel_L\" = \"green\"");
    assert_eq!(materials(&s), [own[0], own[1], GREEN]);
    assert!(
        shape(&s, "wheel_L/0").emission.is_none(),
        "the replaced glTF material's emission goes with it"
    );
    // The most specific name wins whatever the order: node, then mesh, then material.
    assert_eq!(
        materials(&with(
            "\"Metal_A\" = \"red\", \"Body\" = \"blue\", \"chassis\" = \"green\""
        )),
        [GREEN, GREEN, own[2]]
    );
    assert_eq!(
        materials(&with("\"Metal_A\" = \"red\", \"Body\" = \"blue\"")),
        [BLUE, BLUE, own[2]]
    );
}

#[test]
fn material_patterns_match_names_and_yield_to_exact_keys() {
    let dir = scratch("include-globs");
    kit(&dir);
    let with = |entries: &str| {
        let t = text(true, &include(&format!("materials = {{ {entries} }}")));
        materials(&load(&dir, &t).unwrap_or_else(|e| panic!("{e}\n{t}")))
    };
    assert_eq!(with("\"Metal_?\" = \"red\""), [RED, with("")[1], RED]);
    // Among patterns the first written wins; `*` catches the rest.
    assert_eq!(with("\"Metal*\" = \"red\", \"*\" = \"blue\""), [RED, BLUE, RED]);
    assert_eq!(with("\"*\" = \"blue\", \"Metal*\" = \"red\""), [BLUE, BLUE, BLUE]);
    // An exact key beats every pattern.
    assert_eq!(with("\"*\" = \"blue\", \"Paint\" = \"red\""), [BLUE, RED, BLUE]);
    assert_eq!(with("\"wheel*\" = \"green\""), [with("")[0], with("")[1], GREEN]);
}

#[test]
fn material_errors_name_the_file_line_and_key() {
    let dir = scratch("include-material-errors");
    kit(&dir);
    let t = text(true, &include("materials = { \"Paint\" = \"wod\" }"));
    let e = expect_error(
        load(&dir, &t),
        &[
            &at(&t, "materials"),
            "field `include[0].materials.Paint`",
            "unknown material \"wod\"",
            "defined materials: blue, green, red",
        ],
    );
    assert!(!e.to_string().contains('\n'), "{e}");

    let t = text(
        true,
        &include("materials = { \"*\" = \"red\", \"Glass*\" = \"blue\" }"),
    );
    let e = expect_error(
        load(&dir, &t),
        &[
            &at(&t, "materials"),
            "field `include[0].materials.Glass*`",
            "\"Glass*\" matches no material, mesh or node of",
            "kit.gltf",
            "materials \"Metal_A\", \"Metal_B\", \"Paint\"; meshes \"Body\", \"Wheel\"; nodes \"chassis\", \"wheel_L\"",
        ],
    );
    assert!(!e.to_string().contains('\n'), "{e}");
    // An exact name nothing has.
    expect_error(
        load(
            &dir,
            &text(true, &include("materials = { \"Chassis\" = \"red\" }")),
        ),
        &[
            "`include[0].materials.Chassis`",
            "matches no material, mesh or node",
        ],
    );
    expect_error(
        load(&dir, &text(true, &include("materials = { \"\" = \"red\" }"))),
        &["`include[0].materials.`", "an empty key"],
    );
    expect_error(
        load(&dir, &text(true, &include("materials = { \"Paint\" = 3 }"))),
        &["`include[0].materials.Paint`", "expected a string"],
    );
}

/// Outward: every vertex normal is unit and points away from `center`, and every triangle's
/// winding (b − a) × (c − a) agrees with its vertex normals.
fn assert_outward(what: &str, m: &Mesh, center: Vec3) {
    for (i, (p, n)) in m.positions.iter().zip(&m.normals).enumerate() {
        assert!(
            (n.length() - 1.0).abs() < 1e-5,
            "{what}: normal {i} has length {}",
            n.length()
        );
        assert!(
            n.dot(*p - center) > 0.0,
            "{what}: normal {i} {n} points inwards at {p}"
        );
    }
    for t in &m.indices {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        let face = (b - a).cross(c - a);
        assert!(
            face.dot(m.normals[t[0] as usize]) > 0.0,
            "{what}: triangle {t:?} is wound against its normals"
        );
    }
}

fn bounds(m: &Mesh) -> (Vec3, Vec3) {
    Geometry::Mesh(Arc::new(m.clone())).bounds()
}

#[track_caller]
fn assert_near(what: &str, a: Vec3, b: Vec3) {
    assert!((a - b).abs().max_element() < 1e-5, "{what}: {a} vs {b}");
}

#[test]
fn transform_moves_meshes_lights_and_flips_winding_when_mirroring() {
    let dir = scratch("include-transform");
    kit(&dir);
    let load_with = |steps: &str| {
        let t = text(true, &include(&format!("transform = [{steps}]")));
        load(&dir, &t).unwrap_or_else(|e| panic!("{e}\n{t}"))
    };
    let plain = load(&dir, &text(true, &include(""))).unwrap();
    let s = load_with("{ scale = [2, 1, 1] }, { translate = [0, 3, 0] }");
    let chassis = mesh(&s, "chassis/0");
    let (lo, hi) = bounds(chassis);
    assert_near("chassis min", lo, Vec3::new(-1.0, 2.5, -0.5));
    assert_near("chassis max", hi, Vec3::new(1.0, 3.5, 0.5));
    // The wheel's node translation (2, 0, 0) is scaled too: its centre lands at (4, 3, 0).
    let (lo, hi) = bounds(mesh(&s, "wheel_L/0"));
    assert_near("wheel min", lo, Vec3::new(3.0, 2.5, -0.5));
    assert_near("wheel max", hi, Vec3::new(5.0, 3.5, 0.5));
    assert_outward("scaled chassis", chassis, Vec3::new(0.0, 3.0, 0.0));
    assert_eq!(
        chassis.indices,
        mesh(&plain, "chassis/0").indices,
        "no mirror, same winding"
    );
    let Light::Point { position, .. } = &s.lights[0] else {
        panic!("{:?}", s.lights)
    };
    assert_near("the lamp", *position, Vec3::new(0.0, 5.0, 0.0));

    // A mirror (negative determinant) reverses the winding so the faces still point outward.
    let m = load_with("{ scale = [-1, 1, 1] }, { rotate = { axis = [0, 0, 1], angle = 30 } }");
    let mirrored = mesh(&m, "chassis/0");
    assert_outward("mirrored chassis", mirrored, Vec3::ZERO);
    let flipped: Vec<[u32; 3]> = mesh(&plain, "chassis/0")
        .indices
        .iter()
        .map(|&[a, b, c]| [a, c, b])
        .collect();
    assert_eq!(mirrored.indices, flipped);

    let t = text(true, &include("transform = [{ scale = [1, 0, 1] }]"));
    expect_error(
        load(&dir, &t),
        &[&at(&t, "transform"), "`include[0].transform`", "singular"],
    );
}

#[test]
fn camera_comes_from_the_asset_with_its_aspect_ratio() {
    let dir = scratch("include-camera");
    kit(&dir);
    bare(&dir);
    let s = load(&dir, &text(false, &include("camera = true"))).unwrap_or_else(|e| panic!("{e}"));
    assert_near("eye", s.camera.position(), Vec3::new(0.0, 0.0, 5.0));
    assert_near("view", s.camera.forward(), Vec3::NEG_Z);
    assert!((s.camera.fov_y_deg - 0.5f32.to_degrees()).abs() < 1e-4);
    assert_eq!((s.film.width, s.film.height), (768, 512), "the asset's film");
    assert_eq!(s.provenance.camera_aspect, Some(1.5));

    // The include's transform places the camera too: (0, 0, 5) turned 90° about +Y, then moved.
    let steps = "transform = [{ rotate = { axis = [0, 1, 0], angle = 90 } }, { translate = [1, 0, 0] }]";
    let t = text(false, &include(&format!("camera = \"main\"\n{steps}")));
    let s = load(&dir, &t).unwrap_or_else(|e| panic!("{e}"));
    assert_near("moved eye", s.camera.position(), Vec3::new(6.0, 0.0, 0.0));
    assert_near("turned view", s.camera.forward(), Vec3::NEG_X);

    // The film follows the aspect ratio from the side given; both sides must agree with it.
    let film = |sides: &str| {
        let t = text(
            false,
            &format!("{}\n[film]\n{sides}\n", include("camera = \"cam_node\"")),
        );
        load(&dir, &t).map(|s| (s.film.width, s.film.height))
    };
    assert_eq!(film("width = 300").unwrap(), (300, 200));
    assert_eq!(film("height = 101").unwrap(), (152, 101));
    assert_eq!(film("width = 150\nheight = 100").unwrap(), (150, 100));
    let t = text(
        false,
        &format!(
            "{}\n[film]\nwidth = 300\nheight = 300\n",
            include("camera = true")
        ),
    );
    let e = expect_error(
        load(&dir, &t),
        &[
            &at(&t, "height = 300"),
            "`film.height`",
            "300×300 pixels has the aspect ratio 1.0000",
            "aspectRatio is 1.5",
        ],
    );
    assert!(!e.to_string().contains('\n'), "{e}");

    // Errors: no camera in the asset, no camera of that name, a [camera] table as well,
    // two includes asking, and `camera = false` without a [camera] table.
    let t = text(false, "[[include]]\nfile = \"bare.gltf\"\ncamera = true\n");
    expect_error(
        load(&dir, &t),
        &[
            &at(&t, "camera = true"),
            "`include[0].camera`",
            "bare.gltf has no perspective camera",
        ],
    );
    expect_error(
        load(&dir, &text(false, &include("camera = \"side\""))),
        &[
            "`include[0].camera`",
            "no camera named \"side\"",
            "named \"cam_node\", \"main\"",
        ],
    );
    let t = text(true, &include("camera = true"));
    expect_error(
        load(&dir, &t),
        &[
            &at(&t, "camera = true"),
            "`include[0].camera`",
            "[camera] table on line 1 as well",
        ],
    );
    let t = text(
        false,
        &format!("{}{}", include("camera = true"), include("camera = true")),
    );
    expect_error(
        load(&dir, &t),
        &[
            "`include[1].camera`",
            "`include[0].camera` already takes the asset camera",
        ],
    );
    expect_error(
        load(&dir, &text(false, &include("camera = false"))),
        &["field `camera`", "missing required field"],
    );
    expect_error(
        load(&dir, &text(false, &include("camera = 1"))),
        &["`include[0].camera`", "expected true, false or a camera name"],
    );
}

/// Several includes of one file read it once: the memory the scene charges is what one
/// reading of the asset charges plus one placement per distinct transform. Includes placed
/// alike share their meshes and textures (`Arc`), and take names `#2`, `#3`, ….
#[test]
fn includes_of_one_file_read_it_once_and_share_its_data() {
    let dir = scratch("include-shared");
    let asset = kit(&dir);
    let ledger = Ledger::new();
    let options = Options {
        also_inside: Some(dir.to_path_buf()),
        ..Options::new(&ledger)
    };
    let parsed = Parsed::read(&asset, &options).unwrap_or_else(|e| panic!("{e}"));
    let read = ledger.used();
    parsed.place(Mat4::IDENTITY).unwrap();
    let placement = ledger.used() - read;
    assert!(read > 0 && placement > 0, "read {read}, placement {placement}");

    let charged = |includes: &str| {
        let path = write(&dir, "scene.toml", text(true, includes));
        let ledger = Ledger::new();
        let s = scenes::toml::load_in(&path, &ledger).unwrap_or_else(|e| panic!("{e}\n{includes}"));
        (s, ledger.used())
    };
    let (one, used) = charged(&include(""));
    assert_eq!(used, read + placement, "one include");
    let twice = format!(
        "{}{}{}",
        include("materials = { \"*\" = \"red\" }"),
        include("materials = { \"*\" = \"blue\" }"),
        include("transform = [{ translate = [0, 0, -4] }]")
    );
    let (s, used) = charged(&twice);
    println!("kit.gltf: read {read} bytes, placement {placement} bytes; three includes charged {used} bytes");
    assert_eq!(
        used,
        read + 2 * placement,
        "three includes, two transforms: read once, placed twice"
    );
    assert_eq!(
        s.textures.len(),
        one.textures.len(),
        "the asset's texture is held once"
    );
    assert!(
        Arc::ptr_eq(mesh(&s, "chassis/0"), mesh(&s, "chassis/0#2")),
        "placed alike, one mesh"
    );
    assert!(!Arc::ptr_eq(mesh(&s, "chassis/0"), mesh(&s, "chassis/0#3")));
    assert_eq!(shape(&s, "chassis/0").material, RED);
    assert_eq!(
        shape(&s, "chassis/0#2").material,
        BLUE,
        "materials stay per include"
    );
    assert!(shape(&s, "chassis/0#3").material > GREEN);
    let lights: Vec<&str> = s.lights.iter().map(Light::name).collect();
    assert_eq!(lights, ["bulb", "bulb#2", "bulb#3"]);
}
