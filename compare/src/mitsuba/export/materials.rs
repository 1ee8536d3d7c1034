//! Materials → Mitsuba 3 BSDFs, and RGB inputs → `rgb` values or `bitmap` textures.
//!
//! Ours are two-sided except the dielectric (scenes/src/model.rs, `Material`); Mitsuba's are
//! one-sided, so they are wrapped in `twosided`. GGX: Mitsuba's `roughconductor` takes
//! alpha directly (alpha = roughness², Walter et al. 2007 / Burley 2012 remapping) and uses
//! the separable Smith masking G1(ωi)·G1(ωo) (Mitsuba 3 `roughconductor` docs); with
//! `material="none"` its Fresnel term is 1, which is our Schlick Fresnel with f0 = 1; given
//! `eta` and `k` it is the exact conductor Fresnel, which is ours for a GGX with `eta`, `k`.
//!
//! Textures: our texel centres are at ((i + ½)/W, (j + ½)/H) with v = 0 the top row, bilinear,
//! one wrap mode per axis (scenes/src/texture.rs); Mitsuba 3.9.1's `bitmap` with
//! `filter_type="bilinear"` places texels the same way, with v = 0 the first (top) row and
//! `repeat`/`clamp`/`mirror` matching ours exactly (probed with `bitmap.eval` at 15 uv points
//! per mode). It has one wrap mode for both axes, so different modes per axis are refused.
//! A factor is baked into the exported texels (exact: bilinear filtering is linear).

use glam::Vec3;
use scenes::{ComplexIor, Masking, Material, Scattering, TexRgb, TexScalar, WrapMode};

use super::Exporter;
use crate::mitsuba::xml::Element;

/// Id of the Mitsuba BSDF exported for material `index`.
pub(super) fn bsdf_id(index: usize) -> String {
    format!("bsdf-{index}")
}

