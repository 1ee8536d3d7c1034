//! The summed-area table of a texture (Crow 1984, "Summed-Area Tables for Texture Mapping",
//! SIGGRAPH): F(i, j) = Σ_{x<i, y<j} (t(x, y) − m) for 0 ≤ i ≤ W, 0 ≤ j ≤ H, so that the sum
//! over any texel rectangle is four reads. The texture's mean m is subtracted first (Hensley et
//! al. 2005, "Fast Summed-Area Table Generation and its Applications", Eurographics, §4: the
//! table then holds sums that stay near zero instead of growing to W·H·m, which f32 would
//! round to ~W·H·m·2⁻²⁴ absolute); sums are accumulated in f64 and stored as f32.

use glam::{DVec4, Vec4};
use scenes::texture::Texture;

/// The mean texel of `t` and its mean-subtracted table, (W + 1) × (H + 1), row-major, row 0
/// and column 0 zero.
pub fn summed_area_table(t: &Texture) -> (Vec4, Vec<Vec4>) {
    let (w, h) = (t.width as usize, t.height as usize);
    let mean = t.texels.iter().fold(DVec4::ZERO, |s, v| s + v.as_dvec4()) / (w * h).max(1) as f64;
    let mut table = vec![DVec4::ZERO; (w + 1) * (h + 1)];
    for y in 0..h {
        let mut row = DVec4::ZERO;
        for x in 0..w {
            row += t.texels[y * w + x].as_dvec4() - mean;
            table[(y + 1) * (w + 1) + x + 1] = table[y * (w + 1) + x + 1] + row;
        }
    }
    (mean.as_vec4(), table.into_iter().map(|v| v.as_vec4()).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use scenes::texture::WrapMode;

    #[test]
    fn rectangle_sums_are_four_reads() {
        let (w, h) = (5usize, 3usize);
        let texels: Vec<Vec4> = (0..w * h).map(|k| Vec4::splat(k as f32)).collect();
        let t = Texture {
            source: Default::default(),
            width: w as u32,
            height: h as u32,
            texels: texels.clone(),
            wrap: [WrapMode::Repeat; 2],
        };
        let (mean, f) = summed_area_table(&t);
        assert_eq!(mean, Vec4::splat(7.0));
        let at = |i: usize, j: usize| f[j * (w + 1) + i].x as f64;
        // Texels x in 1..4, y in 1..3: the sum of their values minus 6 times the mean.
        let direct: f64 = (1..3).flat_map(|y| (1..4).map(move |x| (y * w + x) as f64)).sum();
        let from_table = at(4, 3) - at(1, 3) - at(4, 1) + at(1, 1) + 6.0 * 7.0;
        assert!((direct - from_table).abs() < 1e-4, "{direct} {from_table}");
        assert_eq!(at(w, h), 0.0, "the whole texture sums to its mean");
    }
}
