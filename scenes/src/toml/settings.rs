//! `[camera]`, `[film]`, `[render]` and `[environment]`.

use glam::Vec3;

use super::inputs::{rgb_const, Bound, Textures};
use super::read::{Field, Table};
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

/// `[film]`: width, height (pixels, default 256 each).
pub(crate) fn film(t: Option<Table>) -> Result<Film, SceneError> {
    let Some(t) = t else {
        return Ok(Film {
            width: DEFAULT_SIDE,
            height: DEFAULT_SIDE,
        });
    };
    t.only(&["width", "height"], "the film")?;
    let side = |key: &str| -> Result<u32, SceneError> {
        match t.get(key) {
            Some(f) => {
                let v = f.i64()?;
                if (1..=MAX_SIDE).contains(&v) {
                    Ok(v as u32)
                } else {
                    Err(f
                        .err(format!("must be in 1..={MAX_SIDE} pixels, got {v}"))
                        .hint("render large images in tiles or lower the resolution"))
                }
            }
            None => Ok(DEFAULT_SIDE),
        }
    };
    let (width, height) = (side("width")?, side("height")?);
    if u64::from(width) * u64::from(height) > MAX_PIXELS {
        return Err(t.err(format!("{width}×{height} pixels is more than 2^28")));
    }
    Ok(Film { width, height })
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

/// `[environment]`: `radiance = [r, g, b]`, or `file = "…"` with `scale` (default 1).
pub(crate) fn environment(t: &Table, textures: &mut Textures) -> Result<Environment, SceneError> {
    t.only(&["radiance", "file", "scale"], "the environment")?;
    match t.one_of(&["radiance", "file"])? {
        Some("radiance") => {
            if let Some(f) = t.get("scale") {
                return Err(f.err("`scale` applies to an environment `file`, not to `radiance`"));
            }
            let radiance = rgb_const(t.get("radiance"), Bound::NonNegative, Vec3::ZERO)?;
            Ok(Environment::Constant { radiance })
        }
        Some(_) => {
            let scale = match t.get("scale") {
                Some(f) => f.non_negative()?,
                None => 1.0,
            };
            let file = t.req("file")?;
            let texture = textures.load(&file, ColorSpace::Srgb, [WrapMode::Repeat, WrapMode::Clamp])?;
            let tex = &textures.list[texture];
            if let Some(i) = tex.texels.iter().position(|t| t.truncate().min_element() < 0.0) {
                let (x, y) = (i % tex.width as usize, i / tex.width as usize);
                return Err(file
                    .err(format!(
                        "the environment map has negative radiance (first at texel ({x}, {y}))"
                    ))
                    .hint("clamp the image to >= 0; lossy EXR compression can leave negative ringing"));
            }
            Ok(Environment::Map { texture, scale })
        }
        None => Err(t
            .err("the environment needs `radiance` or `file`")
            .hint("leave out [environment] for a black background")),
    }
}
