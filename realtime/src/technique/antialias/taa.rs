//! TAA's sequence of frames: where each samples inside the pixel, and where the camera is.
//!
//! Frame i of `frames` (the measured one is the last, i = frames − 1) is offset within every
//! pixel by the Halton (2, 3) point of index i + 1, less ½ (Halton 1964; index 0, the
//! pixel's corner in both bases, is skipped), so any run of frames spreads its samples evenly
//! over the pixel. Under motion the camera has orbited to the scene's view by
//! `orbit_degrees` a frame: frame i sees it (frames − 1 − i)·orbit_degrees before it, so the
//! measured frame is the scene's own view and its ground truth the study's.

use glam::Vec2;
use scenes::Camera;

use super::AntiAliasing;

/// The radical inverse of `i` in `base`: its digits mirrored about the point (Halton 1964,
/// "Algorithm 247: Radical-inverse quasi-random point sequence", CACM 7(12)).
pub fn radical_inverse(mut i: u32, base: u32) -> f32 {
    let inv = 1.0 / base as f64;
    let (mut value, mut scale) = (0.0f64, inv);
    while i > 0 {
        value += f64::from(i % base) * scale;
        i /= base;
        scale *= inv;
    }
    value as f32
}

/// Frame `i`'s sub-pixel offset in pixels, in [−½, ½)², or zero without jitter.
pub fn jitter(i: u32, on: bool) -> Vec2 {
    if !on {
        return Vec2::ZERO;
    }
    Vec2::new(radical_inverse(i + 1, 2), radical_inverse(i + 1, 3)) - 0.5
}

/// The camera of frame `i` of TAA `aa`, from the scene's `camera` (the last frame's).
pub fn camera(aa: &AntiAliasing, camera: &Camera, i: u32) -> Camera {
    match *aa {
        AntiAliasing::Taa {
            frames,
            orbit_degrees,
            orbit_distance,
            ..
        } => camera.orbited(-((frames - 1 - i) as f32) * orbit_degrees, orbit_distance),
        _ => *camera,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_points_fill_the_pixel() {
        assert_eq!(radical_inverse(1, 2), 0.5);
        assert_eq!(radical_inverse(3, 2), 0.75);
        assert!((radical_inverse(2, 3) - 2.0 / 3.0).abs() < 1e-7);
        // 16 frames: every quarter of the pixel in x and every third in y holds a share.
        let points: Vec<Vec2> = (0..16).map(|i| jitter(i, true) + 0.5).collect();
        for q in 0..4 {
            let n = points.iter().filter(|p| (p.x * 4.0) as usize == q).count();
            assert_eq!(n, 4, "quarter {q}");
        }
        assert!(points
            .iter()
            .all(|p| p.cmpge(Vec2::ZERO).all() && p.cmplt(Vec2::ONE).all()));
        assert_eq!(jitter(5, false), Vec2::ZERO);
    }
}
