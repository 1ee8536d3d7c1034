//! `[[material]]` tables → [`Material`]s, indexed by name.

use std::collections::HashMap;

use glam::Vec3;

use super::inputs::{rgb_const, rgb_input, scalar_input, Bound, Textures};
use super::read::{Field, Table};
use crate::model::{ComplexIor, Masking, Material, Scattering, TexRgb, TexScalar};
use crate::SceneError;

const TYPES: &[&str] = &["diffuse", "phong", "ggx", "metal_rough", "mirror", "dielectric"];

/// Interior IOR default: BK7 glass at 589 nm, as Mitsuba 3's `dielectric` (`int_ior="bk7"`).
const BK7_IOR: f32 = 1.5046;
/// Exterior IOR default: air, as Mitsuba 3's `dielectric` (`ext_ior="air"`).
const AIR_IOR: f32 = 1.000_277;

/// Reads every `[[material]]`; names must be unique.
pub(crate) fn read_all(
    doc: &Table,
    textures: &mut Textures,
) -> Result<(Vec<Material>, HashMap<String, usize>), SceneError> {
    let mut materials = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    let mut lines: Vec<Option<usize>> = Vec::new();
    let Some(list) = doc.get("material") else {
        return Ok((materials, names));
    };
    for t in list.tables()? {
        let name_field = t.req("name")?;
        let name = name_field.str()?;
        if name.is_empty() {
            return Err(name_field.err("a material name cannot be empty"));
        }
        if let Some(&first) = names.get(name) {
            let at = lines[first].map(|l| format!(" on line {l}")).unwrap_or_default();
            return Err(name_field
                .err(format!(
                    "duplicate material name {} (first defined{at})",
                    crate::error::echo(name)
                ))
                .hint("give every material its own name"));
        }
        let t = t
            .clone()
            .renamed(format!("material {}", crate::error::echo(name)));
        materials.push(read_one(&t, textures)?);
        names.insert(name.to_string(), materials.len() - 1);
        lines.push(t.line);
    }
    Ok((materials, names))
}

/// One material table.
fn read_one(t: &Table, textures: &mut Textures) -> Result<Material, SceneError> {
    let kind = t.req("type")?.keyword(TYPES)?;
    let fields: &[&str] = match kind {
        "diffuse" => &["name", "type", "albedo"],
        "phong" => &["name", "type", "reflectance", "exponent"],
        "ggx" => &[
            "name",
            "type",
            "reflectance",
            "f0",
            "eta",
            "k",
            "roughness",
            "masking",
            "scattering",
        ],
        "metal_rough" => &[
            "name",
            "type",
            "base_color",
            "metallic",
            "roughness",
            "scattering",
        ],
        "mirror" => &["name", "type", "reflectance"],
        _ => &["name", "type", "int_ior", "ext_ior"],
    };
    if let (Some(f), false) = (t.get("scattering"), fields.contains(&"scattering")) {
        return Err(f
            .err(format!("a {kind} material has no microsurface to scatter on"))
            .hint("scattering = \"multiple\" applies to ggx and metal_rough materials"));
    }
    t.only(fields, &format!("a {kind} material"))?;
    let mut rgb = |key: &str, default: f32| -> Result<TexRgb, SceneError> {
        match t.get(key) {
            Some(f) => rgb_input(&f, Bound::Unit, textures),
            None => Ok(TexRgb::Constant(Vec3::splat(default))),
        }
    };
    Ok(match kind {
        // Mitsuba 3 `diffuse`: reflectance defaults to 0.5.
        "diffuse" => Material::Diffuse {
            albedo: rgb("albedo", 0.5)?,
        },
        "phong" => Material::Phong {
            reflectance: rgb("reflectance", 1.0)?,
            exponent: phong_exponent(&t.req("exponent")?)?,
        },
        "ggx" => {
            let reflectance = rgb("reflectance", 1.0)?;
            let masking = match t.get("masking") {
                Some(m) => match m.keyword(&["height_correlated", "separable"])? {
                    "separable" => Masking::Separable,
                    _ => Masking::HeightCorrelated,
                },
                None => Masking::HeightCorrelated,
            };
            let scattering = scattering(t)?;
            if (masking, scattering) == (Masking::Separable, Scattering::Multiple) {
                let f = t.req("masking")?;
                return Err(f
                    .err("multiple scattering needs height-correlated masking, got \"separable\"")
                    .hint("the random walk on the microsurface is height-correlated by construction (Heitz et al. 2016); drop masking or set it to \"height_correlated\""));
            }
            Material::Ggx {
                reflectance,
                f0: rgb_const(t.get("f0"), Bound::Unit, Vec3::ONE)?,
                conductor: conductor(t)?,
                roughness: scalar_input(&t.req("roughness")?, 1, textures)?,
                masking,
                scattering,
            }
        }
        // glTF 2.0 defaults: baseColorFactor 1, metallicFactor 1, roughnessFactor 1.
        "metal_rough" => {
            let base_color = rgb("base_color", 1.0)?;
            Material::MetalRough {
                base_color,
                metallic: scalar(t, "metallic", 2, textures)?,
                roughness: scalar(t, "roughness", 1, textures)?,
                scattering: scattering(t)?,
            }
        }
        "mirror" => Material::Mirror {
            reflectance: rgb_const(t.get("reflectance"), Bound::Unit, Vec3::ONE)?,
        },
        _ => Material::Dielectric {
            int_ior: ior(t.get("int_ior"), BK7_IOR)?,
            ext_ior: ior(t.get("ext_ior"), AIR_IOR)?,
        },
    })
}

