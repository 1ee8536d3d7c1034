//! Reduced copies of a texture for the filters that read them: the MIP pyramid (Williams
//! 1983, "Pyramidal Parametrics", SIGGRAPH: each level the 2×2 box reduction of the one
//! before) and the RIP map (levels reduced in u and in v separately, every combination).
//!
//! Level l is max(1, ⌊W/2ˡ⌋) × max(1, ⌊H/2ˡ⌋); a texel of level l is the mean of the (up to)
//! 2×2 texels of level l − 1 it covers; an odd row or column count drops the last one, as a
//! plain box pyramid does (power-of-two textures, those of the studies, are reduced exactly).
//! Each level keeps the texture's wrap modes.
//!
//! A colour texture reduced in `MipSpace::Srgb` averages the sRGB encodings (IEC 61966-2-1)
//! of R, G, B and decodes the mean (alpha stays linear): the mistake of mipmapping 8-bit
//! sRGB data as if it were linear, which darkens fine high-contrast detail (a black-and-white
//! checker averages to sRGB 0.5, linear 0.214, not 0.5).

use glam::Vec4;
use scenes::srgb::{linear_to_srgb, srgb_to_linear};
use scenes::texture::Texture;

use super::MipSpace;

/// The size of level `l` of a `width` × `height` texture.
pub fn level_size(width: u32, height: u32, l: u32) -> (u32, u32) {
    ((width >> l).max(1), (height >> l).max(1))
}

/// How many levels a full pyramid of a `width` × `height` texture has (down to 1 × 1).
pub fn level_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// `t` reduced by 2 along u (`du`) and/or v (`dv`), averaged in `space` (sRGB only for a
/// colour texture).
fn reduce(t: &Texture, du: bool, dv: bool, space: MipSpace, colour: bool) -> Texture {
    let (w, h) = (t.width, t.height);
    let (nw, nh) = (
        if du { (w / 2).max(1) } else { w },
        if dv { (h / 2).max(1) } else { h },
    );
    let encode = space == MipSpace::Srgb && colour;
    let to_avg = |v: Vec4| {
        if encode {
            Vec4::new(linear_to_srgb(v.x), linear_to_srgb(v.y), linear_to_srgb(v.z), v.w)
        } else {
            v
        }
    };
    let from_avg = |v: Vec4| {
        if encode {
            Vec4::new(srgb_to_linear(v.x), srgb_to_linear(v.y), srgb_to_linear(v.z), v.w)
        } else {
            v
        }
    };
    let mut texels = Vec::with_capacity(nw as usize * nh as usize);
    for j in 0..nh {
        for i in 0..nw {
            let xs: &[u32] = if du && w > 1 {
                &[2 * i, 2 * i + 1]
            } else {
                &[i.min(w - 1)]
            };
            let ys: &[u32] = if dv && h > 1 {
                &[2 * j, 2 * j + 1]
            } else {
                &[j.min(h - 1)]
            };
            let mut sum = Vec4::ZERO;
            for &y in ys {
                for &x in xs {
                    sum += to_avg(t.texels[(y * w + x) as usize]);
                }
            }
            texels.push(from_avg(sum / (xs.len() * ys.len()) as f32));
        }
    }
    Texture {
        source: t.source.clone(),
        width: nw,
        height: nh,
        texels,
        wrap: t.wrap,
    }
}

/// Levels 1, 2, … of the MIP pyramid of `t` (level 0 is `t`), down to 1 × 1.
pub fn mip_levels(t: &Texture, space: MipSpace, colour: bool) -> Vec<Texture> {
    let mut levels: Vec<Texture> = Vec::new();
    for _ in 1..level_count(t.width, t.height) {
        let next = reduce(levels.last().unwrap_or(t), true, true, space, colour);
        levels.push(next);
    }
    levels
}

/// Every level (i, j) of the RIP map of `t`, reduced i times in u and j times in v, in
/// row-major order of (j, i): `level_count(W, 1)` × `level_count(1, H)` levels, (0, 0) being
/// `t` itself.
pub fn rip_levels(t: &Texture) -> Vec<Texture> {
    let (nu, nv) = (level_count(t.width, 1), level_count(1, t.height));
    let mut out: Vec<Texture> = Vec::with_capacity((nu * nv) as usize);
    for j in 0..nv {
        for i in 0..nu {
            let level = match (i, j) {
                (0, 0) => t.clone(),
                (0, _) => reduce(
                    &out[((j - 1) * nu) as usize],
                    false,
                    true,
                    MipSpace::Linear,
                    false,
                ),
                _ => reduce(
                    &out[(j * nu + i - 1) as usize],
                    true,
                    false,
                    MipSpace::Linear,
                    false,
                ),
            };
            out.push(level);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use scenes::texture::WrapMode;

    fn checker(n: u32) -> Texture {
        let texels = (0..n * n)
            .map(|k| {
                if (k % n + k / n).is_multiple_of(2) {
                    Vec4::ONE
                } else {
                    Vec4::ZERO
                }
            })
            .collect();
        Texture {
            source: Default::default(),
            width: n,
            height: n,
            texels,
            wrap: [WrapMode::Repeat; 2],
        }
    }

    #[test]
    fn a_checker_reduces_to_its_mean_in_linear_and_darker_in_srgb() {
        let t = checker(8);
        let linear = mip_levels(&t, MipSpace::Linear, true);
        assert_eq!(linear.len(), 3);
        assert_eq!((linear[2].width, linear[2].height), (1, 1));
        assert!((linear[0].texels[0].x - 0.5).abs() < 1e-6);
        let srgb = mip_levels(&t, MipSpace::Srgb, true);
        // sRGB 0.5 decodes to 0.214 (IEC 61966-2-1); alpha stays the linear mean.
        assert!(
            (srgb[0].texels[0].x - 0.2140).abs() < 1e-3,
            "{}",
            srgb[0].texels[0].x
        );
        assert!((srgb[0].texels[0].w - 0.5).abs() < 1e-6);
        // A texture that is not colour is never reduced in sRGB.
        assert_eq!(mip_levels(&t, MipSpace::Srgb, false), linear);
    }

    #[test]
    fn levels_of_a_non_square_texture_stop_at_one_texel() {
        let mut t = checker(8);
        t.width = 16;
        t.height = 4;
        t.texels = vec![Vec4::splat(2.0); 64];
        let m = mip_levels(&t, MipSpace::Linear, false);
        let sizes: Vec<(u32, u32)> = m.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(8, 2), (4, 1), (2, 1), (1, 1)]);
        assert!(m.iter().all(|l| l.texels.iter().all(|&v| v == Vec4::splat(2.0))));
        let r = rip_levels(&t);
        assert_eq!(r.len(), 5 * 3);
        assert_eq!((r[3 + 5].width, r[3 + 5].height), (2, 2));
        assert_eq!((r[4 + 2 * 5].width, r[4 + 2 * 5].height), (1, 1));
    }
}
