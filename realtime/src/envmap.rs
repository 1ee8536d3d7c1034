//! Environment mapping: one reflector shaded from maps captured at a point, the classic
//! real-time stand-in for reflections of its surroundings, and its parameters.
//!
//! Each render captures six 90° views from the capture point with the realtime renderer
//! itself (the reflector left out), into a radiance cube, and derives the maps the method
//! reads (`envmap_build.rs`, `shaders/envmap_filter.wgsl`): box mips, prefiltered specular
//! levels, an irradiance cube, nine spherical-harmonic coefficients, and for the sphere and
//! paraboloid methods the same levels warped into their parameterization. The reflector is
//! then shaded from the maps along R = 2(n·ωo)n − ωo (`shaders/envmap.wgsl`); every other
//! shape as under `area_quadrature`. The ground truth (DESIGN.md) is the oracle's exact
//! reflection of the real local geometry; a scene with its local objects switched off
//! (`enabled = false`) is the distant-only variant that measures parameterization and filtering
//! apart from the infinitely-distant assumption. The distance impostors
//! ([`crate::distance_impostor`]) are the cube map with that assumption dropped.
//!
//! | method | map | texels at `size` s | parameters (default) |
//! |---|---|---|---|
//! | `envmap_cube` | cube map (Greene 1986) | 6·s² | common |
//! | `envmap_sphere` | sphere map for one view direction (Miller & Hoffman 1984), warped from the cube | s² | common, `sphere_view` (towards the camera) |
//! | `envmap_paraboloid` | dual-paraboloid map about +Y (Heidrich & Seidel 1998), warped from the cube | 2·s² | common, `seam` (`fill`) |
//!
//! Common parameters: `size` (the map's side at level 0, 128: 4..=2048; the capture's cube
//! face has the same side), `filter_samples` (samples per texel of the specular prefilter, 64:
//! 1..=4096), `prefilter` (`lobe`: the material's lobe, GGX or normalized Phong, by filtered
//! importance sampling; `box`: the box mips as they are — the cheap variant), `irradiance`
//! (`map`: a 16² cosine-convolved cube; `sh9`: nine SH coefficients), `dominant_direction`
//! (`off`: glossy lookups along R, as Karis 2013; `on`: along the lobe's dominant direction,
//! between n and R by the roughness, Lagarde & de Rousiers 2014), `reflector` (the shape's
//! name; default: the scene's one non-diffuse, non-emissive shape, or its one non-emissive shape), `capture` (`x,y,z`,
//! default the reflector's bounding-box centre), `detail` (a surface-detail method, or
//! `none`: lookups by its perturbed normal — environment-mapped normal mapping, EMNM — with
//! that method's parameters), `n` and `env_n` (as `area_quadrature`: the capture's and the
//! other shapes' shading; default 8 and 8).
//!
//! Levels: ⌊log₂ s⌋ − 1 (at most 8), level k of side ⌊s/2ᵏ⌋ holding the lobe of roughness
//! r = k/(levels − 1); a material of width α reads level √α·(levels − 1) (trilinear).

use std::fmt;

use glam::Vec3;

use crate::detail::{Detail, DetailTechnique};
use crate::distance_impostor::Localization;

/// Smallest and largest `size`.
pub const ENVMAP_SIZES: std::ops::RangeInclusive<u32> = 4..=2048;
/// Largest `filter_samples`.
pub const MAX_FILTER_SAMPLES: u32 = 4096;
/// Most prefiltered levels.
pub const MAX_ENVMAP_LEVELS: u32 = 8;
/// Side of the irradiance cube's faces.
pub const IRRADIANCE_SIZE: u32 = 16;

/// How directions map to texels (WGSL `ENVMAP_METHOD`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Parameterization {
    /// Six square faces.
    Cube,
    /// One disk: a mirror ball's image seen from `sphere_view`.
    Sphere,
    /// Two disks, the hemispheres about +Y.
    Paraboloid,
}

/// Every environment-mapping method name, in [`Parameterization::shader_code`] order.
pub const ENVMAP_NAMES: [&str; 3] = ["envmap_cube", "envmap_sphere", "envmap_paraboloid"];

impl Parameterization {
    /// The value of the WGSL override constant `ENVMAP_METHOD` (0: none).
    pub fn shader_code(self) -> u32 {
        match self {
            Parameterization::Cube => 1,
            Parameterization::Sphere => 2,
            Parameterization::Paraboloid => 3,
        }
    }

    /// The method name.
    pub fn name(self) -> &'static str {
        ENVMAP_NAMES[self.shader_code() as usize - 1]
    }

    /// The parameterization of method `name`.
    pub fn by_name(name: &str) -> Option<Parameterization> {
        match name {
            "envmap_cube" => Some(Parameterization::Cube),
            "envmap_sphere" => Some(Parameterization::Sphere),
            "envmap_paraboloid" => Some(Parameterization::Paraboloid),
            _ => None,
        }
    }

    /// Layers of the map (cube faces, paraboloid halves).
    pub fn layers(self) -> u32 {
        match self {
            Parameterization::Cube => 6,
            Parameterization::Sphere => 1,
            Parameterization::Paraboloid => 2,
        }
    }
}

