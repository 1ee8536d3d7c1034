//! Energy compensation: what a GGX lobe adds back for the light that single scattering loses
//! (technique/energy/*.wgsl). A single-scattering microfacet BRDF lets light leave after one
//! reflection; light that meets a second microfacet is dropped, up to 69 % of it for a white
//! conductor at α = 1 and normal incidence (1 − ln 2 is what stays; the oracle's closed form).
//! The ground truth is the oracle's multiple-scattering random walk (Heitz, Hanika, d'Eon &
//! Dachsbacher 2016; `scattering = "multiple"` on the material), and the single-scattering
//! image is the truth of `energy_none`.
//!
//! Every method reads one table, generated here ([`tables`]) and uploaded with the scene's
//! textures: per (cos θo, roughness) texel the split-sum scale and bias A, B of single-scattering
//! GGX with height-correlated masking (E_ss(μ) = f0·A + B under Schlick's Fresnel, E = A + B
//! for F = 1) and the cosine-weighted average E_avg = 2∫E(μ)μ dμ of its row.
//!
//! | method | adds to f_ss·cos θi | failure mode |
//! |---|---|---|
//! | `energy_kulla_conty` | (1 − E(μo))(1 − E(μi))/(π(1 − E_avg)) · F_ms · cos θi, F_ms = F_avg²E_avg/(1 − F_avg(1 − E_avg)) | the lobe's shape is a separable guess (diffuse-like at grazing angles) |
//! | `energy_turquin` | f_ss·cos θi · f0·(1/E(μo) − 1) | scales the single-scattering lobe: no light where it has none, colour only from f0 |
//! | `energy_fdez_aguera` | F_ms·E_ms(μo)/π · cos θi, E_ms = 1 − E, F_ms = E_ss·F_avg/(1 − E_ms·F_avg) | built for image-based lighting: a Lambertian lobe, not reciprocal |
//!
//! F_avg = f0 + (1 − f0)/21 is Schlick's Fresnel averaged over the cosine-weighted hemisphere
//! (2∫(1 − μ)⁵μ dμ = 1/21). For the GGX material the microfacet reflectance is k·F (k its
//! `reflectance`), so k multiplies f0 and F_avg; for glTF metal-rough only the metal's lobe
//! (f0 = base colour, weighted by metalness) is compensated, as the oracle's ground truth
//! defines it; the dielectric layer stays single-scattering in both.

pub mod tables;

use super::method::{wgsl_method_codes, Family, Method, MethodInfo, Override, Row, Settings};
use super::param::{Kind, MethodSpec, Param, Value};

/// Which compensation (WGSL `ENERGY_*`, the pipeline constant `ENERGY_METHOD`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Compensation {
    /// Single scattering only.
    None,
    /// Kulla & Conty 2017.
    KullaConty,
    /// Turquin 2019.
    Turquin,
    /// Fdez-Agüera 2019.
    FdezAguera,
}

/// An energy-compensation method and the resolution of the table it reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EnergyCompensation {
    /// The method.
    pub compensation: Compensation,
    /// Texels of the table along cos θo and along roughness.
    pub lut: u32,
}

/// Default table resolution: 32 × 32, as Karis 2013's split-sum table.
pub const DEFAULT_LUT: u32 = 32;

impl EnergyCompensation {
    /// WGSL `ENERGY_METHOD` (and `frame.energy.x`): its index in [`METHODS`] (WGSL
    /// `ENERGY_NONE` … `ENERGY_FDEZ_AGUERA`).
    pub fn shader_code(&self) -> u32 {
        self.compensation as u32
    }

    /// Whether it reads the table.
    pub fn needs_table(&self) -> bool {
        self.compensation != Compensation::None
    }

    /// The method's row in [`METHODS`].
    pub fn spec(&self) -> &'static MethodSpec<EnergyCompensation> {
        &METHODS[self.shader_code() as usize]
    }

    /// Its parameter rows.
    pub fn rows(&self) -> impl Iterator<Item = &'static Param<EnergyCompensation>> {
        self.spec().params.iter()
    }
}

