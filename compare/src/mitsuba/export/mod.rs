//! Scene model → Mitsuba 3 XML scene (+ PLY meshes and EXR images), exactly or not at all.
//!
//! Every element maps to the Mitsuba 3.9.1 plugin that computes the same quantity; what has
//! no exact counterpart is refused with a message naming the item and the feature
//! ([`NotExpressible`]). The mapping (checked against Mitsuba 3.9.1 with probes and by the
//! z-test of every built-in scene):
//!
//! | Verity | Mitsuba 3 |
//! |---|---|
//! | camera (pinhole, vertical fov, rigid `to_world`) | `perspective`, `fov_axis="y"`, `to_world` = `lookat(eye, eye + forward, up)` |
//! | film W×H, box pixel filter | `hdrfilm` rgb float32, `rfilter` `box` (the `centre` pixel filter is refused: the cross-check compares box-filtered pixels) |
//! | `path` (max_depth, rr_depth) | `path` (same semantics), `independent` sampler |
//! | `direct` without mirror/dielectric surfaces | `path` with max_depth 2 (or 1/0 when lower) |
//! | diffuse, mirror, GGX (f0 = 1 or a conductor's η, k; separable masking) | `twosided` `diffuse`, `conductor`, `roughconductor` (`material="none"`, or `eta` and `k`) |
//! | dielectric | `dielectric` (one-sided: it has an inside) |
//! | RGB texture × factor | `bitmap` of the baked texels (float EXR, same wrap, bilinear) |
//! | sphere, rectangle, disk, mesh | `sphere`, `rectangle`/`disk` under the affine map (half_u, half_v, n, center), `ply` |
//! | emission (front side) | `area` |
//! | point, spot, directional (delta) | `point`, `spot`, `directional` |
//! | constant / map environment | `constant` / `envmap` (same image, no rotation: docs/ARCHITECTURE.md) |

mod lights;
mod materials;
mod shapes;

use std::collections::HashMap;
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use glam::Vec3;
use scenes::layered::{write_atomic, LayeredImage};
use scenes::{IntegratorKind, Material, PixelFilter, Scene};

use super::xml::Element;

/// The Mitsuba 3 release the exporter targets and was checked against.
pub const MITSUBA_VERSION: &str = "3.9.1";

/// Name of the scene file inside an export directory.
pub const SCENE_FILE: &str = "scene.xml";

/// A file the XML refers to, by path relative to the XML file.
#[derive(Clone, Debug, PartialEq)]
pub enum Asset {
    /// A binary PLY mesh.
    Ply(Vec<u8>),
    /// An RGB float image (bitmap texture or environment map).
    Exr(LayeredImage),
}

/// An exported scene: the XML text and the files it refers to.
#[derive(Clone, Debug, PartialEq)]
pub struct Export {
    /// The Mitsuba 3 scene file.
    pub xml: String,
    /// Referenced files, as (path relative to the XML file, content).
    pub assets: Vec<(String, Asset)>,
}

/// Why a scene cannot be exported exactly: one line per item and feature.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NotExpressible {
    /// The scene file.
    pub scene: PathBuf,
    /// Each problem names the item (`material #2 (ggx, used by `ball`)`) and the feature.
    pub problems: Vec<String>,
}

impl fmt::Display for NotExpressible {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: Mitsuba 3 cannot express this scene exactly: {}",
            self.scene.display(),
            self.problems.join("; ")
        )
    }
}

impl std::error::Error for NotExpressible {}

/// Exports `scene` with its own `film` and `render` settings (apply command-line overrides to
/// the scene first). Collects every problem before refusing.
pub fn export(scene: &Scene) -> Result<Export, NotExpressible> {
    let mut ex = Exporter::new(scene);
    let mut root = Element::new("scene")
        .attr("version", "3.0.0")
        .with_comment(format!(
            "Exported by verity {} from {} for Mitsuba {MITSUBA_VERSION}.",
            env!("CARGO_PKG_VERSION"),
            scene.source.display()
        ));
    root.children.push(ex.integrator());
    root.children.push(ex.sensor());
    let bsdfs = ex.bsdfs();
    root.children.extend(bsdfs);
    let shapes = ex.shapes();
    root.children.extend(shapes);
    let lights = ex.lights();
    root.children.extend(lights);
    if ex.problems.is_empty() {
        Ok(Export {
            xml: format!("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n{}", root.render()),
            assets: ex.assets,
        })
    } else {
        Err(NotExpressible {
            scene: scene.source.clone(),
            problems: ex.problems,
        })
    }
}

impl Export {
    /// Writes `scene.xml` and its assets into `dir` (created if needed), each file atomically;
    /// returns the XML path.
    pub fn write(&self, dir: &Path) -> io::Result<PathBuf> {
        std::fs::create_dir_all(dir).map_err(|e| {
            io::Error::new(
                e.kind(),
                format!("{}: cannot create directory: {e}", dir.display()),
            )
        })?;
        for (name, asset) in &self.assets {
            let path = dir.join(name);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).map_err(|e| {
                    io::Error::new(
                        e.kind(),
                        format!("{}: cannot create directory: {e}", parent.display()),
                    )
                })?;
            }
            match asset {
                Asset::Ply(bytes) => write_atomic(&path, bytes)?,
                Asset::Exr(image) => image.write_exr(&path)?,
            }
        }
        let xml = dir.join(SCENE_FILE);
        write_atomic(&xml, self.xml.as_bytes())?;
        Ok(xml)
    }
}

