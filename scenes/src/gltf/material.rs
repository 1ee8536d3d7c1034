//! glTF materials → [`Material::MetalRough`], normal maps and emission; glTF images →
//! linear [`Texture`]s.
//!
//! | glTF (2.0 "Materials") | model | notes |
//! |---|---|---|
//! | baseColorFactor × baseColorTexture (sRGB) | `base_color` | alpha ignored (rendered opaque, noted) |
//! | metallicFactor × metallicRoughnessTexture.B | `metallic` (channel 2) | |
//! | roughnessFactor × metallicRoughnessTexture.G | `roughness` (channel 1) | |
//! | normalTexture (linear), .scale | [`NormalMap`] | tangents from TANGENT or generated |
//! | emissiveFactor × emissiveTexture (sRGB) × KHR_materials_emissive_strength | [`Emission`], front side only | radiance in W·m⁻²·sr⁻¹ taken as is |
//! | occlusionTexture | — | ignored: the oracle computes occlusion exactly |
//! | doubleSided | — | our opaque materials are two-sided already |
//! | no material | glTF default: white, metallic 1, roughness 1 | glTF 2.0 "Default Material" |
//!
//! Sampler wrapS/wrapT map to [`WrapMode`]; filters are the renderers' business. sRGB
//! texels are decoded with the exact IEC 61966-2-1 curve ([`srgb_to_linear`]).

use std::borrow::Cow;
use std::collections::{BTreeSet, HashMap};
use std::path::PathBuf;
use std::sync::Arc;

use ::gltf::material::AlphaMode;
use ::gltf::texture::WrappingMode;
use glam::{Vec3, Vec4};

use super::light::MAX_EMITTED;
use super::source::Asset;
use crate::budget::bytes_of;
use crate::error::SceneError;
use crate::model::{Emission, Material, NormalMap, Scattering, TexRgb, TexScalar, WrapMode};
use crate::srgb::srgb_to_linear;
use crate::texture::{decode_image_bytes, ColorSpace, Texture};

/// What a glTF material turns into, per primitive that uses it.
#[derive(Clone, Debug)]
pub(super) struct Resolved {
    /// Index into the scene's materials.
    pub material: usize,
    /// Emission (front side), if the material emits.
    pub emission: Option<Emission>,
    /// Normal map, if any.
    pub normal_map: Option<NormalMap>,
    /// TEXCOORD set sampled by the material's textures, if it has any.
    pub uv_set: Option<u32>,
}

/// Largest |normalTexture.scale| accepted: beyond it the perturbed normal is tangent to the
/// surface anyway, and from about 10¹⁹ its square overflows f32 when it is normalised.
const MAX_NORMAL_SCALE: f32 = 1e6;

/// Converts materials on demand, sharing textures between them.
pub(super) struct Materials<'a> {
    asset: &'a Asset<'a>,
    /// Scene textures built so far.
    pub textures: Vec<Arc<Texture>>,
    /// Scene materials built so far.
    pub materials: Vec<Material>,
    /// How each glTF material (`None`: the default material) converted.
    pub resolved: HashMap<Option<usize>, Resolved>,
    /// (glTF texture index, is sRGB) → scene texture index.
    slots: HashMap<(usize, bool), usize>,
    /// Decoded images by glTF image index.
    images: HashMap<usize, Arc<::image::DynamicImage>>,
}

impl<'a> Materials<'a> {
    /// An empty table for `asset`.
    pub fn new(asset: &'a Asset<'a>) -> Self {
        Materials {
            asset,
            textures: Vec::new(),
            materials: Vec::new(),
            resolved: HashMap::new(),
            slots: HashMap::new(),
            images: HashMap::new(),
        }
    }

    /// The conversion of `material` (built once, then shared).
    pub fn resolve(
        &mut self,
        material: &::gltf::Material,
        notes: &mut BTreeSet<String>,
    ) -> Result<Resolved, SceneError> {
        if let Some(r) = self.resolved.get(&material.index()) {
            return Ok(r.clone());
        }
        let r = self.convert(material, notes)?;
        self.resolved.insert(material.index(), r.clone());
        Ok(r)
    }

