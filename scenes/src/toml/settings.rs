//! `[camera]`, `[film]`, `[render]` and `[environment]`.

use glam::Vec3;

use super::inputs::{rgb_const, Bound, Textures};
use super::read::{Field, Table};
use crate::gltf::AssetCamera;
use crate::model::{Camera, Environment, Film, IntegratorKind, RenderSettings, SamplerKind, WrapMode};
use crate::pixel_filter::PixelFilter;
use crate::texture::ColorSpace;
use crate::SceneError;

/// Largest film side, and the largest pixel count (2^28 = 16384²).
const MAX_SIDE: i64 = 16384;
const MAX_PIXELS: u64 = 1 << 28;
/// Default film side when `[film]` leaves it out.
const DEFAULT_SIDE: u32 = 256;

/// `[camera]`: eye, target, up (default +Y), fov (vertical, degrees, in (0, 180)). Instead of
/// `eye`, an orbit about the target: `distance` (m, > 0), `azimuth` and `elevation` (degrees,
/// default 0; elevation in (−90, 90)) put the eye at
/// target + distance·(cos e·sin a, sin e, cos e·cos a): azimuth about +Y from +Z, elevation
/// above the XZ plane (what a view-angle sweep turns).
pub(crate) fn camera(t: &Table) -> Result<Camera, SceneError> {
    t.only(
        &["eye", "target", "up", "fov", "distance", "azimuth", "elevation"],
        "the camera",
    )?;
    let target_field = t.req("target")?;
    let target = target_field.position()?;
    let orbit = ["distance", "azimuth", "elevation"].map(|k| t.get(k));
    let eye = match (t.get("eye"), &orbit) {
        (Some(eye), [None, None, None]) => eye.position()?,
        (Some(_), _) => {
            let extra = orbit.iter().flatten().next().expect("an orbit field is present");
            return Err(extra
                .err("the camera has both `eye` and an orbit field")
                .hint("give either `eye`, or `distance` with optional `azimuth`/`elevation`"));
        }
        (None, [distance, azimuth, elevation]) => {
            let Some(distance_field) = distance else {
                return Err(t
                    .err("the camera needs `eye`, or `distance` (with optional `azimuth`/`elevation`)")
                    .hint("add `eye = [x, y, z]`"));
            };
            let d = distance_field.length()?;
            if !(d > 0.0 && d.is_finite()) {
                return Err(distance_field.err(format!("must be a finite distance > 0 m, got {d}")));
            }
            let degrees = |f: &Option<Field>| -> Result<f32, SceneError> {
                match f {
                    Some(f) => {
                        let v = f.f32()?;
                        if v.is_finite() {
                            Ok(v)
                        } else {
                            Err(f.err(format!("must be finite degrees, got {v}")))
                        }
                    }
                    None => Ok(0.0),
                }
            };
            let a = degrees(azimuth)?.to_radians();
            let e_deg = degrees(elevation)?;
            if !(e_deg > -90.0 && e_deg < 90.0) {
                let f = elevation.as_ref().expect("a nonzero elevation was given");
                return Err(f
                    .err(format!("must be in (−90, 90) degrees, got {e_deg}"))
                    .hint("looking straight down or up needs `eye` and an `up` not along the view"));
            }
            let e = e_deg.to_radians();
            target + d * Vec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
        }
    };
    let up = match t.get("up") {
        Some(f) => f.direction()?,
        None => Vec3::Y,
    };
    let fov_field = t.req("fov")?;
    let fov = fov_field.f32()?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(fov_field
            .err(format!("must be in (0, 180) degrees, got {fov}"))
            .hint("fov is the full vertical field of view in degrees"));
    }
    let view = target - eye;
    if view.length() <= 1e-6 * eye.abs().max(target.abs()).max_element().max(1.0) {
        return Err(target_field
            .err("the camera target equals the eye position")
            .hint("move the target away from the eye"));
    }
    if view.normalize().cross(up).length() < 1e-4 {
        let at = t.get("up").unwrap_or(target_field);
        return Err(at
            .err("`up` is parallel to the view direction (target − eye)")
            .hint(
                "give an up vector that is not along the view (e.g. [0, 0, -1] when looking straight down)",
            ));
    }
    Ok(Camera::look_at(eye, target, up, fov))
}

