//! Emissive triangle mesh (glTF emissive primitives, and boxes loaded as 12 triangles).
//!
//! Each triangle emits radiance L(uv) from its front side (counter-clockwise winding, geometric
//! normal n = normalize((p1 − p0) × (p2 − p0))) or from both sides when `two_sided`. uv is
//! interpolated from the vertex uvs with barycentrics (b0, b1, b2); a mesh without uvs uses
//! uv = (b1, b2) as Mitsuba 3's `mesh` does.
//!
//! Sampling: a triangle with probability A_i/A (a [`Distribution1D`] over the areas; the
//! remapped selection coordinate is reused), then a uniform point on it
//! ([`square_to_triangle`], Heitz 2019), so the point density is 1/A over the whole mesh and
//! the solid-angle pdf is r²/(A·|cosθl|) (pbrt-v4 §6.5.4 Triangle::Sample in the area measure, and
//! dω = |cosθl| dA/r², pbrt-v3 §5.5.3). Power Φ = π·A·mean(L), doubled when two-sided
//! (pbrt-v4 §12.4 DiffuseAreaLight::Phi).
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `mesh` | [`Mesh`], finite positions, indices in range, total area > 0 | — | m |
//! | `radiance` L | [`Radiance`], ≥ 0 | — | W·m⁻²·sr⁻¹ |
//! | `two_sided` | bool | false | — |

use std::sync::Arc;

use glam::{Vec2, Vec3};
use scenes::{Mesh, Rgb};

use super::distribution::Distribution1D;
use super::radiance::Radiance;
use super::LightSample;
use crate::sampling::{area_to_solid_angle_pdf, square_to_triangle};

/// Emissive triangle mesh.
#[derive(Clone, Debug)]
pub struct MeshLight {
    /// The mesh (shared with the scene).
    pub mesh: Arc<Mesh>,
    /// Emitted radiance.
    pub radiance: Radiance,
    /// Emits from both sides of every triangle.
    pub two_sided: bool,
    /// Triangle selection ∝ area.
    triangles: Distribution1D,
    /// Total area A.
    area: f32,
}

impl MeshLight {
    /// Checks the mesh (finite positions, indices in range, non-zero total area).
    pub fn new(mesh: Arc<Mesh>, radiance: Radiance, two_sided: bool) -> Result<Self, String> {
        if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(format!(
                "geometry.positions[{i}] = {} must be finite",
                mesh.positions[i]
            ));
        }
        let n = mesh.positions.len();
        if let Some(t) = mesh
            .indices
            .iter()
            .position(|tri| tri.iter().any(|&i| i as usize >= n))
        {
            return Err(format!(
                "geometry.indices[{t}] = {:?} is out of range (the mesh has {n} vertices)",
                mesh.indices[t]
            ));
        }
        if !mesh.uvs.is_empty() && mesh.uvs.len() != n {
            return Err(format!(
                "geometry.uvs has {} entries for {n} vertices",
                mesh.uvs.len()
            ));
        }
        let areas: Vec<f32> = (0..mesh.indices.len())
            .map(|t| {
                let [a, b, c] = corners(&mesh, t);
                0.5 * (b - a).cross(c - a).length()
            })
            .collect();
        let area = areas.iter().map(|&a| a as f64).sum::<f64>() as f32;
        if !(area > 0.0 && area.is_finite()) {
            return Err(format!(
                "geometry: the emissive mesh ({} triangles) has zero total area",
                mesh.indices.len()
            ));
        }
        Ok(MeshLight {
            triangles: Distribution1D::new(&areas),
            mesh,
            radiance,
            two_sided,
            area,
        })
    }

    /// Total area A.
    pub fn area(&self) -> f32 {
        self.area
    }

    /// Triangle (by area) then a uniform point on it; pdf r²/(A·|cosθl|).
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let (t, _, ux) = self.triangles.sample_discrete(u.x);
        let b = square_to_triangle(Vec2::new(ux, u.y));
        let bary = Vec3::new(b.x, b.y, 1.0 - b.x - b.y);
        let [a, b_, c] = corners(&self.mesh, t);
        let point = bary.x * a + bary.y * b_ + bary.z * c;
        let n = (b_ - a).cross(c - a).normalize_or_zero();
        let offset = point - p;
        let dist2 = offset.length_squared();
        let dist = dist2.sqrt();
        let wi = offset / dist;
        // The light faces p when wo = −wi leaves the front.
        if !self.two_sided && n.dot(wi) >= 0.0 {
            return None;
        }
        let pdf = dist2 / (self.area * n.dot(wi).abs());
        if !(pdf.is_finite() && pdf > 0.0) {
            return None;
        }
        Some(LightSample {
            wi,
            dist,
            li: self.radiance.eval(self.uv(t, bary)),
            pdf,
            delta: false,
        })
    }

    /// r²/(A·|cosθl|) for `wi` from `p` hitting the mesh at `p_light` with geometric normal
    /// `n_light`; 0 where a one-sided triangle faces away from `p`.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        if !self.two_sided && n_light.dot(wi) >= 0.0 {
            return 0.0;
        }
        area_to_solid_angle_pdf(p, wi, p_light, self.area, n_light)
    }

    /// L(uv) towards `wo` if `wo` leaves an emitting side, else zero.
    pub fn emitted(&self, n: Vec3, uv: Vec2, wo: Vec3) -> Rgb {
        self.radiance.emitted(self.two_sided, n, uv, wo)
    }

    /// Φ = π·A·mean(L), ×2 when two-sided.
    pub fn power(&self) -> f32 {
        self.radiance.power(self.two_sided, self.area)
    }

    /// Texture coordinate at barycentrics (b0, b1, b2) of triangle `t`.
    fn uv(&self, t: usize, bary: Vec3) -> Vec2 {
        if self.mesh.uvs.is_empty() {
            return Vec2::new(bary.y, bary.z);
        }
        let [i, j, k] = self.mesh.indices[t].map(|i| i as usize);
        let uvs = &self.mesh.uvs;
        bary.x * uvs[i] + bary.y * uvs[j] + bary.z * uvs[k]
    }
}

