//! Masks: which pixels a metric is computed over.
//!
//! | mask | selects |
//! |---|---|
//! | [`Mask::all`] | every pixel |
//! | [`Mask::rectangle`] | pixels with x0 ≤ x < x1, y0 ≤ y < y1 (raster coordinates, row 0 at the top) |
//! | [`Mask::object_ids`] | pixels whose reference `object_id.Y` (shape index + 1, 0 = background) is listed |
//! | [`Mask::objects`] | the same by shape name or pattern (`floor`, `sphere_*`), through the reference's object-name table |
//! | [`Mask::from_image`] | pixels of a custom mask image whose first channel is > 0.5 |
//! | [`Mask::interior`] | pixels of a surface away from its edges: no background, no object-id, depth or normal discontinuity |
//!
//! Masks combine by intersection ([`Mask::and`]).

use glam::Vec3;
use scenes::layered::LayeredImage;

/// Largest second difference of the unit normal across an interior pixel ([`Mask::interior`]):
/// 0.25 is a turn of about 14° concentrated in one pixel (|n₁ + n₂ − 2n| for a crease of angle
/// θ between two flat faces is 2 sin(θ/2) at its pixel); a sphere of radius r pixels turns by
/// about 1/r² per pixel², far below it once r > 2.
pub const NORMAL_KINK: f32 = 0.25;

/// The names of an object-name table for an error message (the first 20, then a count).
fn list_names(names: &[String]) -> String {
    const SHOWN: usize = 20;
    let mut text = names
        .iter()
        .take(SHOWN)
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > SHOWN {
        text += &format!(" … and {} more", names.len() - SHOWN);
    }
    if names.is_empty() {
        text = "none".into();
    }
    text
}

/// A set of pixels of a width × height image, with a name for reports.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask {
    /// Shown in reports and error messages (`all`, `floor`, …).
    pub name: String,
    /// Width in pixels.
    pub width: usize,
    /// One flag per pixel, row-major.
    pub pixels: Vec<bool>,
}

impl Mask {
    /// Every pixel.
    pub fn all(width: usize, height: usize) -> Mask {
        Mask {
            name: "all".into(),
            width,
            pixels: vec![true; width * height],
        }
    }

    /// The pixels `x0 ≤ x < x1`, `y0 ≤ y < y1` (clipped to the image).
    pub fn rectangle(name: &str, width: usize, height: usize, [x0, y0, x1, y1]: [usize; 4]) -> Mask {
        let pixels = (0..width * height)
            .map(|i| (x0..x1).contains(&(i % width)) && (y0..y1).contains(&(i / width)))
            .collect();
        Mask {
            name: name.into(),
            width,
            pixels,
        }
    }

    /// The pixels where the reference's `object_id.Y` is one of `ids` (shape index + 1).
    pub fn object_ids(name: &str, reference: &LayeredImage, ids: &[u32]) -> Result<Mask, String> {
        let id = reference
            .channel("object_id.Y")
            .ok_or_else(|| format!("mask `{name}`: the reference has no object_id.Y channel"))?;
        Ok(Mask {
            name: name.into(),
            width: reference.width as usize,
            pixels: id.iter().map(|&v| ids.iter().any(|&k| k as f32 == v)).collect(),
        })
    }

    /// The pixels of a mask image (EXR) whose first channel is above 0.5.
    pub fn from_image(name: &str, image: &LayeredImage) -> Result<Mask, String> {
        let (_, data) = image
            .channels
            .first()
            .ok_or_else(|| format!("mask `{name}`: the mask image has no channels"))?;
        Ok(Mask {
            name: name.into(),
            width: image.width as usize,
            pixels: data.iter().map(|&v| v > 0.5).collect(),
        })
    }

    /// The pixels of the shapes named by `patterns` in the reference: each pattern is a whole
    /// number (an object id, as [`Mask::object_ids`]) or a shape name with optional `*` and
    /// `?` wildcards ([`scenes::glob`]) looked up in the reference's object-name table
    /// ([`scenes::layered::OBJECT_NAMES_ATTRIBUTE`]). A name or pattern that matches no shape
    /// is an error listing the names there are.
    pub fn objects(name: &str, reference: &LayeredImage, patterns: &[&str]) -> Result<Mask, String> {
        let names = || -> Result<Vec<String>, String> {
            reference.object_names()?.ok_or_else(|| {
                format!(
                    "mask `{name}`: the reference has no object-name table (header attribute `{}`), so objects can only be given by id",
                    scenes::layered::OBJECT_NAMES_ATTRIBUTE
                )
            })
        };
        let mut ids = Vec::new();
        for pattern in patterns {
            if let Ok(id) = pattern.parse::<u32>() {
                ids.push(id);
                continue;
            }
            let names = names()?;
            let before = ids.len();
            ids.extend(
                (1..)
                    .zip(&names)
                    .filter(|(_, n)| scenes::glob::matches(pattern, n))
                    .map(|(id, _)| id),
            );
            if ids.len() == before {
                return Err(format!(
                    "mask `{name}`: `{pattern}` matches no object; objects: {}",
                    list_names(&names)
                ));
            }
        }
        Mask::object_ids(name, reference, &ids)
    }