    fn convert(
        &mut self,
        material: &::gltf::Material,
        notes: &mut BTreeSet<String>,
    ) -> Result<Resolved, SceneError> {
        let at = match material.index() {
            Some(i) => format!("materials[{i}]"),
            None => "(default material)".to_string(),
        };
        if material.alpha_mode() != AlphaMode::Opaque {
            notes.insert(format!(
                "{at}.alphaMode: {:?} is ignored; the surface is rendered opaque",
                material.alpha_mode()
            ));
        }
        let mut uv = UvSet::default();
        let (base_color, metallic, roughness) = self.metal_rough(material, &at, &mut uv)?;
        let normal_map = match material.normal_texture() {
            Some(nt) => {
                let field = format!("{at}.normalTexture");
                if nt.scale().is_nan() || nt.scale().abs() > MAX_NORMAL_SCALE {
                    return Err(self.asset.err(
                        format!("{field}.scale"),
                        format!(
                            "must be finite and at most {MAX_NORMAL_SCALE:e} in magnitude, got {}",
                            nt.scale()
                        ),
                    ));
                }
                uv.use_set(self.asset, nt.tex_coord(), &field)?;
                let texture = self.texture(&nt.texture(), ColorSpace::Linear, &field)?;
                Some(NormalMap {
                    texture,
                    scale: nt.scale(),
                })
            }
            None => None,
        };
        let emission = self.emission(material, &at, &mut uv)?;
        self.materials.push(Material::MetalRough {
            base_color,
            metallic,
            roughness,
            scattering: Scattering::Single,
        });
        Ok(Resolved {
            material: self.materials.len() - 1,
            emission,
            normal_map,
            uv_set: uv.set.map(|(s, _)| s),
        })
    }

    /// Base colour, metallic and roughness inputs of `material`'s pbrMetallicRoughness.
    fn metal_rough(
        &mut self,
        material: &::gltf::Material,
        at: &str,
        uv: &mut UvSet,
    ) -> Result<(TexRgb, TexScalar, TexScalar), SceneError> {
        let pbr = material.pbr_metallic_roughness();
        let pbr_at = format!("{at}.pbrMetallicRoughness");
        let bcf = pbr.base_color_factor();
        let base = Vec3::new(bcf[0], bcf[1], bcf[2]);
        self.check_unit(&format!("{pbr_at}.baseColorFactor"), &bcf)?;
        let metallic = pbr.metallic_factor();
        let roughness = pbr.roughness_factor();
        self.check_unit(&format!("{pbr_at}.metallicFactor"), &[metallic])?;
        self.check_unit(&format!("{pbr_at}.roughnessFactor"), &[roughness])?;
        let base_color = match pbr.base_color_texture() {
            Some(info) => {
                let field = format!("{pbr_at}.baseColorTexture");
                uv.use_set(self.asset, info.tex_coord(), &field)?;
                let texture = self.texture(&info.texture(), ColorSpace::Srgb, &field)?;
                TexRgb::Image {
                    texture,
                    factor: base,
                }
            }
            None => TexRgb::Constant(base),
        };
        let (metallic, roughness) = match pbr.metallic_roughness_texture() {
            Some(info) => {
                let field = format!("{pbr_at}.metallicRoughnessTexture");
                uv.use_set(self.asset, info.tex_coord(), &field)?;
                let texture = self.texture(&info.texture(), ColorSpace::Linear, &field)?;
                (
                    TexScalar::Image {
                        texture,
                        channel: 2,
                        factor: metallic,
                    },
                    TexScalar::Image {
                        texture,
                        channel: 1,
                        factor: roughness,
                    },
                )
            }
            None => (TexScalar::Constant(metallic), TexScalar::Constant(roughness)),
        };
        Ok((base_color, metallic, roughness))
    }

    /// emissiveFactor × emissiveTexture × emissive_strength, or `None` when it is zero.
    fn emission(
        &mut self,
        material: &::gltf::Material,
        at: &str,
        uv: &mut UvSet,
    ) -> Result<Option<Emission>, SceneError> {
        let factor = Vec3::from(material.emissive_factor());
        if !(factor.is_finite() && factor.min_element() >= 0.0) {
            return Err(self.asset.err(
                format!("{at}.emissiveFactor"),
                format!("must be finite and ≥ 0, got {factor}"),
            ));
        }
        let strength = material.emissive_strength().unwrap_or(1.0);
        if !(strength.is_finite() && strength >= 0.0) {
            return Err(self.asset.err(
                format!("{at}.extensions.KHR_materials_emissive_strength.emissiveStrength"),
                format!("must be finite and ≥ 0, got {strength}"),
            ));
        }
        let radiance = factor * strength;
        // factor and strength are finite and ≥ 0, so the product is ≥ 0 or +∞, never NaN.
        if radiance.max_element() > MAX_EMITTED {
            return Err(self.asset.err(
                format!("{at}.extensions.KHR_materials_emissive_strength.emissiveStrength"),
                format!(
                    "emissiveStrength {strength:e} × emissiveFactor {factor} exceeds {MAX_EMITTED:e}, more than the renderers can sum in f32"
                ),
            ));
        }
        if radiance == Vec3::ZERO {
            return Ok(None);
        }
        let radiance = match material.emissive_texture() {
            Some(info) => {
                let field = format!("{at}.emissiveTexture");
                uv.use_set(self.asset, info.tex_coord(), &field)?;
                let texture = self.texture(&info.texture(), ColorSpace::Srgb, &field)?;
                TexRgb::Image {
                    texture,
                    factor: radiance,
                }
            }
            None => TexRgb::Constant(radiance),
        };
        Ok(Some(Emission {
            radiance,
            two_sided: false,
        }))
    }