/// `[film]` as written: the sides it gives, each checked, with its field;
/// [`FilmSides::resolve`] makes the film once the camera is known.
pub(crate) struct FilmSides<'a> {
    width: Option<(u32, Field<'a>)>,
    height: Option<(u32, Field<'a>)>,
}

/// `[film]`: width, height (pixels, default 256 each; see [`FilmSides::resolve`]).
pub(crate) fn film(t: Option<Table>) -> Result<FilmSides, SceneError> {
    let Some(t) = t else {
        return Ok(FilmSides {
            width: None,
            height: None,
        });
    };
    t.only(&["width", "height"], "the film")?;
    let side = |key: &str| -> Result<Option<(u32, Field)>, SceneError> {
        let Some(f) = t.get(key) else { return Ok(None) };
        let v = f.i64()?;
        if (1..=MAX_SIDE).contains(&v) {
            Ok(Some((v as u32, f)))
        } else {
            Err(f
                .err(format!("must be in 1..={MAX_SIDE} pixels, got {v}"))
                .hint("render large images in tiles or lower the resolution"))
        }
    };
    let (width, height) = (side("width")?, side("height")?);
    // Only two given sides can exceed it: one side and the default (or an aspect) stay within
    // 16384² = 2^28.
    if let (Some((w, _)), Some((h, _))) = (&width, &height) {
        if u64::from(*w) * u64::from(*h) > MAX_PIXELS {
            return Err(t.err(format!("{w}×{h} pixels is more than 2^28")));
        }
    }
    Ok(FilmSides { width, height })
}

impl FilmSides<'_> {
    /// The film. Under the scene file's own camera: the sides given, 256 for each left out.
    /// Under an included asset's camera (`[[include]] camera`) with an `aspectRatio` a:
    /// without `[film]` sides, the asset's own film (512 high, width round(512·a)); with one
    /// side, the other is round(width / a) or round(height·a); with both, they must have the
    /// aspect a up to rounding ([`Film::fits_aspect`]) or it is an error. An asset camera
    /// without `aspectRatio` (glTF: the viewport's aspect is used) takes the sides given, or
    /// the asset's square film when none are.
    pub fn resolve(&self, asset: Option<&AssetCamera>) -> Result<Film, SceneError> {
        let given = |s: &Option<(u32, Field)>| s.as_ref().map(|(v, _)| *v);
        let (w, h) = (given(&self.width), given(&self.height));
        let aspect = asset.and_then(|c| c.aspect);
        let (width, height) = match (asset, aspect, &self.width, &self.height) {
            (Some(c), _, None, None) => (c.film.width, c.film.height),
            (_, Some(a), Some((w, f)), None) => (*w, follow(f, "height", f64::from(*w) / f64::from(a), a)?),
            (_, Some(a), None, Some((h, f))) => (follow(f, "width", f64::from(*h) * f64::from(a), a)?, *h),
            (_, Some(a), Some((w, _)), Some((h, f))) => {
                if !(Film {
                    width: *w,
                    height: *h,
                })
                .fits_aspect(a)
                {
                    return Err(f
                        .err(format!(
                            "{w}×{h} pixels has the aspect ratio {:.4}, but the included camera's aspectRatio is {a}",
                            f64::from(*w) / f64::from(*h)
                        ))
                        .hint("give only `width` (the height follows the camera's aspect ratio) or only `height`"));
                }
                (*w, *h)
            }
            _ => (w.unwrap_or(DEFAULT_SIDE), h.unwrap_or(DEFAULT_SIDE)),
        };
        Ok(Film { width, height })
    }
}

/// The film side `key` that the camera's aspect ratio `a` makes from the side `given`:
/// round(`exact`), which must lie in 1..=16384.
fn follow(given: &Field, key: &str, exact: f64, a: f32) -> Result<u32, SceneError> {
    let side = exact.round();
    if (1.0..=MAX_SIDE as f64).contains(&side) {
        return Ok(side as u32);
    }
    Err(given
        .err(format!(
            "with the included camera's aspectRatio {a}, it makes the film {key} {side}, outside 1..={MAX_SIDE}"
        ))
        .hint("give the other side instead"))
}