    /// Pixels of a surface away from its edges in `reference` (the pixels whose metrics do not
    /// depend on how a renderer anti-aliases geometry):
    ///
    /// - not the background (object id 0), and the whole 3×3 neighbourhood has the pixel's id;
    /// - no depth kink: the second difference of `depth.Z` across the pixel, horizontally and
    ///   vertically, is within 1 % of its depth (a crease or a step in depth);
    /// - no normal kink: the second difference of `normal.X/Y/Z` across the pixel is below
    ///   [`NORMAL_KINK`] in length (a crease the depth hardly shows, e.g. a cube's edge seen
    ///   head-on; a smooth curve's normals turn evenly and pass);
    /// - not on the image border.
    ///
    /// Without `object_id.Y` and `depth.Z` channels it selects every pixel; without `normal.*`
    /// the normal test is skipped.
    pub fn interior(reference: &LayeredImage) -> Mask {
        let (w, h) = (reference.width as usize, reference.height as usize);
        let mut mask = Mask::all(w, h);
        mask.name = "interior".into();
        let (Some(id), Some(depth)) = (reference.channel("object_id.Y"), reference.channel("depth.Z")) else {
            return mask;
        };
        let normal = reference.xyz("normal");
        for (i, keep) in mask.pixels.iter_mut().enumerate() {
            let (x, y) = (i % w, i / w);
            if x == 0 || y == 0 || x + 1 == w || y + 1 == h || id[i] == 0.0 {
                *keep = false;
                continue;
            }
            let same_id = (-1isize..=1)
                .flat_map(|dy| (-1isize..=1).map(move |dx| (dx, dy)))
                .all(|(dx, dy)| id[(y as isize + dy) as usize * w + (x as isize + dx) as usize] == id[i]);
            let d = depth[i];
            let kink = |a: f32, b: f32| (a + b - 2.0 * d).abs() > 0.01 * d.abs().max(1e-6);
            let smooth =
                d.is_finite() && !kink(depth[i - 1], depth[i + 1]) && !kink(depth[i - w], depth[i + w]);
            let crease = normal.as_ref().is_some_and(|n| {
                let bent = |a: Vec3, b: Vec3| (a + b - 2.0 * n[i]).length() > NORMAL_KINK;
                bent(n[i - 1], n[i + 1]) || bent(n[i - w], n[i + w])
            });
            *keep = same_id && smooth && !crease;
        }
        mask
    }

    /// Pixels both masks select; the name joins both.
    pub fn and(&self, other: &Mask) -> Mask {
        Mask {
            name: format!("{}&{}", self.name, other.name),
            width: self.width,
            pixels: self
                .pixels
                .iter()
                .zip(&other.pixels)
                .map(|(a, b)| *a && *b)
                .collect(),
        }
    }

    /// Number of pixels of the image the mask covers.
    pub fn len(&self) -> usize {
        self.pixels.len()
    }

    /// True for a mask of an empty image.
    pub fn is_empty(&self) -> bool {
        self.pixels.is_empty()
    }

    /// Number of selected pixels.
    pub fn count(&self) -> usize {
        self.pixels.iter().filter(|&&p| p).count()
    }

    /// Whether pixel `i` is selected.
    pub fn selects(&self, i: usize) -> bool {
        self.pixels[i]
    }

    /// Mean of `values` (f32 maps or f64 terms) over the selected pixels, accumulated in f64;
    /// NaN if none is selected.
    pub fn mean<T: Copy + Into<f64>>(&self, values: &[T]) -> f64 {
        let (sum, n) = values
            .iter()
            .zip(&self.pixels)
            .filter(|(_, &p)| p)
            .fold((0.0f64, 0usize), |(s, n), (&v, _)| (s + v.into(), n + 1));
        sum / n as f64
    }