    /// Every value finite and in [0, 1] (glTF's range for colour and strength factors).
    fn check_unit(&self, field: &str, values: &[f32]) -> Result<(), SceneError> {
        if values.iter().all(|v| (0.0..=1.0).contains(v)) {
            Ok(())
        } else {
            Err(self
                .asset
                .err(field, format!("values must lie in [0, 1], got {values:?}")))
        }
    }

    /// The scene texture for glTF `texture` decoded in `space` (shared when reused).
    fn texture(
        &mut self,
        texture: &::gltf::Texture,
        space: ColorSpace,
        field: &str,
    ) -> Result<usize, SceneError> {
        let key = (texture.index(), space == ColorSpace::Srgb);
        if let Some(&slot) = self.slots.get(&key) {
            return Ok(slot);
        }
        let image_index = texture.source().index();
        let image = self.image(&texture.source(), field)?;
        let sampler = texture.sampler();
        let wrap = [wrap_mode(sampler.wrap_s()), wrap_mode(sampler.wrap_t())];
        // `to_texels` makes two RGBA f32 copies (16 bytes a texel each) at once.
        let count = u64::from(image.width()) * u64::from(image.height());
        self.asset.charge(
            bytes_of(count, 2 * 16),
            &format!(
                "the {}×{} RGBA f32 texels of images[{image_index}]",
                image.width(),
                image.height()
            ),
            field,
        )?;
        let texels = to_texels(&image, space);
        let mut tex = Texture::from_texels(image.width(), image.height(), texels, wrap);
        tex.source = PathBuf::from(format!("{}#images[{image_index}]", self.asset.file.display()));
        self.textures.push(Arc::new(tex));
        let slot = self.textures.len() - 1;
        self.slots.insert(key, slot);
        Ok(slot)
    }

    /// Decodes glTF image `image` (PNG or JPEG from a buffer view, file or data URI).
    fn image(
        &mut self,
        image: &::gltf::Image,
        used_by: &str,
    ) -> Result<Arc<::image::DynamicImage>, SceneError> {
        if let Some(img) = self.images.get(&image.index()) {
            return Ok(img.clone());
        }
        let field = format!("images[{}]", image.index());
        let bytes = match image.source() {
            ::gltf::image::Source::View { view, .. } => Cow::Borrowed(self.asset.view_bytes(&view)),
            ::gltf::image::Source::Uri { uri, .. } => {
                Cow::Owned(self.asset.read_uri(uri, &format!("{field}.uri"), None)?)
            }
        };
        let cannot = |e: String| {
            self.asset
                .err(
                    &field,
                    format!("cannot decode the image (used by {used_by}): {e}"),
                )
                .hint("glTF images must be PNG or JPEG")
        };
        // Header first, against the budget (texture.rs); the decoded image stays cached for
        // every texture that uses it: charged at its own size.
        let decoded = decode_image_bytes(&bytes, self.asset.ledger).map_err(cannot)?;
        let (width, height) = (decoded.width(), decoded.height());
        self.asset.charge(
            bytes_of(
                u64::from(width) * u64::from(height),
                decoded.color().bytes_per_pixel().into(),
            ),
            &format!("the {width}×{height} decoded texels of {field}"),
            &field,
        )?;
        let decoded = Arc::new(decoded);
        self.images.insert(image.index(), decoded.clone());
        Ok(decoded)
    }
}

/// The one TEXCOORD set a material's textures share (our meshes carry one uv set).
#[derive(Default)]
struct UvSet {
    set: Option<(u32, String)>,
}

impl UvSet {
    fn use_set(&mut self, asset: &Asset, set: u32, field: &str) -> Result<(), SceneError> {
        match &self.set {
            Some((s, first)) if *s != set => Err(asset.err(
                format!("{field}.texCoord"),
                format!(
                    "uses TEXCOORD_{set} but {first} uses TEXCOORD_{s}; one uv set per material is supported"
                ),
            )),
            Some(_) => Ok(()),
            None => {
                self.set = Some((set, field.to_string()));
                Ok(())
            }
        }
    }
}

/// glTF sampler wrap mode → ours.
fn wrap_mode(mode: WrappingMode) -> WrapMode {
    match mode {
        WrappingMode::ClampToEdge => WrapMode::Clamp,
        WrappingMode::MirroredRepeat => WrapMode::Mirror,
        WrappingMode::Repeat => WrapMode::Repeat,
    }
}

/// RGBA texels in linear space, row 0 at the top; RGB decoded from sRGB when `space` says
/// so, alpha always linear.
fn to_texels(image: &::image::DynamicImage, space: ColorSpace) -> Vec<Vec4> {
    let rgba = image.to_rgba32f();
    rgba.pixels()
        .map(|p| {
            let [r, g, b, a] = p.0;
            match space {
                ColorSpace::Srgb => Vec4::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b), a),
                ColorSpace::Linear => Vec4::new(r, g, b, a),
            }
        })
        .collect()
}