const LUT: Param<EnergyCompensation> = Param {
    name: "lut",
    kind: Kind::Whole(2, 256),
    unit: "texels",
    doc: "N of the N×N table over (cos θo, roughness), texel i at i/(N − 1), read bilinearly",
    source: "Karis 2013, \"Real Shading in Unreal Engine 4\", SIGGRAPH course (32×32 split-sum table)",
    unset: "",
    get: |e| Some(Value::Whole(e.lut)),
    set: |e, v| {
        e.lut = v.whole()?;
        Some(())
    },
};

/// The energy-compensation methods (every method's `n`, `env_n`, `mesh_n`; the table's `lut`).
pub static METHODS: &[MethodSpec<EnergyCompensation>] = &[
    MethodSpec {
        name: "energy_none",
        summary: "single-scattering GGX: light that meets a second microfacet is lost (up to 69 % at roughness 1)",
        source: "Walter, Marschner, Li & Torrance 2007, \"Microfacet Models for Refraction through Rough Surfaces\", EGSR",
        default: || EnergyCompensation {
            compensation: Compensation::None,
            lut: DEFAULT_LUT,
        },
        params: &[],
    },
    MethodSpec {
        name: "energy_kulla_conty",
        summary: "adds a separable lobe (1 − E(μo))(1 − E(μi))/(π(1 − E_avg)) coloured by F_ms = F_avg²E_avg/(1 − \
                  F_avg(1 − E_avg))",
        source: "Kulla & Conty 2017, \"Revisiting Physically Based Shading at Imageworks\", SIGGRAPH course",
        default: || EnergyCompensation {
            compensation: Compensation::KullaConty,
            lut: DEFAULT_LUT,
        },
        params: &[LUT],
    },
    MethodSpec {
        name: "energy_turquin",
        summary: "scales the single-scattering lobe by 1 + f0·(1/E(μo) − 1)",
        source: "Turquin 2019, \"Practical multiple scattering compensation for microfacet models\", ILM tech. report",
        default: || EnergyCompensation {
            compensation: Compensation::Turquin,
            lut: DEFAULT_LUT,
        },
        params: &[LUT],
    },
    MethodSpec {
        name: "energy_fdez_aguera",
        summary: "adds a Lambertian lobe F_ms·(1 − E(μo))/π, F_ms = E_ss·F_avg/(1 − (1 − E)·F_avg), from the split-sum \
                  table",
        source: "Fdez-Agüera 2019, \"A Multiple-Scattering Microfacet Model for Real-Time Image-based Lighting\", JCGT \
                 8(1)",
        default: || EnergyCompensation {
            compensation: Compensation::FdezAguera,
            lut: DEFAULT_LUT,
        },
        params: &[LUT],
    },
];

/// The energy-compensation family.
pub struct EnergyCompensationFamily;

impl Family for EnergyCompensationFamily {
    fn title(&self) -> &'static str {
        "Energy compensation"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// Over N×N quadrature (n = 8, env_n = 8), unshadowed.
    fn method(&self, name: &str) -> Option<Method> {
        Method::from_table(METHODS, name, 8)
    }

    fn wgsl_codes(&self) -> String {
        wgsl_method_codes("ENERGY_", None, METHODS)
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("energy/table.wgsl", include_str!("table.wgsl")),
            ("energy/kulla_conty.wgsl", include_str!("kulla_conty.wgsl")),
            ("energy/turquin.wgsl", include_str!("turquin.wgsl")),
            ("energy/fdez_aguera.wgsl", include_str!("fdez_aguera.wgsl")),
        ]
    }
}

impl Settings for EnergyCompensation {
    fn method_name(&self) -> &'static str {
        self.spec().name
    }

    fn rows(&self) -> Vec<Row> {
        Row::all(EnergyCompensation::rows(self))
    }

    fn overrides(&self) -> Vec<Override> {
        vec![Override::shading("ENERGY_METHOD", self.shader_code())]
    }
}

/// WGSL `ENERGY_METHOD` of `m` (and `frame.energy.x`): its part's, or `ENERGY_NONE`.
pub fn code(m: &Method) -> u32 {
    m.get::<EnergyCompensation>()
        .map_or(0, EnergyCompensation::shader_code)
}
