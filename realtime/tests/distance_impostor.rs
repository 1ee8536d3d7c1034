//! Distance impostors end to end on the adapter at hand (lavapipe in CI), in the closed room of
//! emissive checkerboards the studies use (scenes/studies/scenes/distance-room*.toml): zero
//! iterations is the plain cube map bit for bit; the iteration converges on the room's planar
//! walls, monotonically, to what the search finds, each step costing one more fetch; an
//! index-matched glass ball traced by double refraction shows the room exactly as if it were
//! not there, while the first interface alone of a real glass ball misses; and the errors for
//! a refractor that is not closed and for out-of-range parameters name what is wrong.
//! Accuracy against the oracle is measured by scenes/studies/distance-impostor-*.toml.

mod support;

use std::path::Path;

use realtime::{Method, PipelineKind, RasterOutput, RasterSettings};
use scenes::Scene;
use support::{method, rel_rms, renderer, rgb_id};

const SIZE: u32 = 48;
/// The ball's object id (its index + 1: it is the file's first shape).
const BALL: f32 = 1.0;

/// A study room, with `edit` applied to its text.
fn room(file: &str, edit: impl Fn(String) -> String) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/studies/scenes")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    scenes::toml::load_str(&edit(text), &path).unwrap_or_else(|e| panic!("{e}"))
}

fn render(scene: &Scene, m: &Method) -> RasterOutput {
    let s = RasterSettings::new(SIZE, SIZE)
        .method(m.clone())
        .pipeline(PipelineKind::Forward)
        .frames(0, 1)
        .counters(true);
    renderer()
        .render(scene, &s)
        .unwrap_or_else(|e| panic!("{m}: {e}"))
}

/// The cheap shading of everything but the ball (its walls are emitters on black).
fn lookup(name: &str, params: &[(&str, &str)]) -> Method {
    let mut p = vec![("n", "1"), ("env_n", "0"), ("size", "64")];
    p.extend_from_slice(params);
    method(name, &p)
}

fn fetches(out: &RasterOutput) -> f64 {
    out.counters
        .as_ref()
        .expect("counters were requested")
        .texel_fetches_per_pixel
}

#[test]
fn zero_iterations_is_the_plain_cube_map() {
    let scene = room("distance-room.toml", |t| t);
    let plain = render(&scene, &lookup("envmap_cube", &[]));
    let zero = render(&scene, &lookup("distance_impostor", &[("iterations", "0")]));
    let (a, _) = rgb_id(&plain);
    let (b, _) = rgb_id(&zero);
    let same = a
        .iter()
        .zip(&b)
        .all(|(x, y)| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()));
    assert!(same, "iterations = 0 must be the plain lookup, bit for bit");
    assert_eq!(fetches(&plain), fetches(&zero));
}

#[test]
fn iterations_converge_on_planar_walls_to_the_search() {
    let scene = room("distance-room.toml", |t| t);
    let search = render(
        &scene,
        &lookup(
            "distance_search",
            &[("linear_steps", "32"), ("secant_steps", "8")],
        ),
    );
    let plain = render(&scene, &lookup("envmap_cube", &[]));
    let plain_error = rel_rms(&plain, &search, BALL);
    assert!(
        plain_error > 0.3,
        "the plain map should be far off in a room this close: {plain_error}"
    );
    let mut errors = Vec::new();
    let mut costs = Vec::new();
    for k in [1, 2, 4, 8] {
        let out = render(
            &scene,
            &lookup("distance_impostor", &[("iterations", &k.to_string())]),
        );
        errors.push(rel_rms(&out, &search, BALL));
        costs.push(fetches(&out));
    }
    println!("relative RMS against the search: plain {plain_error:.4}, 1/2/4/8 iterations {errors:?}; fetches {costs:?}");
    assert!(
        errors[0] > 0.03,
        "one iteration has not converged yet: {errors:?}"
    );
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "not monotone: {errors:?}");
    assert!(
        errors[3] < 0.01,
        "eight iterations should agree with the search: {errors:?}"
    );
    assert!(
        costs.windows(2).all(|w| w[1] > w[0]) && costs[0] > fetches(&plain),
        "each iteration costs fetches: plain {}, {costs:?}",
        fetches(&plain)
    );
}

