//! Environment mapping: one reflector shaded from maps captured at a point, the classic
//! real-time stand-in for reflections of its surroundings, and its parameters.
//!
//! Each render captures six 90° views from the capture point with the realtime renderer
//! itself (the reflector left out), into a radiance cube, and derives the maps the method
//! reads ([`build`], [`filter`], `technique/envmap/filter.wgsl`): box mips, prefiltered specular
//! levels, an irradiance cube, nine spherical-harmonic coefficients, and for the sphere and
//! paraboloid methods the same levels warped into their parameterization. The reflector is
//! then shaded from the maps along R = 2(n·ωo)n − ωo (`technique/envmap/envmap.wgsl`); every other
//! shape as under `area_quadrature`. The ground truth (docs/ARCHITECTURE.md) is the oracle's exact
//! reflection of the real local geometry; a scene with its local objects switched off
//! (`enabled = false`) is the distant-only variant that measures parameterization and filtering
//! apart from the infinitely-distant assumption. The distance impostors
//! ([`super::distance_impostor`]) are the cube map with that assumption dropped.
//!
//! The methods, their papers and their parameters with ranges and defaults are [`METHODS`]
//! and [`COMMON`] (docs/methods.md is made from them). Besides those, an environment-mapping
//! method takes `detail` (a surface-detail method, or `none`: lookups by its perturbed normal —
//! environment-mapped normal mapping, EMNM — with that method's parameters), `n` and `env_n`
//! (as `area_quadrature`: the capture's and the other shapes' shading; default 8 and 8).
//!
//! Levels: ⌊log₂ s⌋ − 1 (at most 8), level k of side ⌊s/2ᵏ⌋ holding the lobe of roughness
//! r = k/(levels − 1); a material of width α reads level √α·(levels − 1) (trilinear).

use std::fmt;

use glam::Vec3;

use super::detail::{self, Detail};
use super::method::{wgsl_method_codes, Family, Method, MethodInfo, Row};
use super::param::{Kind, MethodSpec, Param, Value};
use localization::Localization;

pub(crate) mod build;
pub(crate) mod filter;
pub mod localization;

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

impl Parameterization {
    /// The value of the WGSL override constant `ENVMAP_METHOD`: 1 + its index in [`METHODS`]
    /// (0: none).
    pub fn shader_code(self) -> u32 {
        match self {
            Parameterization::Cube => 1,
            Parameterization::Sphere => 2,
            Parameterization::Paraboloid => 3,
        }
    }

    /// The method name.
    pub fn name(self) -> &'static str {
        METHODS[self.shader_code() as usize - 1].name
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

impl Irradiance {
    /// `envmap.info.y` of envmap/envmap.wgsl (`IRRADIANCE_MAP`, `IRRADIANCE_SH9`).
    pub fn shader_code(self) -> u32 {
        match self {
            Irradiance::Map => 0,
            Irradiance::Sh9 => 1,
        }
    }
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
    /// distances ([`super::distance_impostor`]; `Distant` for the `envmap_*` methods).
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

    /// Its parameter rows: [`COMMON`], then those of `spec` (its method's row of
    /// [`METHODS`] or of the distance impostors').
    pub fn rows(
        &self,
        spec: &'static MethodSpec<EnvMapping>,
    ) -> impl Iterator<Item = &'static Param<EnvMapping>> {
        COMMON.iter().chain(spec.params)
    }
}