/// Export state: the scene, the problems found, the files to write.
struct Exporter<'a> {
    scene: &'a Scene,
    problems: Vec<String>,
    assets: Vec<(String, Asset)>,
    /// Baked texture files by (texture index, factor bits).
    texture_files: HashMap<(usize, [u32; 3]), String>,
}

impl<'a> Exporter<'a> {
    fn new(scene: &'a Scene) -> Self {
        Exporter {
            scene,
            problems: Vec::new(),
            assets: Vec::new(),
            texture_files: HashMap::new(),
        }
    }

    fn refuse(&mut self, problem: String) {
        self.problems.push(problem);
    }

    /// Whether any shape uses a mirror or dielectric material (a perfect-specular surface).
    fn has_specular_surfaces(&self) -> bool {
        self.scene.shapes.iter().any(|s| {
            matches!(
                self.scene.materials.get(s.material),
                Some(Material::Mirror { .. } | Material::Dielectric { .. })
            )
        })
    }

    /// `path` with the scene's depth and Russian-roulette start.
    fn integrator(&mut self) -> Element {
        let s = self.scene.render;
        let max_depth = match s.integrator {
            IntegratorKind::Path => s.max_depth,
            IntegratorKind::Direct => {
                if self.has_specular_surfaces() {
                    self.refuse(
                        "integrator `direct`: ours follows perfect-specular chains (mirror, dielectric) \
                         before the direct-light bounce; Mitsuba's `direct` and `path` have no such mode"
                            .into(),
                    );
                }
                // Without specular surfaces `direct` is emission + one bounce of direct light.
                if s.max_depth < 0 || s.max_depth >= 2 {
                    2
                } else {
                    s.max_depth
                }
            }
            IntegratorKind::DirectUnshadowed => {
                self.refuse(format!(
                    "integrator `{}`: Mitsuba 3 cannot ignore visibility",
                    IntegratorKind::DirectUnshadowed.name()
                ));
                2
            }
            IntegratorKind::Ao => {
                self.refuse("integrator `ao`: Mitsuba 3 has no ambient-occlusion integrator".into());
                1
            }
        };
        Element::plugin("integrator", "path")
            .child(Element::integer("max_depth", i64::from(max_depth)))
            .child(Element::integer("rr_depth", i64::from(s.rr_depth)))
            .child(Element::boolean("hide_emitters", false))
    }

    /// `perspective` sensor with the `hdrfilm` and `independent` sampler.
    fn sensor(&mut self) -> Element {
        if self.scene.render.pixel_filter != PixelFilter::Box {
            self.refuse(format!(
                "pixel_filter `{}`: only the box pixel filter is exported (Mitsuba's `rfilter` `box`)",
                self.scene.render.pixel_filter.name()
            ));
        }
        let cam = &self.scene.camera;
        let eye = cam.position();
        let forward = cam.forward();
        let up = Vec3::from(cam.to_world.matrix3.y_axis).normalize();
        let (center, radius) = self.scene.bounding_sphere();
        // Far enough for the whole scene (Mitsuba's default far clip is 10⁴ m).
        let far = ((center - eye).length() + radius) * 4.0;
        let film = &self.scene.film;
        Element::plugin("sensor", "perspective")
            .child(Element::string("fov_axis", "y"))
            .child(Element::float("fov", cam.fov_y_deg))
            .child(Element::float("near_clip", 1e-4))
            .child(Element::float("far_clip", far.max(1e4)))
            .child(
                Element::new("transform")
                    .attr("name", "to_world")
                    .child(lookat(eye, eye + forward, up)),
            )
            .child(
                Element::plugin("sampler", "independent")
                    .child(Element::integer("sample_count", i64::from(self.scene.render.spp)))
                    .child(Element::integer(
                        "seed",
                        (self.scene.render.seed % (1 << 31)) as i64,
                    )),
            )
            .child(
                Element::plugin("film", "hdrfilm")
                    .child(Element::integer("width", i64::from(film.width)))
                    .child(Element::integer("height", i64::from(film.height)))
                    .child(Element::string("pixel_format", "rgb"))
                    .child(Element::string("component_format", "float32"))
                    .child(Element::plugin("rfilter", "box")),
            )
    }

    /// The file of texture `index` × `factor` as linear float RGB (a `bitmap`'s `filename`).
    fn texture_file(&mut self, index: usize, factor: Vec3) -> String {
        let key = (index, factor.to_array().map(f32::to_bits));
        if let Some(name) = self.texture_files.get(&key) {
            return name.clone();
        }
        let tex = &self.scene.textures[index];
        let texels: Vec<Vec3> = tex.texels.iter().map(|t| t.truncate() * factor).collect();
        let mut image = LayeredImage::new(tex.width, tex.height);
        image.push_rgb("", &texels);
        let name = format!("textures/tex{index}-{}.exr", self.texture_files.len());
        self.assets.push((name.clone(), Asset::Exr(image)));
        self.texture_files.insert(key, name.clone());
        name
    }
}

/// `<lookat origin target up/>`.
fn lookat(origin: Vec3, target: Vec3, up: Vec3) -> Element {
    use super::xml::triple;
    Element::new("lookat")
        .attr("origin", triple(origin))
        .attr("target", triple(target))
        .attr("up", triple(up))
}
