//! Cascaded shadow maps for directional lights (Zhang et al. 2006, "Parallel-Split Shadow Maps
//! for Large-scale Virtual Environments", VRCIA 2006; Dimitrov 2007, "Cascaded Shadow Maps",
//! NVIDIA whitepaper): the camera view-depth range, its parallel splits, the camera-frustum
//! slices and each cascade's light-space square. The formulas and the fit are stated in the
//! shadow module's "Cascades".

use glam::Vec3;
use scenes::{Camera, Scene};

use super::frustum::{corners, orthographic, LightFrustum};
use super::Shadow;
use crate::camera::camera_near;

/// The camera view-depth range [n, f] the cascades split: n the camera's near plane, f the
/// farthest corner of the scene's bounding box along the view direction, at least n.
pub fn cascade_range(scene: &Scene) -> (f32, f32) {
    let near = camera_near(scene);
    let (eye, forward) = (scene.camera.position(), scene.camera.forward());
    let far = corners(scene.bounds())
        .iter()
        .map(|c| (*c - eye).dot(forward))
        .fold(near, f32::max);
    (near, far)
}

/// The split depths z_0 = n < … < z_k = f of `k` cascades over the view depths [n, f], by the
/// practical split scheme of Zhang et al. 2006 (the shadow module's "Cascades"): the mix, by λ,
/// of the logarithmic split n·(f/n)^(i/k) and the uniform split n + (f − n)·i/k. The endpoints
/// are n and f exactly.
pub fn pssm_splits(near: f32, far: f32, k: u32, lambda: f32) -> Vec<f32> {
    let k = k.max(1);
    (0..=k)
        .map(|i| match i {
            0 => near,
            _ if i == k => far,
            _ => {
                let t = i as f32 / k as f32;
                let log = near * (far / near).powf(t);
                let uniform = near + (far - near) * t;
                lambda * log + (1.0 - lambda) * uniform
            }
        })
        .collect()
}

/// The eight world-space corners of the camera's view frustum between view depths z0 and z1
/// (along its view direction), for a film of aspect `aspect` = width / height: at depth z the
/// frustum is z·tan(fov_y/2) high and aspect times as wide on each side of the axis (the
/// projection of `Camera::ray_direction`).
pub fn frustum_slice(camera: &Camera, aspect: f32, z0: f32, z1: f32) -> [Vec3; 8] {
    let tan_half = (0.5 * camera.fov_y_deg.to_radians()).tan();
    let m = camera.to_world.matrix3;
    let (right, up) = (Vec3::from(m.x_axis), Vec3::from(m.y_axis));
    let (eye, forward) = (camera.position(), camera.forward());
    std::array::from_fn(|k| {
        let z = if k & 4 == 0 { z0 } else { z1 };
        let sx = if k & 1 == 0 { -1.0 } else { 1.0 };
        let sy = if k & 2 == 0 { -1.0 } else { 1.0 };
        eye + forward * z + right * (sx * z * tan_half * aspect) + up * (sy * z * tan_half)
    })
}