/// The parameters every environment-mapping method shares, distance impostors included
/// (`n` and `env_n` are every method's, default 8 and 8; `detail` is the method's).
pub static COMMON: &[Param<EnvMapping>] = &[
    Param {
        name: "size",
        kind: Kind::Whole(*ENVMAP_SIZES.start(), *ENVMAP_SIZES.end()),
        unit: "texels per side",
        doc: "side of the map at level 0 (and of the capture's cube faces)",
        source: "",
        unset: "",
        get: |e| Some(Value::Whole(e.size)),
        set: |e, v| {
            e.size = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "filter_samples",
        kind: Kind::Whole(1, MAX_FILTER_SAMPLES),
        unit: "",
        doc: "samples per texel of the lobe prefilter (filtered importance sampling)",
        source: "Křivánek & Colbert 2008, \"Real-time Shading with Filtered Importance Sampling\", CGF 27(4)",
        unset: "",
        get: |e| Some(Value::Whole(e.filter_samples)),
        set: |e, v| {
            e.filter_samples = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "prefilter",
        kind: Kind::Keyword(&["lobe", "box"]),
        unit: "",
        doc: "lobe: each level convolved with the material's lobe (GGX or normalized Phong); \
              box: the plain box mips, the cheap variant",
        source: "Karis 2013, \"Real Shading in Unreal Engine 4\" (split sum, n = v = r)",
        unset: "",
        get: |e| {
            Some(Value::Keyword(match e.prefilter {
                Prefilter::Lobe => "lobe",
                Prefilter::Box => "box",
            }))
        },
        set: |e, v| {
            e.prefilter = match v.keyword()? {
                "lobe" => Prefilter::Lobe,
                _ => Prefilter::Box,
            };
            Some(())
        },
    },
    Param {
        name: "irradiance",
        kind: Kind::Keyword(&["map", "sh9"]),
        unit: "",
        doc: "map: a 16² cosine-convolved cube; sh9: nine spherical-harmonic coefficients",
        source: "Ramamoorthi & Hanrahan 2001, \"An Efficient Representation for Irradiance Environment Maps\", SIGGRAPH",
        unset: "",
        get: |e| {
            Some(Value::Keyword(match e.irradiance {
                Irradiance::Map => "map",
                Irradiance::Sh9 => "sh9",
            }))
        },
        set: |e, v| {
            e.irradiance = match v.keyword()? {
                "map" => Irradiance::Map,
                _ => Irradiance::Sh9,
            };
            Some(())
        },
    },
    Param {
        name: "dominant_direction",
        kind: Kind::Switch,
        unit: "",
        doc: "glossy lookups along the lobe's dominant direction, between n and R by the roughness (off: along R)",
        source: "Lagarde & de Rousiers 2014, \"Moving Frostbite to Physically Based Rendering\", SIGGRAPH course",
        unset: "",
        get: |e| Some(Value::Switch(e.dominant_direction)),
        set: |e, v| {
            e.dominant_direction = v.switch()?;
            Some(())
        },
    },
    Param {
        name: "reflector",
        kind: Kind::Name,
        unit: "",
        doc: "the shape shaded from the maps",
        source: "",
        unset: "the scene's one non-diffuse, non-emissive shape, or its one non-emissive shape",
        get: |e| e.reflector.clone().map(Value::Name),
        set: |e, v| match v {
            Value::Name(n) => {
                e.reflector = Some(n);
                Some(())
            }
            _ => None,
        },
    },
    Param {
        name: "capture",
        kind: Kind::Vector,
        unit: "m",
        doc: "the point the maps are captured at",
        source: "",
        unset: "the reflector's bounding-box centre",
        get: |e| e.capture.map(Value::Vector),
        set: |e, v| {
            e.capture = Some(v.vector()?);
            Some(())
        },
    },
];

/// The environment-mapping methods, in `ENVMAP_METHOD` order (1, 2, 3).
pub static METHODS: &[MethodSpec<EnvMapping>] = &[
    MethodSpec {
        name: "envmap_cube",
        summary: "cube map, hardware-seamless filtering; 6·s² texels",
        source: "Greene 1986, \"Environment Mapping and Other Applications of World Projections\", IEEE CG&A 6(11)",
        default: || EnvMapping::new(Parameterization::Cube),
        params: &[],
    },
    MethodSpec {
        name: "envmap_sphere",
        summary: "sphere map for one view direction, warped from the cube; s² texels",
        source: "Miller & Hoffman 1984, \"Illumination and Reflection Maps\", SIGGRAPH course notes",
        default: || EnvMapping::new(Parameterization::Sphere),
        params: &[Param {
            name: "sphere_view",
            kind: Kind::Vector,
            unit: "",
            doc: "the direction from the reflector towards the viewer the map is made for (not zero)",
            source: "",
            unset: "towards the scene's camera",
            get: |e| e.sphere_view.map(Value::Vector),
            set: |e, v| {
                e.sphere_view = Some(v.vector()?.try_normalize()?);
                Some(())
            },
        }],
    },
    MethodSpec {
        name: "envmap_paraboloid",
        summary: "dual-paraboloid map about +Y, warped from the cube; 2·s² texels",
        source: "Heidrich & Seidel 1998, \"View-independent Environment Maps\", Graphics Hardware",
        default: || EnvMapping::new(Parameterization::Paraboloid),
        params: &[Param {
            name: "seam",
            kind: Kind::Keyword(&["fill", "none"]),
            unit: "",
            doc: "fill: the texels past each unit disk continue the parameterization; none: black",
            source: "",
            unset: "",
            get: |e| Some(Value::Keyword(if e.seam_fill { "fill" } else { "none" })),
            set: |e, v| {
                e.seam_fill = v.keyword()? == "fill";
                Some(())
            },
        }],
    },
];

/// The values of an environment map's `detail`: `none`, then every detail method.
const DETAIL_CHOICES: [&str; 1 + detail::METHODS.len()] = {
    let mut names = ["none"; 1 + detail::METHODS.len()];
    let mut i = 0;
    while i < detail::METHODS.len() {
        names[i + 1] = detail::METHODS[i].name;
        i += 1;
    }
    names
};

/// `detail` of the environment-mapping methods: a surface-detail method, with its parameters,
/// added to the method as its `Detail` part.
pub static DETAIL: Param<Method> = Param {
    name: "detail",
    kind: Kind::Keyword(&DETAIL_CHOICES),
    unit: "",
    doc: "lookups along the normals a surface-detail method perturbs (environment-mapped normal mapping), \
          with that method's parameters; none: the reflector's own normals",
    source: "",
    unset: "",
    get: |m| {
        Some(Value::Keyword(
            m.get::<Detail>().map_or("none", |d| d.technique.name()),
        ))
    },
    set: |m, v| {
        match v.keyword()? {
            "none" => m.remove::<Detail>(),
            name => m.insert(Detail::by_name(name)?),
        }
        Some(())
    },
};

/// The rows every environment-mapping and distance-impostor method shares: [`COMMON`] and
/// `detail`.
pub fn shared_rows() -> Vec<Row> {
    let mut rows = Row::all(COMMON);
    rows.push(Row(&DETAIL));
    rows
}

/// The environment-mapping family.
pub struct EnvironmentMapping;

impl Family for EnvironmentMapping {
    fn title(&self) -> &'static str {
        "Environment mapping"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// Over N×N quadrature (n = 8, env_n = 8), unshadowed, without surface detail.
    fn method(&self, name: &str) -> Option<Method> {
        Method::from_table(METHODS, name, 8)
    }

    fn shared_rows(&self) -> Vec<Row> {
        shared_rows()
    }

    fn wgsl_codes(&self) -> String {
        wgsl_method_codes("ENVMAP_", Some("NONE"), METHODS)
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[("envmap/envmap.wgsl", include_str!("envmap.wgsl"))]
    }
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
}