#[test]
fn index_matched_glass_shows_the_room_as_if_absent() {
    // η = 1: no reflection, no bending; double refraction must find the exit and look the
    // room up along the unbent ray from there.
    let matched = room("distance-room-glass.toml", |t| {
        t.replace("int_ior = 1.5", "int_ior = 1.0")
    });
    let absent = room("distance-room-glass.toml", |t| {
        t.replace("name = \"glass_ball\"", "name = \"glass_ball\"\nenabled = false")
    });
    let direct = render(&absent, &Method::quadrature(1).with_env_n(0));
    let (_, ids) = rgb_id(&render(&matched, &lookup("envmap_cube", &[])));
    let on_ball = |a: &RasterOutput| support::rel_rms_where(a, &direct, |i, _| ids[i] == BALL);
    let double = on_ball(&render(
        &matched,
        &lookup("distance_search", &[("double_refraction", "on")]),
    ));
    let plain = on_ball(&render(&matched, &lookup("envmap_cube", &[])));
    println!("index-matched glass against the room without it: double refraction {double:.4}, plain map {plain:.4}");
    assert!(
        double < 0.08,
        "double refraction through η = 1 should see the room straight: {double}"
    );
    assert!(
        plain > 3.0 * double,
        "the plain map should not: {plain} vs {double}"
    );

    // η = 1.5: the first interface alone sends the rays elsewhere than the two do.
    let glass = room("distance-room-glass.toml", |t| t);
    let two = render(&glass, &lookup("distance_search", &[("double_refraction", "on")]));
    let one = render(&glass, &lookup("distance_search", &[]));
    let apart = rel_rms(&one, &two, BALL);
    assert!(
        apart > 0.2,
        "one and two interfaces should differ for real glass: {apart}"
    );
}

#[test]
fn layered_maps_add_nothing_to_an_empty_room_and_complete_the_occluders() {
    let search = |layers: u32| {
        lookup(
            "distance_search",
            &[
                ("linear_steps", "64"),
                ("secant_steps", "4"),
                ("layers", &layers.to_string()),
            ],
        )
    };
    // The empty room is star-shaped about the capture point: one surface per direction, so
    // the peeled layers are empty and the layered search must find what the one-layer one does.
    let empty = room("distance-room.toml", |t| t);
    let one = render(&empty, &search(1));
    let three = render(&empty, &search(3));
    let empty_apart = rel_rms(&three, &one, BALL);

    // Beside the occluders (convex boxes apart from each other) a direction from the capture
    // point meets at most three surfaces: a box's near and far faces and the wall behind.
    // Three layers hold them all, so a fourth changes nothing; one layer loses the walls
    // behind the boxes, and two keep the far face as the last, solid, layer, losing them too.
    let occluded = room("distance-room-occluders.toml", |t| t);
    let outs: Vec<RasterOutput> = (1..=4).map(|k| render(&occluded, &search(k))).collect();
    let versus_four: Vec<f64> = outs.iter().map(|o| rel_rms(o, &outs[3], BALL)).collect();
    let costs: Vec<f64> = outs.iter().map(fetches).collect();
    println!(
        "layered search, relative RMS: empty room 3 vs 1 layer {empty_apart:.2e}; occluders, 1/2/3 layers vs 4 {versus_four:?}; fetches {costs:?}"
    );
    assert!(
        empty_apart < 1e-3,
        "further layers of an empty room must change nothing: {empty_apart}"
    );
    assert!(
        versus_four[2] < 1e-3,
        "three layers already hold every surface: {versus_four:?}"
    );
    assert!(
        versus_four[0] > 0.05 && versus_four[1] > 0.05,
        "one or two layers lose the walls behind the boxes: {versus_four:?}"
    );
    assert!(
        costs.windows(2).all(|w| w[1] > w[0]),
        "each layer costs fetches: {costs:?}"
    );
}

#[test]
fn bad_parameters_and_open_refractors_are_named() {
    let err = Method::parse("distance_impostor", &[("iterations".into(), "65".into())]).unwrap_err();
    assert!(err.contains("iterations") && err.contains("0..=64"), "{err}");
    let err = Method::parse("distance_search", &[("iterations".into(), "2".into())]).unwrap_err();
    assert!(
        err.contains("no parameter `iterations`") && err.contains("linear_steps"),
        "{err}"
    );
    let err = Method::parse("envmap_cube", &[("double_refraction".into(), "on".into())]).unwrap_err();
    assert!(err.contains("no parameter `double_refraction`"), "{err}");

    let pane = room("distance-room.toml", |t| {
        t.replace(
            "type = \"sphere\"\nmaterial = \"mirror\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.5",
            "type = \"rectangle\"\nmaterial = \"glass\"\ncenter = [0.0, 0.0, 0.0]\nsize = [1.0, 1.0]\nnormal = [0, 0, 1]",
        )
        .replace(
            "name = \"mirror\"\ntype = \"mirror\"",
            "name = \"glass\"\ntype = \"dielectric\"\nint_ior = 1.5",
        )
    });
    let s = RasterSettings::new(8, 8).method(lookup("distance_search", &[("double_refraction", "on")]));
    let err = renderer()
        .render(&pane, &s)
        .expect_err("an open refractor is refused")
        .to_string();
    assert!(
        err.contains("double_refraction = on") && err.contains("mirror_ball") && err.contains("closed shape"),
        "{err}"
    );
}