/// What the glossy lookups read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Prefilter {
    /// Each level convolved with the material's lobe (GGX, or normalized Phong).
    Lobe,
    /// The box-filtered mips of the radiance cube, unconvolved.
    Box,
}

/// How diffuse reflection is looked up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Irradiance {
    /// A cosine-convolved irradiance cube.
    Map,
    /// Nine spherical-harmonic coefficients.
    Sh9,
}

/// An environment-mapping method and its parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvMapping {
    /// The map's parameterization.
    pub parameterization: Parameterization,
    /// Side of level 0 (cube faces, the sphere map, each paraboloid).
    pub size: u32,
    /// Samples per texel of the lobe prefilter.
    pub filter_samples: u32,
    /// Lobe prefiltering or plain box mips.
    pub prefilter: Prefilter,
    /// Irradiance cube or SH9.
    pub irradiance: Irradiance,
    /// Glossy lookups along the GGX lobe's dominant direction, between n and R, instead of R
    /// (Lagarde & de Rousiers 2014).
    pub dominant_direction: bool,
    /// Paraboloid only: fill the texels past each unit disk with the continued
    /// parameterization (the seam handled), or leave them black.
    pub seam_fill: bool,
    /// The reflector's shape name (None: the scene's one non-diffuse, non-emissive shape, or
    /// its one non-emissive shape).
    pub reflector: Option<String>,
    /// The capture point (None: the reflector's bounding-box centre).
    pub capture: Option<Vec3>,
    /// Sphere map only: the direction from the reflector towards the viewer the map is made
    /// for (None: towards the scene's camera).
    pub sphere_view: Option<Vec3>,
    /// Cube map only: how mirror and dielectric lookups are localized by the stored
    /// distances ([`crate::distance_impostor`]; `Distant` for the `envmap_*` methods).
    pub localization: Localization,
    /// Localized only: trace a dielectric's refracted ray to its exit through the
    /// refractor's own distance map.
    pub double_refraction: bool,
}

impl EnvMapping {
    /// `parameterization` with the defaults of the module table.
    pub fn new(parameterization: Parameterization) -> EnvMapping {
        EnvMapping {
            parameterization,
            size: 128,
            filter_samples: 64,
            prefilter: Prefilter::Lobe,
            irradiance: Irradiance::Map,
            dominant_direction: false,
            seam_fill: true,
            reflector: None,
            capture: None,
            sphere_view: None,
            localization: Localization::Distant,
            double_refraction: false,
        }
    }

    /// The method called `name` with its defaults: an `envmap_*` or distance-impostor
    /// method (a localized cube map).
    pub fn by_name(name: &str) -> Option<EnvMapping> {
        if let Some(p) = Parameterization::by_name(name) {
            return Some(EnvMapping::new(p));
        }
        Localization::by_name(name).map(|localization| EnvMapping {
            localization,
            ..EnvMapping::new(Parameterization::Cube)
        })
    }

