//! Shapes → Mitsuba 3 shapes, with their `area` emitters.
//!
//! Sphere: `sphere` with `center` and `radius` (no rotation, so Mitsuba's local uv frame is
//! the world frame, as our sphere uv). Rectangle and disk: Mitsuba's `rectangle` ([-1, 1]²,
//! normal +Z, uv = ((x + 1)/2, (y + 1)/2)) and `disk` (unit disk, normal +Z, uv = (r, φ/2π))
//! under the affine `to_world` with columns (half_u, half_v, normalize(half_u × half_v),
//! center) — scenes/src/model.rs `Geometry` (probed: a hit on the mapped rectangle returns our
//! uv and normal). Meshes: binary PLY; vertex normals when the mesh has them, else
//! `face_normals` (Mitsuba would otherwise compute smooth normals); uvs unflipped
//! (`flip_tex_coords` false: our v = 0 is the top row, as Mitsuba's `bitmap`).
//! Emission: Mitsuba's `area` emits on the front side only, like ours by default.

use glam::Vec3;
use scenes::{Geometry, Shape};

use super::materials::bsdf_id;
use super::{Asset, Exporter};
use crate::mitsuba::ply;
use crate::mitsuba::xml::{num, Element};

impl Exporter<'_> {
    /// One `<shape>` per shape.
    pub(super) fn shapes(&mut self) -> Vec<Element> {
        let scene = self.scene;
        scene
            .shapes
            .iter()
            .enumerate()
            .filter_map(|(i, s)| self.shape(i, s))
            .collect()
    }

    fn shape(&mut self, index: usize, shape: &Shape) -> Option<Element> {
        let what = format!("shape `{}`", shape.name);
        if shape.normal_map.is_some() {
            self.refuse(format!(
                "{what}: normal map; Mitsuba's `normalmap` builds its tangent frame from ∂p/∂u, not \
                 MikkTSpace tangents as glTF (and we) do"
            ));
        }
        if shape.displacement.is_some() {
            self.refuse(format!(
                "{what}: displacement; the exporter writes the base surface only (export \
                 `scenes::displacement::patch_mesh` as a mesh to cross-check a displaced patch)"
            ));
        }
        let mut el = match &shape.geometry {
            Geometry::Sphere { center, radius } => Element::plugin("shape", "sphere")
                .child(Element::point("center", *center))
                .child(Element::float("radius", *radius)),
            Geometry::Rectangle {
                center,
                half_u,
                half_v,
            } => {
                let m = self.affine(&what, *center, *half_u, *half_v)?;
                Element::plugin("shape", "rectangle").child(m)
            }
            Geometry::Disk {
                center,
                half_u,
                half_v,
            } => {
                let m = self.affine(&what, *center, *half_u, *half_v)?;
                Element::plugin("shape", "disk").child(m)
            }
            Geometry::Mesh(mesh) => {
                let file = format!("meshes/{index}-{}.ply", scenes::to_identifier(&shape.name));
                self.assets.push((file.clone(), Asset::Ply(ply::encode(mesh))));
                Element::plugin("shape", "ply")
                    .child(Element::string("filename", &file))
                    .child(Element::boolean("face_normals", mesh.normals.is_empty()))
                    .child(Element::boolean("flip_tex_coords", false))
            }
        };
        el = el
            .attr(
                "id",
                format!("shape-{index}-{}", scenes::to_identifier(&shape.name)),
            )
            .with_comment(format!("shape `{}`", shape.name))
            .child(Element::reference(&bsdf_id(shape.material)));
        if let Some(emission) = &shape.emission {
            if emission.two_sided {
                self.refuse(format!(
                    "{what}: two-sided emission; Mitsuba's `area` emitter emits on the front side only"
                ));
                return None;
            }
            let radiance = self.rgb_input("radiance", &emission.radiance, &format!("{what} emission"))?;
            el = el.child(Element::plugin("emitter", "area").child(radiance));
        }
        Some(el)
    }

    /// `<transform name="to_world"><matrix …/>` with columns (half_u, half_v, n, center).
    fn affine(&mut self, what: &str, center: Vec3, half_u: Vec3, half_v: Vec3) -> Option<Element> {
        let n = half_u.cross(half_v);
        if !(n.length() > 0.0 && n.is_finite()) {
            self.refuse(format!("{what}: degenerate parallelogram (half_u × half_v = 0)"));
            return None;
        }
        Some(affine_matrix(center, half_u, half_v, n.normalize()))
    }
}

/// Mitsuba's `<matrix value="…"/>` (16 numbers, row-major) for the affine map with columns
/// (u, v, n, c).
pub(super) fn affine_matrix(c: Vec3, u: Vec3, v: Vec3, n: Vec3) -> Element {
    let rows = [
        [u.x, v.x, n.x, c.x],
        [u.y, v.y, n.y, c.y],
        [u.z, v.z, n.z, c.z],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let value = rows
        .iter()
        .flat_map(|r| r.iter().map(|x| num(*x)))
        .collect::<Vec<_>>()
        .join(" ");
    Element::new("transform")
        .attr("name", "to_world")
        .child(Element::new("matrix").attr("value", value))
}