    /// `values` with every unselected pixel set to 0 (for error maps).
    pub fn zero_outside(&self, mut values: Vec<f32>) -> Vec<f32> {
        for (v, &p) in values.iter_mut().zip(&self.pixels) {
            if !p {
                *v = 0.0;
            }
        }
        values
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangle_and_object_masks_select_what_they_say() {
        let r = Mask::rectangle("r", 4, 3, [1, 1, 3, 2]);
        assert_eq!(r.count(), 2);
        assert!(r.selects(5) && r.selects(6) && !r.selects(4));
        let mut img = LayeredImage::new(2, 2);
        img.push_channel("object_id.Y", vec![0.0, 1.0, 2.0, 1.0]);
        let m = Mask::object_ids("one", &img, &[1]).unwrap();
        assert_eq!(m.pixels, vec![false, true, false, true]);
        assert_eq!(
            m.and(&Mask::rectangle("top right", 2, 2, [1, 0, 2, 1])).count(),
            1
        );
        assert!(Mask::object_ids("x", &LayeredImage::new(2, 2), &[1])
            .unwrap_err()
            .contains("object_id.Y"));
        assert_eq!(m.mean(&[9.0, 1.0, 9.0, 3.0]), 2.0);
        assert_eq!(m.zero_outside(vec![9.0, 1.0, 9.0, 3.0]), vec![0.0, 1.0, 0.0, 3.0]);
    }

    #[test]
    fn interior_drops_object_boundaries_and_depth_creases() {
        // 6×6: object 1 on the left three columns, object 2 on the right; flat depth except
        // a crease along row 3 of object 1.
        let (w, h) = (6usize, 6usize);
        let mut img = LayeredImage::new(w as u32, h as u32);
        let id: Vec<f32> = (0..w * h).map(|i| if i % w < 3 { 1.0 } else { 2.0 }).collect();
        let depth: Vec<f32> = (0..w * h)
            .map(|i| if i % w < 3 && i / w == 3 { 1.5 } else { 1.0 })
            .collect();
        img.push_channel("object_id.Y", id);
        img.push_channel("depth.Z", depth);
        let m = Mask::interior(&img);
        // Column 1 rows 1, 2 touch the crease on row 3 only for row 2 (its neighbour) … row 1 is
        // clean; columns 2 and 3 touch the id boundary; column 4 is interior on rows 1..=4.
        assert!(m.selects(w + 1), "row 1, col 1 is interior");
        assert!(!m.selects(2 * w + 1), "row 2 sees the crease on row 3");
        assert!(!m.selects(3 * w + 1), "the crease itself");
        assert!(!m.selects(w + 2) && !m.selects(w + 3), "next to the id boundary");
        assert!((1..5).all(|y| m.selects(y * w + 4)), "right object's interior");
        assert!(
            !m.selects(0) && !m.selects(w * h - 1),
            "the border is never interior"
        );
    }

    #[test]
    fn interior_drops_the_background_and_normal_creases() {
        // 8×6: background on the left two columns, one object elsewhere at constant depth,
        // whose normal turns by 90° between columns 4 and 5 (a cube's edge seen head-on).
        let (w, h) = (8usize, 6usize);
        let mut img = LayeredImage::new(w as u32, h as u32);
        img.push_channel(
            "object_id.Y",
            (0..w * h).map(|i| if i % w < 2 { 0.0 } else { 1.0 }).collect(),
        );
        img.push_channel("depth.Z", vec![1.0; w * h]);
        let normals: Vec<Vec3> = (0..w * h)
            .map(|i| if i % w < 5 { Vec3::Z } else { Vec3::X })
            .collect();
        img.push_xyz("normal", &normals);
        let m = Mask::interior(&img);
        assert!(
            (1..5).all(|y| !m.selects(y * w + 1)),
            "background is never interior"
        );
        assert!((1..5).all(|y| m.selects(y * w + 3)), "flat, one id, one normal");
        assert!(
            (1..5).all(|y| !m.selects(y * w + 4) && !m.selects(y * w + 5)),
            "the crease"
        );
        assert!((1..5).all(|y| m.selects(y * w + 6)), "past the crease");
        // A smooth turn (a cylinder of radius 20 pixels) is not a crease.
        let curved: Vec<Vec3> = (0..w * h)
            .map(|i| {
                let a = (i % w) as f32 / 20.0;
                Vec3::new(a.sin(), 0.0, a.cos())
            })
            .collect();
        img.push_xyz("normal", &curved);
        let m = Mask::interior(&img);
        assert!((1..5).all(|y| (3..7).all(|x| m.selects(y * w + x))));
    }

    #[test]
    fn object_masks_take_names_patterns_and_ids() {
        let mut img = LayeredImage::new(4, 1);
        img.push_channel("object_id.Y", vec![0.0, 1.0, 2.0, 3.0]);
        let none = Mask::objects("m", &img, &["floor"]).unwrap_err();
        assert!(none.contains("no object-name table"), "{none}");
        assert_eq!(
            Mask::objects("m", &img, &["2"]).unwrap().pixels,
            [false, false, true, false]
        );
        img.set_object_names(["floor", "sphere_m", "sphere_d"]);
        assert_eq!(
            Mask::objects("m", &img, &["floor"]).unwrap().pixels,
            [false, true, false, false]
        );
        assert_eq!(
            Mask::objects("m", &img, &["sphere_*"]).unwrap().pixels,
            [false, false, true, true]
        );
        assert_eq!(
            Mask::objects("m", &img, &["floor", "?phere_d"]).unwrap().pixels,
            [false, true, false, true]
        );
        let e = Mask::objects("m", &img, &["ball*"]).unwrap_err();
        assert!(
            e.contains("`ball*` matches no object") && e.contains("floor, sphere_m, sphere_d"),
            "{e}"
        );
    }
}
