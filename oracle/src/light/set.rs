//! The scene's emitters and which of them next-event estimation picks ([`super::selection`]:
//! ∝ power, pbrt-v4 §12.6.2, or for many lights ∝ a per-region importance).
//!
//! Order (the AOV order of [`scenes::Scene::light_names`]): emissive shapes in scene order, then
//! [`scenes::Scene::lights`], then the environment (unnamed) last.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use scenes::texture::Texture;
use scenes::{Environment, Geometry, Light, Scene};

use super::directional::DirectionalLight;
use super::disk::DiskLight;
use super::environment::EnvironmentLight;
use super::mesh::MeshLight;
use super::point::PointLight;
use super::radiance::Radiance;
use super::rectangle::RectangleLight;
use super::selection::{EmitterBounds, Selection};
use super::sphere::SphereLight;
use super::spot::SpotLight;
use super::{Emitter, LightSample};

/// All emitters of a scene with their selection distribution.
#[derive(Clone, Debug)]
pub struct LightSet {
    emitters: Vec<Emitter>,
    /// Which emitter to sample from a point.
    selection: Selection,
    /// Emitter index of each scene shape, if emissive.
    shape_to_emitter: Vec<Option<usize>>,
    /// Index of the environment emitter.
    environment: Option<usize>,
    /// Emitters an escaping ray can see: sun disks, then the environment.
    distant: Vec<usize>,
    /// Number of named lights (emissive shapes + scene lights).
    named: usize,
}

impl LightSet {
    /// Builds every emitter of `scene`. Errors name the shape or light and the field at fault
    /// (zero-area light, negative or NaN radiance, bad texture index, …); callers prefix the
    /// scene file.
    pub fn new(scene: &Scene) -> Result<LightSet, String> {
        let mut emitters = Vec::new();
        let mut bounds = Vec::new();
        let mut shape_to_emitter = vec![None; scene.shapes.len()];
        for (i, shape) in scene.shapes.iter().enumerate() {
            let Some(emission) = &shape.emission else {
                continue;
            };
            if shape.displacement.is_some() {
                return Err(format!(
                    "shape '{}' (shapes[{i}]): an emitting shape cannot be displaced (area lights are \
                     sampled on their undisplaced surface)",
                    shape.name
                ));
            }
            let emitter = area_emitter(scene, &shape.geometry, emission)
                .map_err(|e| format!("shape '{}' (shapes[{i}]): {e}", shape.name))?;
            shape_to_emitter[i] = Some(emitters.len());
            bounds.push(Some(area_bounds(&shape.geometry, &emitter)));
            emitters.push(emitter);
        }
        let scene_bounds = scene.bounds();
        let (_, scene_radius) = Scene::sphere_around(scene_bounds);
        for (i, light) in scene.lights.iter().enumerate() {
            let emitter = delta_emitter(light, &scene.textures, scene_radius)
                .map_err(|e| format!("light '{}' (lights[{i}]): {e}", light.name()))?;
            bounds.push(delta_bounds(light));
            emitters.push(emitter);
        }
        let named = emitters.len();
        let mut environment = None;
        if let Some(env) = &scene.environment {
            let emitter =
                environment_emitter(scene, env, scene_radius).map_err(|e| format!("environment: {e}"))?;
            environment = Some(emitters.len());
            emitters.push(Emitter::Environment(emitter));
        }
        let distant = (0..emitters.len())
            .filter(|&i| match &emitters[i] {
                Emitter::Directional(d) => !d.is_delta(),
                Emitter::Environment(_) => true,
                _ => false,
            })
            .collect();
        bounds.resize(emitters.len(), None);
        let powers: Vec<f32> = emitters.iter().map(|e| e.power()).collect();
        let (lo, hi) = grid_box(scene, scene_bounds);
        Ok(LightSet {
            selection: Selection::new(&powers, &bounds, lo, hi),
            emitters,
            shape_to_emitter,
            environment,
            distant,
            named,
        })
    }

    /// The emitters, named lights first (see [`LightSet::named_count`]).
    pub fn emitters(&self) -> &[Emitter] {
        &self.emitters
    }

    /// Emitter index of `scene.shapes[shape]`, if that shape is emissive.
    pub fn emitter_of_shape(&self, shape: usize) -> Option<usize> {
        self.shape_to_emitter.get(shape).copied().flatten()
    }