/// The `shadow.cascades` orthographic frusta of a directional light travelling along `axis`
/// (the shadow module's "Cascades").
pub(super) fn cascades(
    scene: &Scene,
    name: &str,
    axis: Vec3,
    size: f32,
    shadow: &Shadow,
    aspect: f32,
) -> Vec<LightFrustum> {
    let (near, far) = cascade_range(scene);
    let k = shadow.cascades;
    let z = pssm_splits(near, far, k, shadow.split_lambda);
    (0..k as usize)
        .map(|i| {
            let slice = frustum_slice(&scene.camera, aspect, z[i], z[i + 1]);
            let label = format!("{name} cascade {}/{k}", i + 1);
            let mut f = orthographic(scene, &label, axis, size, Some((&slice, shadow.map)));
            f.slice = Some((z[i], z[i + 1]));
            f
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::maps::tests::{cascaded, hard, rect, scene, single_layers, sun};
    use super::*;
    use crate::technique::shadow::maps::light_frusta;
    use glam::Vec3;
    use scenes::{Geometry, Light};

    /// Zhang et al. 2006's splits: λ = 0 uniform, λ = 1 logarithmic (constant ratio), every λ
    /// increasing from n to f exactly, and between the two.
    #[test]
    fn pssm_splits_mix_uniform_and_logarithmic() {
        let (n, f) = (0.01f32, 100.0f32);
        let uniform = pssm_splits(n, f, 4, 0.0);
        for (i, z) in uniform.iter().enumerate() {
            let want = n + (f - n) * i as f32 / 4.0;
            assert!(
                (z - want).abs() <= 1e-5 * want,
                "uniform z_{i} = {z}, want {want}"
            );
        }
        let log = pssm_splits(n, f, 4, 1.0);
        for (i, z) in log.iter().enumerate() {
            let want = n * 10f32.powi(i as i32);
            assert!(
                (z - want).abs() <= 1e-5 * want,
                "logarithmic z_{i} = {z}, want {want}"
            );
        }
        for lambda in [0.0, 0.25, 0.5, 0.9, 1.0] {
            for k in 1..=4 {
                let z = pssm_splits(n, f, k, lambda);
                assert_eq!(z.len(), k as usize + 1);
                assert_eq!((z[0], z[k as usize]), (n, f), "λ {lambda}, k {k}: {z:?}");
                assert!(z.windows(2).all(|w| w[0] < w[1]), "λ {lambda}, k {k}: {z:?}");
            }
            let z = pssm_splits(n, f, 4, lambda);
            for i in 0..=4 {
                assert!(
                    log[i] * (1.0 - 1e-6) <= z[i] && z[i] <= uniform[i] * (1.0 + 1e-6),
                    "λ {lambda}: z_{i} = {} outside [{}, {}]",
                    z[i],
                    log[i],
                    uniform[i]
                );
            }
        }
    }

    /// NDC of world point p in frustum f (x, y in [−1, 1], z in [0, 1] inside).
    fn ndc(f: &LightFrustum, p: Vec3) -> Vec3 {
        let c = f.view_proj * p.extend(1.0);
        c.truncate() / c.w
    }

    /// A camera at the centre of a 200 m sphere (bounds ±100 m) looking along +x: every
    /// cascade's orthographic frustum holds its slice's eight corners (the slices lie inside
    /// the scene's box, so the clip to it changes nothing), the splits are the PSSM ones over
    /// [camera near, 100 m], and the first cascade's texels are the finest.
    #[test]
    fn each_cascade_holds_its_slice() {
        let mut s = scene(
            vec![(
                Geometry::Sphere {
                    center: Vec3::ZERO,
                    radius: 100.0,
                },
                false,
            )],
            vec![sun(Vec3::new(-0.3, -1.0, 0.2))],
        );
        s.camera = Camera::look_at(Vec3::ZERO, Vec3::X, Vec3::Y, 40.0);
        let aspect = 1.5;
        let (n, f) = cascade_range(&s);
        assert!(
            (n - camera_near(&s)).abs() < 1e-9 && (f - 100.0).abs() < 1e-3,
            "{n} {f}"
        );
        for lambda in [0.0, 0.5, 1.0] {
            let layers = light_frusta(&s, &cascaded(4, lambda), aspect).remove(0);
            assert_eq!(layers.len(), 4);
            let z = pssm_splits(n, f, 4, lambda);
            for (i, c) in layers.iter().enumerate() {
                assert_eq!(c.slice, Some((z[i], z[i + 1])), "{}", c.describe());
                assert!(!c.perspective && c.name == format!("sun cascade {}/4", i + 1));
                for p in frustum_slice(&s.camera, aspect, z[i], z[i + 1]) {
                    let q = ndc(c, p);
                    assert!(
                        q.x.abs() <= 1.0 && q.y.abs() <= 1.0 && (0.0..=1.0).contains(&q.z),
                        "λ {lambda}, {}: corner {p} at {q}",
                        c.describe()
                    );
                }
                // Snapped: the square is a whole number of texels of size 2·half/(side − 2).
                let (_, texel) = c.texel(512);
                assert!((texel * 512.0 - c.extent).abs() <= 1e-4 * c.extent);
            }
            assert!(layers[0].extent < layers[3].extent, "λ {lambda}");
        }
        // The slice's corners: at depth z, z·tan 20° above and below the axis, 1.5× that across.
        let c = frustum_slice(&s.camera, aspect, 1.0, 2.0);
        let t = 20f32.to_radians().tan();
        assert!(c[0].abs_diff_eq(Vec3::new(1.0, -t, -1.5 * t), 1e-6), "{}", c[0]);
        assert!(
            c[7].abs_diff_eq(Vec3::new(2.0, 2.0 * t, 3.0 * t), 1e-6),
            "{}",
            c[7]
        );
    }

    /// A low camera over a long floor with a post: every floor point the camera sees lies in
    /// the frustum of the cascade its view depth selects (the slice clipped to the scene's box
    /// keeps every receiver), the clipped squares are smaller than the one map over the scene,
    /// and `cascades = 1` is that one map exactly. Other lights keep one layer.
    #[test]
    fn cascades_cover_every_visible_receiver() {
        let mut s = scene(
            vec![
                (
                    Geometry::Rectangle {
                        center: Vec3::new(0.0, 0.0, -28.0),
                        half_u: Vec3::new(0.0, 0.0, 30.0),
                        half_v: Vec3::new(4.0, 0.0, 0.0),
                    },
                    false,
                ),
                (rect(Vec3::new(0.0, 0.5, -3.0), 0.1, false), false),
            ],
            vec![
                sun(Vec3::new(0.4, -0.5, -0.6)),
                Light::Point {
                    name: "point".into(),
                    position: Vec3::new(0.0, 3.0, 0.0),
                    intensity: Vec3::ONE,
                },
            ],
        );
        s.camera = Camera::look_at(
            Vec3::new(0.0, 1.2, 1.5),
            Vec3::new(0.0, 0.3, -10.0),
            Vec3::Y,
            45.0,
        );
        let one = single_layers(&s, &hard());
        let axis = Vec3::new(0.4, -0.5, -0.6).normalize();
        assert_eq!(one[0], orthographic(&s, "sun", axis, one[0].size, None));
        let all = light_frusta(&s, &cascaded(4, 0.5), 1.0);
        assert_eq!((all[0].len(), all[1].len()), (4, 1));
        let layers = &all[0];
        let (eye, forward) = (s.camera.position(), s.camera.forward());
        let mut seen = [0usize; 4];
        for j in 0..=240 {
            for i in 0..=16 {
                let p = Vec3::new(-4.0 + 0.5 * i as f32, 0.0, 2.0 - 0.25 * j as f32);
                let dir = (p - eye).normalize();
                let local = s.camera.to_world.matrix3.inverse() * dir;
                let t = 22.5f32.to_radians().tan();
                if local.z >= 0.0 || (local.x / -local.z).abs() > t || (local.y / -local.z).abs() > t {
                    continue;
                }
                let d = (p - eye).dot(forward);
                let c = layers.iter().position(|c| d <= c.slice.unwrap().1).unwrap_or(3);
                seen[c] += 1;
                let q = ndc(&layers[c], p);
                assert!(
                    q.x.abs() <= 1.0 && q.y.abs() <= 1.0 && (0.0..=1.0).contains(&q.z),
                    "{p} (view depth {d}) outside {}: {q}",
                    layers[c].describe()
                );
            }
        }
        assert!(
            seen.iter().all(|&n| n > 0),
            "every cascade has receivers: {seen:?}"
        );
        assert!(layers.iter().all(|c| c.extent < one[0].extent), "{layers:?}");
    }
}