/// Largest η and k accepted: metals in the visible have η < 5 and k < 12 (gold, silver,
/// aluminium, tungsten); 100 is far beyond any and keeps η² + k² finite in f32.
const MAX_IOR: f32 = 100.0;

/// The optional complex index `eta`, `k` of a GGX conductor: both or neither, not with `f0`.
fn conductor(t: &Table) -> Result<Option<ComplexIor>, SceneError> {
    let (eta, k) = match (t.get("eta"), t.get("k")) {
        (None, None) => return Ok(None),
        (Some(eta), Some(k)) => (eta, k),
        (Some(f), None) | (None, Some(f)) => {
            return Err(f.err("a conductor needs both eta and k").hint(
                "give the complex index of refraction η + ik per channel, e.g. gold eta = [0.143, 0.374, 1.442], \
                 k = [3.983, 2.385, 1.603]",
            ))
        }
    };
    if let Some(f0) = t.get("f0") {
        return Err(f0
            .err(
                "f0 is Schlick's approximation, and this material gives the exact conductor Fresnel (eta, k)",
            )
            .hint("drop f0, or drop eta and k"));
    }
    let channels = |f: &Field, zero_allowed: bool| -> Result<Vec3, SceneError> {
        let v = f.rgb()?;
        let ok = |x: f32| x <= MAX_IOR && (x > 0.0 || (zero_allowed && x == 0.0));
        if v.to_array().into_iter().all(ok) {
            Ok(v)
        } else {
            let range = if zero_allowed { "[0, 100]" } else { "(0, 100]" };
            Err(f.err(format!(
                "must lie in {range} in every channel, got {:?}",
                v.to_array()
            )))
        }
    };
    Ok(Some(ComplexIor {
        eta: channels(&eta, false)?,
        k: channels(&k, true)?,
    }))
}

/// The optional `scattering` keyword: "single" (the default) or "multiple".
fn scattering(t: &Table) -> Result<Scattering, SceneError> {
    Ok(match t.get("scattering") {
        Some(f) => match f.keyword(&["single", "multiple"])? {
            "multiple" => Scattering::Multiple,
            _ => Scattering::Single,
        },
        None => Scattering::Single,
    })
}

/// An optional scalar input defaulting to 1.
fn scalar(t: &Table, key: &str, channel: usize, textures: &mut Textures) -> Result<TexScalar, SceneError> {
    match t.get(key) {
        Some(f) => scalar_input(&f, channel, textures),
        None => Ok(TexScalar::Constant(1.0)),
    }
}

/// An index of refraction: finite and > 0.
fn ior(field: Option<Field>, default: f32) -> Result<f32, SceneError> {
    field.map_or(Ok(default), |f| f.positive())
}

/// Largest Phong exponent: a lobe cosⁿ falls to half at θ ≈ √(2 ln 2 / n), 0.07° at n = 10⁶;
/// beyond it the normalization (n + 2)/(2π) times cosⁿ underflows and overflows into NaN.
const MAX_PHONG_EXPONENT: f32 = 1e6;

/// A Phong exponent in [0, [`MAX_PHONG_EXPONENT`]].
fn phong_exponent(f: &Field) -> Result<f32, SceneError> {
    let n = f.non_negative()?;
    if n > MAX_PHONG_EXPONENT {
        return Err(f
            .err(format!("must be at most 1e6, got {n:?}"))
            .hint("a lobe of exponent 1e6 is 0.07° wide; use a mirror material for a sharper one"));
    }
    Ok(n)
}