    /// Whether emitter `i` is the convex emitter of `scene.shapes[shape]` itself: it lights no
    /// point of its own surface ([`Emitter::is_convex_shape`]).
    pub fn is_own_convex_emitter(&self, shape: usize, i: usize) -> bool {
        self.emitter_of_shape(shape) == Some(i) && self.emitters[i].is_convex_shape()
    }

    /// Index of the environment emitter, if the scene has one.
    pub fn environment(&self) -> Option<usize> {
        self.environment
    }

    /// Emitters a ray leaving the scene can hit: non-delta directional lights (sun disks) and
    /// the environment. The radiance of an escaping ray with direction ω is the sum of their
    /// [`Emitter::radiance_from_direction`]`(ω)`, each MIS-weighted with its own
    /// [`Emitter::pdf_li`] × [`LightSet::selection_pmf`].
    pub fn distant(&self) -> &[usize] {
        &self.distant
    }

    /// Picks an emitter for the point `p` with `u_select` and samples it with `u`: returns its
    /// index and the sample with `pdf` multiplied by the selection probability.
    pub fn sample(&self, p: Vec3, u_select: f32, u: Vec2) -> Option<(usize, LightSample)> {
        if self.emitters.is_empty() {
            return None;
        }
        let (i, pmf) = self.selection.sample(p, u_select);
        if pmf <= 0.0 {
            return None;
        }
        let mut s = self.emitters[i].sample_li(p, u)?;
        s.pdf *= pmf;
        Some((i, s))
    }

    /// Probability that [`LightSet::sample`] at `p` picks emitter `i` (0 for an index out of
    /// range).
    pub fn selection_pmf(&self, i: usize, p: Vec3) -> f32 {
        if i < self.emitters.len() {
            self.selection.pmf(i, p)
        } else {
            0.0
        }
    }

    /// Number of named lights, `scene.light_names().len()`: named light k is emitter k.
    pub fn named_count(&self) -> usize {
        self.named
    }
}

/// The area emitter of an emissive shape.
fn area_emitter(scene: &Scene, geometry: &Geometry, emission: &scenes::Emission) -> Result<Emitter, String> {
    let radiance = Radiance::new(&emission.radiance, &scene.textures, "emission.radiance")?;
    let two_sided = emission.two_sided;
    Ok(match geometry {
        Geometry::Sphere { center, radius } => {
            Emitter::Sphere(SphereLight::new(*center, *radius, radiance, two_sided)?)
        }
        Geometry::Rectangle {
            center,
            half_u,
            half_v,
        } => Emitter::Rectangle(RectangleLight::new(
            *center, *half_u, *half_v, radiance, two_sided,
        )?),
        Geometry::Disk {
            center,
            half_u,
            half_v,
        } => Emitter::Disk(DiskLight::new(*center, *half_u, *half_v, radiance, two_sided)?),
        Geometry::Mesh(mesh) => Emitter::Mesh(MeshLight::new(Arc::clone(mesh), radiance, two_sided)?),
    })
}

/// Where an area emitter lies: its shape's box, and the front normal of a one-sided
/// rectangle or disk.
fn area_bounds(geometry: &Geometry, emitter: &Emitter) -> EmitterBounds {
    let (lo, hi) = geometry.bounds();
    let front = match emitter {
        Emitter::Rectangle(l) if !l.two_sided => Some(l.normal()),
        Emitter::Disk(l) if !l.two_sided => Some(l.normal()),
        _ => None,
    };
    EmitterBounds { lo, hi, front }
}

/// Where a scene light lies: a point for point and spot lights, nothing (distant) for
/// directional lights.
fn delta_bounds(light: &Light) -> Option<EmitterBounds> {
    match light {
        Light::Point { position, .. } | Light::Spot { position, .. } => Some(EmitterBounds {
            lo: *position,
            hi: *position,
            front: None,
        }),
        Light::Directional { .. } => None,
    }
}

/// The light-selection grid's box: the shapes' box `shapes` ([`Scene::bounds`]) grown to hold
/// the point and spot lights.
fn grid_box(scene: &Scene, shapes: (Vec3, Vec3)) -> (Vec3, Vec3) {
    let lights = scene.lights.iter().filter_map(|l| delta_bounds(l).map(|b| b.lo));
    lights.fold(shapes, |(lo, hi), p| (lo.min(p), hi.max(p)))
}