/// `[render]`: spp, integrator, max_depth, rr_depth, seed, ao_radius, sampler, pixel_filter
/// (defaults as [`RenderSettings::default`]).
pub(crate) fn render(t: Option<Table>) -> Result<RenderSettings, SceneError> {
    let mut r = RenderSettings::default();
    let Some(t) = t else {
        return Ok(r);
    };
    t.only(
        &[
            "spp",
            "integrator",
            "max_depth",
            "rr_depth",
            "seed",
            "ao_radius",
            "sampler",
            "pixel_filter",
        ],
        "the render settings",
    )?;
    if let Some(f) = t.get("spp") {
        r.spp = f.int_in(1, i64::from(u32::MAX))? as u32;
    }
    if let Some(f) = t.get("integrator") {
        r.integrator = f.one_of(&IntegratorKind::SPELLINGS)?;
    }
    if let Some(f) = t.get("max_depth") {
        let d = f.int_in(-1, i64::from(i32::MAX))?;
        if d == 0 {
            return Err(f
                .err("must be -1 (unbounded) or >= 1, got 0")
                .hint("1 = emitters seen directly, 2 = direct illumination"));
        }
        r.max_depth = d as i32;
    }
    if let Some(f) = t.get("rr_depth") {
        r.rr_depth = f.int_in(1, i64::from(u32::MAX))? as u32;
    }
    if let Some(f) = t.get("seed") {
        r.seed = f.int_in(0, i64::MAX)? as u64;
    }
    if let Some(f) = t.get("ao_radius") {
        r.ao_radius = f.positive()?;
    }
    if let Some(f) = t.get("sampler") {
        r.sampler = match f.keyword(&["sobol", "independent"])? {
            "independent" => SamplerKind::Independent,
            _ => SamplerKind::Sobol,
        };
    }
    if let Some(f) = t.get("pixel_filter") {
        r.pixel_filter = f.one_of(&PixelFilter::SPELLINGS)?;
    }
    Ok(r)
}

/// `[environment]`: `radiance = [r, g, b]`, or `file = "…"` with `scale` (default 1) and
/// `negative` (what to do with negative texels: `"error"`, the default, or `"clamp"` them to
/// 0). Returns the environment and how many texels were clamped.
pub(crate) fn environment(t: &Table, textures: &mut Textures) -> Result<(Environment, u64), SceneError> {
    t.only(&["radiance", "file", "scale", "negative"], "the environment")?;
    match t.one_of(&["radiance", "file"])? {
        Some("radiance") => {
            for key in ["scale", "negative"] {
                if let Some(f) = t.get(key) {
                    return Err(f.err(format!(
                        "`{key}` applies to an environment `file`, not to `radiance`"
                    )));
                }
            }
            let radiance = rgb_const(t.get("radiance"), Bound::NonNegative, Vec3::ZERO)?;
            Ok((Environment::Constant { radiance }, 0))
        }
        Some(_) => {
            let scale = match t.get("scale") {
                Some(f) => f.non_negative()?,
                None => 1.0,
            };
            let clamp = match t.get("negative") {
                Some(f) => f.keyword(&["error", "clamp"])? == "clamp",
                None => false,
            };
            let file = t.req("file")?;
            let first_new = textures.list.len();
            let texture = textures.load(&file, ColorSpace::Srgb, [WrapMode::Repeat, WrapMode::Clamp])?;
            let tex = &textures.list[texture];
            let negative = |t: &glam::Vec4| t.truncate().min_element() < 0.0;
            let Some(i) = tex.texels.iter().position(negative) else {
                return Ok((Environment::Map { texture, scale }, 0));
            };
            if !clamp {
                let (x, y) = (i % tex.width as usize, i / tex.width as usize);
                return Err(file
                    .err(format!(
                        "the environment map has negative radiance (first at texel ({x}, {y}))"
                    ))
                    .hint("add `negative = \"clamp\"` to set negative components to 0, or clamp the image; lossy EXR compression can leave negative ringing"));
            }
            // A texture an earlier input shares (same file, colour space and wrap) is copied,
            // so that only the environment sees the clamped texels.
            let texture = if texture < first_new {
                let copy = (**tex).clone();
                textures
                    .ledger
                    .charge(
                        crate::budget::bytes_of(copy.texels.len() as u64, 16),
                        format!("a clamped copy of {}", copy.source.display()),
                    )
                    .map_err(|e| file.err(e.to_string()))?;
                textures.list.push(std::sync::Arc::new(copy));
                textures.list.len() - 1
            } else {
                texture
            };
            let texels = &mut std::sync::Arc::make_mut(&mut textures.list[texture]).texels;
            let mut clamped = 0;
            for t in texels.iter_mut().filter(|t| negative(t)) {
                *t = t.truncate().max(Vec3::ZERO).extend(t.w);
                clamped += 1;
            }
            Ok((Environment::Map { texture, scale }, clamped))
        }
        None => Err(t
            .err("the environment needs `radiance` or `file`")
            .hint("leave out [environment] for a black background")),
    }
}