    /// The method name.
    pub fn name(&self) -> &'static str {
        self.localization
            .name()
            .unwrap_or_else(|| self.parameterization.name())
    }

    /// Prefiltered levels at level-0 side `size`: ⌊log₂ size⌋ − 1, between 1 and
    /// [`MAX_ENVMAP_LEVELS`] (the last one's side is 2–3 texels at most, 4 at least).
    pub fn levels(size: u32) -> u32 {
        (size.max(1).ilog2())
            .saturating_sub(1)
            .clamp(1, MAX_ENVMAP_LEVELS)
    }

    /// Texels of the prefiltered map at level 0 (the memory the equal-memory study equalises).
    pub fn texels(&self) -> u64 {
        u64::from(self.parameterization.layers()) * u64::from(self.size) * u64::from(self.size)
    }

    /// The parameter names this method accepts besides `n`, `env_n` and the detail's.
    pub(crate) fn param_names(&self) -> Vec<&'static str> {
        let mut names = vec![
            "size",
            "filter_samples",
            "prefilter",
            "irradiance",
            "dominant_direction",
            "reflector",
            "capture",
            "detail",
        ];
        match self.parameterization {
            Parameterization::Cube => {}
            Parameterization::Sphere => names.push("sphere_view"),
            Parameterization::Paraboloid => names.push("seam"),
        }
        names.extend(self.localization.param_names());
        names
    }

    /// Sets `key` from `value` (ranges already named by the caller's spec); None if refused.
    pub(crate) fn set(&mut self, key: &str, value: &str) -> Option<()> {
        match key {
            "size" => {
                let v: u32 = value.parse().ok()?;
                self.size = ENVMAP_SIZES.contains(&v).then_some(v)?;
            }
            "filter_samples" => {
                let v: u32 = value.parse().ok()?;
                self.filter_samples = (1..=MAX_FILTER_SAMPLES).contains(&v).then_some(v)?;
            }
            "prefilter" => {
                self.prefilter = match value {
                    "lobe" => Prefilter::Lobe,
                    "box" => Prefilter::Box,
                    _ => return None,
                }
            }
            "irradiance" => {
                self.irradiance = match value {
                    "map" => Irradiance::Map,
                    "sh9" => Irradiance::Sh9,
                    _ => return None,
                }
            }
            "dominant_direction" => {
                self.dominant_direction = match value {
                    "on" | "true" => true,
                    "off" | "false" => false,
                    _ => return None,
                }
            }
            "seam" => {
                self.seam_fill = match value {
                    "fill" => true,
                    "none" => false,
                    _ => return None,
                }
            }
            "reflector" => {
                let v = value.trim();
                self.reflector = (!v.is_empty()).then(|| v.to_string());
                self.reflector.as_ref()?;
            }
            "capture" => self.capture = Some(parse_vec3(value)?),
            "sphere_view" => {
                let v = parse_vec3(value)?;
                self.sphere_view = Some(v.try_normalize()?);
            }
            "double_refraction" => {
                self.double_refraction = match value {
                    "on" | "true" => true,
                    "off" | "false" => false,
                    _ => return None,
                }
            }
            _ => self.localization.set(key, value)?,
        }
        Some(())
    }

    /// Its own parameters as `k=v` pairs (the detail's are the caller's).
    pub(crate) fn params(&self, detail: Option<&Detail>) -> Vec<(&'static str, String)> {
        let mut p = vec![
            ("size", self.size.to_string()),
            ("filter_samples", self.filter_samples.to_string()),
            (
                "prefilter",
                match self.prefilter {
                    Prefilter::Lobe => "lobe",
                    Prefilter::Box => "box",
                }
                .to_string(),
            ),
            (
                "irradiance",
                match self.irradiance {
                    Irradiance::Map => "map",
                    Irradiance::Sh9 => "sh9",
                }
                .to_string(),
            ),
        ];
        p.push((
            "dominant_direction",
            if self.dominant_direction { "on" } else { "off" }.to_string(),
        ));
        if let Some(r) = &self.reflector {
            p.push(("reflector", r.clone()));
        }
        if let Some(c) = self.capture {
            p.push(("capture", format_vec3(c)));
        }
        match self.parameterization {
            Parameterization::Cube => {}
            Parameterization::Sphere => {
                if let Some(v) = self.sphere_view {
                    p.push(("sphere_view", format_vec3(v)));
                }
            }
            Parameterization::Paraboloid => {
                p.push(("seam", if self.seam_fill { "fill" } else { "none" }.to_string()));
            }
        }
        p.extend(self.localization.params(self));
        p.push((
            "detail",
            detail.map_or("none", |d| d.technique.name()).to_string(),
        ));
        p
    }
}

/// `x,y,z` (brackets and spaces allowed: `[0, 1, 2]`) as three finite numbers.
fn parse_vec3(value: &str) -> Option<Vec3> {
    let inner = value.trim().trim_start_matches('[').trim_end_matches(']');
    let v: Vec<f32> = inner
        .split(',')
        .map(|c| c.trim().parse::<f32>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()?;
    (v.len() == 3).then(|| Vec3::new(v[0], v[1], v[2]))
}

fn format_vec3(v: Vec3) -> String {
    format!("{},{},{}", v.x, v.y, v.z)
}

/// The detail method called `name` with its defaults, `none` (Some(None)), or None if unknown.
pub(crate) fn detail_by_name(name: &str) -> Option<Option<Detail>> {
    if name == "none" {
        return Some(None);
    }
    DetailTechnique::by_name(name).map(|t| Some(Detail::new(t)))
}

impl fmt::Display for Parameterization {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_and_memory() {
        assert_eq!(EnvMapping::levels(128), 6);
        assert_eq!(EnvMapping::levels(157), 6);
        assert_eq!(EnvMapping::levels(4), 1);
        assert_eq!(EnvMapping::levels(2048), 8);
        let cube = EnvMapping::new(Parameterization::Cube);
        let sphere = EnvMapping {
            size: 314,
            ..EnvMapping::new(Parameterization::Sphere)
        };
        let parab = EnvMapping {
            size: 222,
            ..EnvMapping::new(Parameterization::Paraboloid)
        };
        assert_eq!(cube.texels(), 98_304);
        assert!((sphere.texels() as f64 / 98_304.0 - 1.0).abs() < 0.01);
        assert!((parab.texels() as f64 / 98_304.0 - 1.0).abs() < 0.01);
    }

    #[test]
    fn vectors_parse() {
        assert_eq!(parse_vec3("1,2,3"), Some(Vec3::new(1.0, 2.0, 3.0)));
        assert_eq!(parse_vec3("[0, -1.5, 2]"), Some(Vec3::new(0.0, -1.5, 2.0)));
        for bad in ["1,2", "1,2,3,4", "a,b,c", "1,NaN,2", ""] {
            assert_eq!(parse_vec3(bad), None, "{bad}");
        }
    }
}