/// The emitter of a scene light.
fn delta_emitter(light: &Light, textures: &[Arc<Texture>], scene_radius: f32) -> Result<Emitter, String> {
    Ok(match light {
        Light::Point {
            position, intensity, ..
        } => Emitter::Point(PointLight::new(*position, *intensity)?),
        Light::Spot {
            position,
            direction,
            intensity,
            cutoff_deg,
            beam_width_deg,
            projection,
            ..
        } => {
            let spot = SpotLight::new(*position, *direction, *intensity, *cutoff_deg, *beam_width_deg)?;
            Emitter::Spot(match projection {
                Some(p) => spot.projecting(Radiance::new(&p.texture, textures, "texture")?, p.up)?,
                None => spot,
            })
        }
        Light::Directional {
            direction,
            irradiance,
            angular_diameter_deg,
            ..
        } => Emitter::Directional(DirectionalLight::new(
            *direction,
            *irradiance,
            *angular_diameter_deg,
            scene_radius,
        )?),
    })
}

/// The environment emitter.
fn environment_emitter(
    scene: &Scene,
    env: &Environment,
    scene_radius: f32,
) -> Result<EnvironmentLight, String> {
    match env {
        Environment::Constant { radiance } => EnvironmentLight::constant(*radiance, scene_radius),
        Environment::Map { texture, scale } => {
            let t = scene.textures.get(*texture).ok_or_else(|| {
                format!(
                    "texture = {texture} is out of range (the scene has {} textures)",
                    scene.textures.len()
                )
            })?;
            EnvironmentLight::map(Arc::clone(t), *scale, scene_radius)
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use glam::Vec4;
    use scenes::texture::Texture;
    use scenes::{Camera, Emission, Film, Material, Mesh, RenderSettings, Shape, TexRgb, WrapMode};

    use super::*;

    fn shape(name: &str, geometry: Geometry, radiance: Option<Vec3>) -> Shape {
        Shape {
            name: name.to_string(),
            geometry,
            material: 0,
            emission: radiance.map(|r| Emission {
                radiance: TexRgb::Constant(r),
                two_sided: false,
            }),
            normal_map: None,
            displacement: None,
        }
    }

    fn scene(shapes: Vec<Shape>, lights: Vec<Light>, environment: Option<Environment>) -> Scene {
        Scene {
            source: PathBuf::from("test.toml"),
            camera: Camera::look_at(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0),
            film: Film { width: 4, height: 4 },
            render: RenderSettings::default(),
            textures: vec![Arc::new(Texture::from_texels(
                2,
                1,
                vec![Vec4::ONE, Vec4::splat(3.0)],
                [WrapMode::Repeat; 2],
            ))],
            materials: vec![Material::Diffuse {
                albedo: TexRgb::Constant(Vec3::splat(0.5)),
            }],
            shapes,
            lights,
            environment,
            provenance: Default::default(),
        }
    }

    fn rect() -> Geometry {
        Geometry::Rectangle {
            center: Vec3::new(0.0, 2.0, 0.0),
            half_u: Vec3::X,
            half_v: Vec3::Z,
        }
    }

    fn full_scene() -> Scene {
        let mesh = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![[0, 1, 2]],
            ..Mesh::default()
        };
        scene(
            vec![
                shape(
                    "floor",
                    Geometry::Disk {
                        center: Vec3::ZERO,
                        half_u: Vec3::X,
                        half_v: Vec3::Z,
                    },
                    None,
                ),
                shape("panel", rect(), Some(Vec3::splat(4.0))),
                shape(
                    "ball",
                    Geometry::Sphere {
                        center: Vec3::Y,
                        radius: 0.5,
                    },
                    Some(Vec3::new(1.0, 0.0, 0.0)),
                ),
                shape("dark", Geometry::Mesh(Arc::new(mesh)), Some(Vec3::ZERO)),
            ],
            vec![
                Light::Point {
                    name: "bulb".into(),
                    position: Vec3::new(1.0, 3.0, 0.0),
                    intensity: Vec3::splat(10.0),
                },
                Light::Directional {
                    name: "sun".into(),
                    direction: -Vec3::Y,
                    irradiance: Vec3::splat(2.0),
                    angular_diameter_deg: 0.53,
                },
            ],
            Some(Environment::Map {
                texture: 0,
                scale: 0.5,
            }),
        )
    }

    #[test]
    fn light_set_orders_maps_and_selects_by_power() {
        let s = full_scene();
        let set = LightSet::new(&s).unwrap();
        assert_eq!(set.named_count(), s.light_names().len());
        assert_eq!(set.emitters().len(), 6);
        assert_eq!(set.environment(), Some(5));
        assert_eq!(set.distant(), [4, 5], "sun disk and environment");
        let map: Vec<_> = (0..5).map(|i| set.emitter_of_shape(i)).collect();
        assert_eq!(map, [None, Some(0), Some(1), Some(2), None]);
        assert!(matches!(set.emitters()[0], Emitter::Rectangle(_)));
        assert!(matches!(set.emitters()[3], Emitter::Point(_)));
        assert!(matches!(set.emitters()[4], Emitter::Directional(_)));
        let total: f32 = set.emitters().iter().map(|e| e.power()).sum();
        let sum: f32 = (0..6).map(|i| set.selection_pmf(i, Vec3::ZERO)).sum();
        assert!((sum - 1.0).abs() < 1e-6, "Σ pmf = {sum}");
        for (i, e) in set.emitters().iter().enumerate() {
            let want = e.power() / total;
            assert!(
                (set.selection_pmf(i, Vec3::ZERO) - want).abs() < 1e-6,
                "pmf[{i}] = {}, expected {want}",
                set.selection_pmf(i, Vec3::ZERO)
            );
        }
        assert_eq!(
            set.selection_pmf(2, Vec3::ZERO),
            0.0,
            "zero-power mesh must never be selected"
        );
        // Φ of the 4 m² panel with L = 4: π·4·4.
        assert!((set.emitters()[0].power() - 16.0 * PI_F32).abs() < 1e-3);
    }

    const PI_F32: f32 = std::f32::consts::PI;

    #[test]
    fn light_set_sample_multiplies_by_selection_probability() {
        let set = LightSet::new(&full_scene()).unwrap();
        let p = Vec3::new(0.2, 0.5, 0.1);
        for k in 0..200 {
            let u_sel = (k as f32 + 0.5) / 200.0;
            let u = Vec2::new(0.37, 0.61);
            let Some((i, s)) = set.sample(p, u_sel, u) else {
                continue;
            };
            let single = set.emitters()[i].sample_li(p, u).unwrap();
            let want = single.pdf * set.selection_pmf(i, p);
            assert!(
                (s.pdf - want).abs() <= 1e-6 * want,
                "emitter {i}: pdf {}, expected {want}",
                s.pdf
            );
            assert_ne!(i, 2, "zero-power emitter selected");
        }
    }

    #[test]
    fn light_set_all_zero_power_is_uniform_and_empty_is_none() {
        let dark = scene(
            vec![shape("a", rect(), Some(Vec3::ZERO))],
            vec![Light::Point {
                name: "b".into(),
                position: Vec3::Y,
                intensity: Vec3::ZERO,
            }],
            None,
        );
        let set = LightSet::new(&dark).unwrap();
        assert!(
            (set.selection_pmf(0, Vec3::ZERO) - 0.5).abs() < 1e-7
                && (set.selection_pmf(1, Vec3::ZERO) - 0.5).abs() < 1e-7
        );
        let empty = LightSet::new(&scene(vec![], vec![], None)).unwrap();
        assert!(empty.sample(Vec3::ZERO, 0.5, Vec2::splat(0.5)).is_none());
        assert_eq!(
            (
                empty.named_count(),
                empty.environment(),
                empty.selection_pmf(0, Vec3::ZERO)
            ),
            (0, None, 0.0)
        );
    }

    #[test]
    fn light_set_errors_name_the_shape_light_and_field() {
        let zero_area = Geometry::Rectangle {
            center: Vec3::ZERO,
            half_u: Vec3::X,
            half_v: Vec3::ZERO,
        };
        let cases: Vec<(Scene, &[&str])> = vec![
            (
                scene(vec![shape("lamp", zero_area, Some(Vec3::ONE))], vec![], None),
                &["shape 'lamp' (shapes[0])", "half_u", "zero area"],
            ),
            (
                scene(
                    vec![shape("neg", rect(), Some(Vec3::new(1.0, -1.0, 0.0)))],
                    vec![],
                    None,
                ),
                &["shape 'neg'", "emission.radiance", "≥ 0"],
            ),
            (
                scene(
                    vec![shape(
                        "nan",
                        Geometry::Sphere {
                            center: Vec3::ZERO,
                            radius: f32::NAN,
                        },
                        Some(Vec3::ONE),
                    )],
                    vec![],
                    None,
                ),
                &["shape 'nan'", "geometry.radius"],
            ),
            (
                scene(
                    vec![],
                    vec![
                        Light::Point {
                            name: "ok".into(),
                            position: Vec3::Y,
                            intensity: Vec3::ONE,
                        },
                        Light::Point {
                            name: "bad".into(),
                            position: Vec3::Y,
                            intensity: Vec3::new(f32::NAN, 0.0, 0.0),
                        },
                    ],
                    None,
                ),
                &["light 'bad' (lights[1])", "intensity"],
            ),
            (
                scene(
                    vec![],
                    vec![],
                    Some(Environment::Map {
                        texture: 3,
                        scale: 1.0,
                    }),
                ),
                &["environment", "texture = 3"],
            ),
            (
                scene(
                    vec![],
                    vec![],
                    Some(Environment::Constant {
                        radiance: Vec3::splat(f32::INFINITY),
                    }),
                ),
                &["environment", "radiance"],
            ),
        ];
        for (s, needles) in cases {
            let e = LightSet::new(&s).unwrap_err();
            for n in needles {
                assert!(e.contains(n), "error {e:?} should mention {n:?}");
            }
        }
        // A textured emission whose texture index is out of range.
        let mut s = scene(vec![shape("tex", rect(), Some(Vec3::ONE))], vec![], None);
        s.shapes[0].emission = Some(Emission {
            radiance: TexRgb::Image {
                texture: 9,
                factor: Vec3::ONE,
            },
            two_sided: true,
        });
        let e = LightSet::new(&s).unwrap_err();
        assert!(
            e.contains("shape 'tex'") && e.contains("emission.radiance.texture = 9"),
            "{e}"
        );
    }

    /// With many lights (the per-region selection grid), light sampling stays unbiased: the
    /// unshadowed irradiance estimated from `sample` (selection × light pdf) matches Lambert's
    /// closed form summed over 24 one-sided ceiling lights of three radiances, at points near
    /// and far from most of them.
    #[test]
    fn light_set_many_lights_irradiance_is_unbiased() {
        use crate::light::test_support::{polygon_irradiance, Pcg32};
        let mut shapes = vec![shape(
            "floor",
            Geometry::Rectangle {
                center: Vec3::ZERO,
                half_u: Vec3::new(4.0, 0.0, 0.0),
                half_v: Vec3::new(0.0, 0.0, -4.0),
            },
            None,
        )];
        let mut lights = Vec::new();
        for k in 0..24 {
            let center = Vec3::new(-2.5 + (k % 6) as f32, 3.0, -1.5 + (k / 6) as f32);
            let (half_u, half_v) = (Vec3::new(0.1, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.15));
            let l = 1.0 + (k % 3) as f32;
            shapes.push(shape(
                &format!("light{k}"),
                Geometry::Rectangle {
                    center,
                    half_u,
                    half_v,
                },
                Some(Vec3::splat(l)),
            ));
            let corners = [
                center - half_u - half_v,
                center + half_u - half_v,
                center + half_u + half_v,
                center - half_u + half_v,
            ];
            lights.push((corners, l));
        }
        let set = LightSet::new(&scene(shapes, vec![], None)).unwrap();
        assert!(matches!(set.selection, Selection::Grid(_)));
        let mut rng = Pcg32::new(9, 2);
        for p in [
            Vec3::new(-2.5, 0.0, -1.5),
            Vec3::new(0.2, 1.0, 0.3),
            Vec3::new(3.5, 2.5, 3.5),
        ] {
            let want: f32 = lights
                .iter()
                .map(|(c, l)| l * polygon_irradiance(p, Vec3::Y, c))
                .sum();
            let n = 200_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let v = match set.sample(p, rng.next_f32(), rng.next_2d()) {
                    Some((_, s)) => f64::from(s.li.x * Vec3::Y.dot(s.wi).max(0.0) / s.pdf),
                    None => 0.0,
                };
                sum += v;
                sum2 += v * v;
            }
            let mean = sum / f64::from(n);
            let stderr = ((sum2 / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
            assert!(
                (mean - f64::from(want)).abs() < 4.0 * stderr + 1e-4 * f64::from(want),
                "{p}: E = {mean} ± {stderr}, Lambert {want}"
            );
        }
    }
}