/// The three corner positions of triangle `t`.
fn corners(mesh: &Mesh, t: usize) -> [Vec3; 3] {
    mesh.indices[t].map(|i| mesh.positions[i as usize])
}

#[cfg(test)]
mod tests {
    use glam::Vec4;
    use scenes::texture::Texture;
    use scenes::WrapMode;

    use super::*;
    use crate::light::test_support::{check_pdf_consistency, irradiance, polygon_irradiance, Pcg32};
    use crate::light::Emitter;

    const L: Rgb = Vec3::new(1.0, 3.0, 0.25);

    /// Unit cube [0, 1]³ shifted by `o`, 12 triangles wound counter-clockwise from outside.
    fn cube(o: Vec3) -> Mesh {
        let positions = (0..8)
            .map(|k| o + Vec3::new((k & 1) as f32, ((k >> 1) & 1) as f32, ((k >> 2) & 1) as f32))
            .collect();
        // Faces as quads (a, b, c, d) counter-clockwise seen from outside.
        let quads = [
            [0, 4, 6, 2], // −X
            [1, 3, 7, 5], // +X
            [0, 1, 5, 4], // −Y
            [2, 6, 7, 3], // +Y
            [0, 2, 3, 1], // −Z
            [4, 5, 7, 6], // +Z
        ];
        let indices = quads
            .iter()
            .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
            .collect();
        Mesh {
            positions,
            indices,
            ..Mesh::default()
        }
    }

    /// Some(n) if `x` lies on a triangle of `mesh` (geometric normal of that triangle).
    fn on(mesh: &Mesh, x: Vec3, eps: f32) -> Option<Vec3> {
        (0..mesh.indices.len()).find_map(|t| {
            let [a, b, c] = corners(mesh, t);
            let n = (b - a).cross(c - a).normalize();
            let tol = eps + 1e-5;
            let inside = [(a, b), (b, c), (c, a)]
                .iter()
                .all(|&(p, q)| (q - p).cross(x - p).dot(n) >= -tol);
            (inside && (x - a).dot(n).abs() <= tol).then_some(n)
        })
    }

