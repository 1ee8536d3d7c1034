//! Image textures: RGBA f32 in linear space, bilinear filtering, wrap modes.
//!
//! Texel (i, j) has its centre at uv = ((i + 0.5)/W, (j + 0.5)/H); v = 0 is the top row
//! (glTF's convention, and row 0 = +Y for equirectangular maps). Colour textures
//! (base colour, emission) are sRGB-decoded on load with the exact IEC 61966-2-1 curve;
//! data textures (normal, roughness/metallic) and float images (EXR, HDR) stay linear.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec4};

use crate::error::SceneError;
use crate::model::WrapMode;

/// How 8-bit texels are decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorSpace {
    /// sRGB-encoded colour (decoded to linear on load).
    Srgb,
    /// Linear data.
    Linear,
}

/// A loaded texture.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Where it came from (for messages); empty for generated textures.
    pub source: PathBuf,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major RGBA texels, linear, row 0 at the top.
    pub texels: Vec<Vec4>,
    /// Wrap mode in u and v.
    pub wrap: [WrapMode; 2],
}

/// Exact sRGB → linear decode (IEC 61966-2-1).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Exact linear → sRGB encode (IEC 61966-2-1), for previews.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

impl Texture {
    /// A texture from linear RGBA texels (row 0 at the top).
    pub fn from_texels(width: u32, height: u32, texels: Vec<Vec4>, wrap: [WrapMode; 2]) -> Self {
        assert_eq!(
            texels.len(),
            (width * height) as usize,
            "texel count must be width × height"
        );
        Texture {
            source: PathBuf::new(),
            width,
            height,
            texels,
            wrap,
        }
    }

    /// Texel (i, j) after applying the wrap mode to out-of-range indices.
    #[inline]
    pub fn texel(&self, i: i64, j: i64) -> Vec4 {
        let x = wrap_index(i, self.width as i64, self.wrap[0]);
        let y = wrap_index(j, self.height as i64, self.wrap[1]);
        self.texels[(y * self.width as i64 + x) as usize]
    }

    /// Bilinear lookup at `uv`, texel centres at ((i + ½)/W, (j + ½)/H).
    pub fn sample(&self, uv: Vec2) -> Vec4 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return Vec4::ZERO;
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let top = self.texel(i, j) * (1.0 - fx) + self.texel(i + 1, j) * fx;
        let bottom = self.texel(i, j + 1) * (1.0 - fx) + self.texel(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

fn wrap_index(i: i64, n: i64, mode: WrapMode) -> i64 {
    match mode {
        WrapMode::Repeat => i.rem_euclid(n),
        WrapMode::Clamp => i.clamp(0, n - 1),
        WrapMode::Mirror => {
            let period = i.rem_euclid(2 * n);
            if period < n {
                period
            } else {
                2 * n - 1 - period
            }
        }
    }
}

/// Loads an image file as a texture: PNG/JPEG (8/16-bit, decoded per `color_space`), EXR and
/// Radiance HDR (always linear). Errors name the file.
pub fn load_texture(
    path: &Path,
    color_space: ColorSpace,
    wrap: [WrapMode; 2],
) -> Result<Texture, SceneError> {
    let _ = (path, color_space, wrap);
    Err(SceneError::new(path, "texture loading is not written yet"))
}
