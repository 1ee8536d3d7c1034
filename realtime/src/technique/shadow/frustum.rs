//! A shadow map layer's projection as built on the CPU ([`LightFrustum`]), and the
//! orthographic fit of directional lights and cascades (the shadow module's "Cascades";
//! [`super::maps`] fits the perspective frusta of local lights).

use glam::{Mat4, Vec3};
use scenes::Scene;

/// Far plane as a multiple of the farthest bounding-box depth, chosen here.
pub const FAR_MARGIN: f32 = 1.01;
/// One map layer's frustum (a light's, or one cascade of it), as built on the CPU.
#[derive(Clone, Debug, PartialEq)]
pub struct LightFrustum {
    /// The light's name, with `cascade i/k` for cascades (the pass label).
    pub name: String,
    /// World to clip.
    pub view_proj: Mat4,
    /// Eye, or a point on the axis (orthographic).
    pub eye: Vec3,
    /// Unit view direction.
    pub axis: Vec3,
    /// Perspective (true) or orthographic.
    pub perspective: bool,
    /// Full field of view (perspective, degrees) or side of the square extent (orthographic, m).
    pub extent: f32,
    /// Near and far view depth.
    pub near: f32,
    /// Far view depth.
    pub far: f32,
    /// Nearest blocker depth PCSS's search assumes (module docs).
    pub search_near: f32,
    /// PCSS light-size term (w_light, or 2·tan(θ/2) for directional lights).
    pub size: f32,
    /// The emitter's own shape.
    pub own_shape: Option<usize>,
    /// A cascade's camera view-depth slice [z_i, z_{i+1}]; None for a map over the scene.
    pub slice: Option<(f32, f32)>,
    /// One of a cube map's six faces (maps.rs `cube`).
    pub cube_face: bool,
}

impl LightFrustum {
    /// World size of one texel at view depth z of a `side`² map: (a, b) with τ = a·z + b.
    pub fn texel(&self, side: u32) -> (f32, f32) {
        if self.perspective {
            (2.0 * (0.5 * self.extent.to_radians()).tan() / side as f32, 0.0)
        } else {
            (0.0, self.extent / side as f32)
        }
    }

    /// `name: perspective 123.4°, depth 0.9–1.5 m, w_light 0.5 m`; cascades add their slice.
    pub fn describe(&self) -> String {
        let slice = self.slice.map_or(String::new(), |(z0, z1)| {
            format!(", camera depth {z0:.4}–{z1:.4} m")
        });
        if self.perspective {
            format!(
                "{}: perspective {:.1}°, depth {:.4}–{:.4} m (search from {:.4}), w_light {} m{slice}",
                self.name, self.extent, self.near, self.far, self.search_near, self.size
            )
        } else {
            format!(
                "{}: orthographic {:.4} m square, depth {:.4}–{:.4} m (search from {:.4}), penumbra {} m/m{slice}",
                self.name, self.extent, self.near, self.far, self.search_near, self.size
            )
        }
    }
}

/// The eight corners of an axis-aligned box.
pub fn corners((lo, hi): (Vec3, Vec3)) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The light-space (`view`) bounding box of `points`.
fn light_box(view: &Mat4, points: &[Vec3]) -> (Vec3, Vec3) {
    points
        .iter()
        .map(|c| view.transform_point3(*c))
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        })
}

/// An orthographic frustum along the travel direction `axis`, its depth range over the whole
/// scene; its square over the scene's bounding box, or with `cascade` = (the eight corners of
/// a camera-frustum slice, the map side) over that slice (module docs, "Cascades").
pub fn orthographic(
    scene: &Scene,
    name: &str,
    axis: Vec3,
    size: f32,
    cascade: Option<(&[Vec3; 8], u32)>,
) -> LightFrustum {
    let (centre, radius) = scene.bounding_sphere();
    let eye = centre - axis * (2.0 * radius);
    let view = Mat4::look_to_rh(eye, axis, axis.any_orthonormal_vector());
    let (lo, hi) = light_box(&view, &corners(scene.bounds()));
    let (cx, cy, half) = match cascade {
        None => (
            0.5 * (lo.x + hi.x),
            0.5 * (lo.y + hi.y),
            0.5 * (hi.x - lo.x).max(hi.y - lo.y) * FAR_MARGIN,
        ),
        Some((slice, side)) => {
            let (slo, shi) = light_box(&view, slice);
            cascade_square((lo, hi), (slo, shi), side, radius)
        }
    };
    let margin = 0.01 * radius;
    let (near, far) = (-hi.z - margin, -lo.z + margin);
    let proj = Mat4::orthographic_rh(cx - half, cx + half, cy - half, cy + half, near, far);
    LightFrustum {
        name: name.to_string(),
        view_proj: proj * view,
        eye,
        axis,
        perspective: false,
        extent: 2.0 * half,
        near,
        far,
        search_near: near,
        size,
        own_shape: None,
        slice: None,
        cube_face: false,
    }
}

/// A cascade's light-space square (centre x, centre y, half side): the slice's light-space box
/// clipped to the scene's (the slice's own box if they miss each other: nothing there to
/// shadow), its larger side × [`FAR_MARGIN`], snapped to texels of size t = 2·half/(side − 2)
/// (Valient 2008, the shadow module's "Cascades"); at least 10⁻⁴ × the scene radius across.
fn cascade_square(scene: (Vec3, Vec3), slice: (Vec3, Vec3), side: u32, radius: f32) -> (f32, f32, f32) {
    let (mut lo, mut hi) = (slice.0.max(scene.0), slice.1.min(scene.1));
    if lo.x > hi.x || lo.y > hi.y {
        (lo, hi) = slice;
    }
    let half = (0.5 * (hi.x - lo.x).max(hi.y - lo.y) * FAR_MARGIN).max(1e-4 * radius);
    let texel = 2.0 * half / side.saturating_sub(2).max(1) as f32;
    let snap = |c: f32| (c / texel).round() * texel;
    (
        snap(0.5 * (lo.x + hi.x)),
        snap(0.5 * (lo.y + hi.y)),
        0.5 * texel * side as f32,
    )
}