    #[test]
    fn light_mesh_cube_pdf_matches_sample_and_points_lie_on_it() {
        for two_sided in [false, true] {
            let mesh = Arc::new(cube(Vec3::new(-0.5, 1.0, -0.5)));
            let l = MeshLight::new(mesh.clone(), Radiance::Constant(L), two_sided).unwrap();
            assert!((l.area() - 6.0).abs() < 1e-5, "cube area {}", l.area());
            let e = Emitter::Mesh(l);
            for p in [Vec3::ZERO, Vec3::new(2.0, 3.0, 1.0), Vec3::new(0.0, 1.5, 0.0)] {
                let found = check_pdf_consistency(&e, p, 4000, 13, |x, eps| on(&mesh, x, eps));
                let inside = (p - Vec3::new(0.0, 1.5, 0.0)).abs().max_element() < 0.5;
                assert_eq!(found > 0, two_sided || !inside, "{p}: {found} samples");
            }
        }
    }

    #[test]
    fn light_mesh_cube_irradiance_matches_visible_faces() {
        // Outward, one-sided cube: from outside only the faces facing p emit towards it, and a
        // convex box never occludes itself, so E = Σ over front faces of Lambert's formula.
        let mesh = cube(Vec3::new(-0.5, 1.0, -0.5));
        let e = Emitter::Mesh(MeshLight::new(Arc::new(mesh.clone()), Radiance::Constant(L), false).unwrap());
        for (p, n) in [
            (Vec3::ZERO, Vec3::Y),
            (Vec3::new(1.5, 0.2, 1.2), Vec3::new(-0.5, 1.0, -0.5).normalize()),
            (Vec3::new(0.0, 30.0, 0.0), -Vec3::Y),
        ] {
            let mut want = 0.0;
            for q in 0..6 {
                let [a, b, c] = corners(&mesh, 2 * q);
                let d = mesh.positions[mesh.indices[2 * q + 1][2] as usize];
                if (b - a).cross(c - a).dot(p - a) > 0.0 {
                    want += polygon_irradiance(p, n, &[a, b, c, d]);
                }
            }
            irradiance(&e, p, n, 200_000, 19).assert_matches(L * want, 4.0, 2e-4, &format!("cube from {p}"));
        }
    }

    #[test]
    fn light_mesh_texture_uses_interpolated_uv() {
        let texels = (0..16).map(|k| Vec4::new(k as f32, 2.0, 1.0, 1.0)).collect();
        let tex = Arc::new(Texture::from_texels(4, 4, texels, [WrapMode::Clamp; 2]));
        // Quad in the z = 0 plane with uv = (x, y), facing +Z.
        let mesh = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            ..Mesh::default()
        };
        let radiance = Radiance::Image {
            texture: tex.clone(),
            factor: Vec3::splat(0.5),
        };
        let l = MeshLight::new(Arc::new(mesh), radiance, false).unwrap();
        let mut rng = Pcg32::new(8, 1);
        let p = Vec3::new(0.3, 0.6, 1.0);
        for _ in 0..500 {
            let s = l.sample_li(p, rng.next_2d()).unwrap();
            let x = p + s.wi * s.dist;
            let want = tex.sample(x.truncate()).truncate() * 0.5;
            assert!(
                (s.li - want).abs().max_element() < 1e-2,
                "at {x}: li {}, expected {want}",
                s.li
            );
            let hit = l.emitted(Vec3::Z, x.truncate(), -s.wi);
            assert!(
                (hit - s.li).abs().max_element() < 1e-2,
                "emitted {hit} vs li {}",
                s.li
            );
        }
        assert_eq!(l.emitted(Vec3::Z, Vec2::ZERO, -Vec3::Z), Rgb::ZERO, "back face");
    }

    #[test]
    fn light_mesh_rejects_degenerate_input() {
        let flat = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X],
            indices: vec![[0, 1, 2]],
            ..Mesh::default()
        };
        let e = MeshLight::new(Arc::new(flat), Radiance::Constant(L), false).unwrap_err();
        assert!(e.contains("zero total area"), "{e}");
        let bad = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![[0, 1, 3]],
            ..Mesh::default()
        };
        let e = MeshLight::new(Arc::new(bad), Radiance::Constant(L), false).unwrap_err();
        assert!(e.contains("geometry.indices[0]"), "{e}");
        let nan = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0)],
            indices: vec![[0, 1, 2]],
            ..Mesh::default()
        };
        let e = MeshLight::new(Arc::new(nan), Radiance::Constant(L), false).unwrap_err();
        assert!(e.contains("geometry.positions[2]"), "{e}");
    }
}