impl Exporter<'_> {
    /// One `<bsdf id="bsdf-i">` per material some shape uses (unused ones are skipped, so
    /// they cannot make a scene inexpressible).
    pub(super) fn bsdfs(&mut self) -> Vec<Element> {
        let mut out = Vec::new();
        for (index, material) in self.scene.materials.iter().enumerate() {
            let users: Vec<&str> = self
                .scene
                .shapes
                .iter()
                .filter(|s| s.material == index)
                .map(|s| s.name.as_str())
                .collect();
            if users.is_empty() {
                continue;
            }
            let what = format!(
                "material #{index} ({}, used by `{}`)",
                material_kind(material),
                users.join("`, `")
            );
            if let Some(bsdf) = self.bsdf(material, &what) {
                out.push(bsdf.attr("id", bsdf_id(index)));
            }
        }
        out
    }

    fn bsdf(&mut self, material: &Material, what: &str) -> Option<Element> {
        let one_sided = match material {
            Material::Diffuse { albedo } => {
                let reflectance = self.rgb_input("reflectance", albedo, what)?;
                Element::plugin("bsdf", "diffuse").child(reflectance)
            }
            Material::Mirror { reflectance } => Element::plugin("bsdf", "conductor")
                .child(Element::string("material", "none"))
                .child(Element::rgb("specular_reflectance", *reflectance)),
            Material::Ggx {
                scattering: Scattering::Multiple,
                ..
            } => {
                self.refuse(format!(
                    "{what}: multiple scattering on the microsurface (Heitz et al. 2016) has no \
                     Mitsuba 3 counterpart (`roughconductor` is single-scattering)"
                ));
                return None;
            }
            Material::Ggx {
                reflectance,
                f0,
                roughness,
                masking,
                scattering: Scattering::Single,
                conductor,
            } => self.ggx(reflectance, *f0, *conductor, roughness, *masking, what)?,
            Material::Dielectric { int_ior, ext_ior } => {
                // One-sided on purpose: the dielectric has an inside.
                return Some(
                    Element::plugin("bsdf", "dielectric")
                        .child(Element::float("int_ior", *int_ior))
                        .child(Element::float("ext_ior", *ext_ior)),
                );
            }
            Material::Phong { .. } => {
                self.refuse(format!(
                    "{what}: Mitsuba 3 has no normalized Phong lobe (its `phong` plugin was not ported from Mitsuba 0.6)"
                ));
                return None;
            }
            Material::MetalRough { .. } => {
                self.refuse(format!(
                    "{what}: glTF metallic-roughness (Lambert + GGX mixed by Schlick Fresnel) has no exact \
                     Mitsuba 3 counterpart (`principled` uses a different diffuse and Fresnel)"
                ));
                return None;
            }
        };
        Some(Element::plugin("bsdf", "twosided").child(one_sided))
    }

    /// `roughconductor` for GGX with f0 = 1 or a conductor's exact Fresnel, separable masking and
    /// a constant roughness.
    fn ggx(
        &mut self,
        reflectance: &TexRgb,
        f0: Vec3,
        conductor: Option<ComplexIor>,
        roughness: &TexScalar,
        masking: Masking,
        what: &str,
    ) -> Option<Element> {
        let mut ok = true;
        if conductor.is_none() && f0 != Vec3::ONE {
            self.refuse(format!(
                "{what}: Schlick Fresnel with f0 = {f0} ≠ 1; Mitsuba's `roughconductor` has either F = 1 \
                 (material=\"none\") or the exact conductor Fresnel"
            ));
            ok = false;
        }
        if masking == Masking::HeightCorrelated {
            self.refuse(format!(
                "{what}: height-correlated Smith masking; Mitsuba's `roughconductor` uses the separable \
                 form (set `masking = \"separable\"`)"
            ));
            ok = false;
        }
        let alpha = match roughness {
            TexScalar::Constant(r) if *r > 0.0 => Some(r * r),
            TexScalar::Constant(_) => {
                self.refuse(format!(
                    "{what}: roughness 0 is a mirror; Mitsuba's `roughconductor` needs alpha > 0 (use a `mirror`)"
                ));
                None
            }
            TexScalar::Image { .. } => {
                self.refuse(format!(
                    "{what}: textured roughness; Mitsuba filters alpha, we filter roughness and square it, \
                     which differ between texels"
                ));
                None
            }
        };
        let spec = self.rgb_input("specular_reflectance", reflectance, what);
        let (alpha, spec) = (alpha?, spec?);
        if !ok {
            return None;
        }
        let bsdf = Element::plugin("bsdf", "roughconductor")
            .child(Element::string("distribution", "ggx"))
            .child(Element::float("alpha", alpha))
            .child(Element::boolean("sample_visible", true));
        // F = 1, or the conductor's exact Fresnel of the same complex index (verified against
        // `roughconductor`'s at 0°, 40° and 70°: equal to 10⁻⁷).
        let bsdf = match conductor {
            None => bsdf.child(Element::string("material", "none")),
            Some(ior) => bsdf
                .child(Element::rgb("eta", ior.eta))
                .child(Element::rgb("k", ior.k)),
        };
        Some(bsdf.child(spec))
    }

    /// `<rgb name=… value=…/>` for a constant, `<texture type="bitmap" name=…>` for an image.
    pub(super) fn rgb_input(&mut self, name: &str, input: &TexRgb, what: &str) -> Option<Element> {
        match input {
            TexRgb::Constant(c) => Some(Element::rgb(name, *c)),
            TexRgb::Image { texture, factor } => {
                let wrap = self.scene.textures[*texture].wrap;
                if wrap[0] != wrap[1] {
                    self.refuse(format!(
                        "{what}: texture with wrap modes {:?} in u and {:?} in v; Mitsuba's `bitmap` has one \
                         wrap mode for both axes",
                        wrap[0], wrap[1]
                    ));
                    return None;
                }
                let file = self.texture_file(*texture, *factor);
                Some(
                    Element::plugin("texture", "bitmap")
                        .attr("name", name)
                        .child(Element::string("filename", &file))
                        .child(Element::string("filter_type", "bilinear"))
                        .child(Element::string("wrap_mode", wrap_name(wrap[0])))
                        .child(Element::boolean("raw", true)),
                )
            }
        }
    }
}

/// Mitsuba's `wrap_mode` name for a wrap mode.
fn wrap_name(mode: WrapMode) -> &'static str {
    match mode {
        WrapMode::Repeat => "repeat",
        WrapMode::Clamp => "clamp",
        WrapMode::Mirror => "mirror",
    }
}

/// The TOML `type` name of a material (for messages).
pub(super) fn material_kind(m: &Material) -> &'static str {
    match m {
        Material::Diffuse { .. } => "diffuse",
        Material::Phong { .. } => "phong",
        Material::Ggx { .. } => "ggx",
        Material::MetalRough { .. } => "metal_rough",
        Material::Mirror { .. } => "mirror",
        Material::Dielectric { .. } => "dielectric",
    }
}
