//! The icosphere: a regular icosahedron inscribed in the unit sphere, each triangle split into
//! four `subdivisions` times with the new vertices pushed out onto the sphere (loop-free
//! midpoint subdivision, as in Hoppe's and most modelling packages' "icosphere"). Level s has
//! 20·4^s triangles and 10·4^s + 2 vertices, shared between triangles (the mesh is closed and
//! every edge belongs to exactly two triangles). The shading-frequency studies tessellate a
//! sphere with it: its faces approximate the sphere ever closer, its vertex normals are the
//! sphere's exact normals at the vertices.
//!
//! Vertices of the icosahedron: the cyclic permutations of (0, ±1, ±φ), φ = (1 + √5)/2,
//! normalised (Coxeter 1973, "Regular Polytopes", §3.7).

use std::collections::HashMap;

use glam::Vec3;

/// Most subdivisions accepted: level 7 has 327 680 triangles.
pub const MAX_SUBDIVISIONS: u32 = 7;

/// Vertices on the unit sphere and counter-clockwise (seen from outside) triangles of the
/// icosphere of `subdivisions` levels (at most [`MAX_SUBDIVISIONS`]).
pub fn unit_icosphere(subdivisions: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    assert!(
        subdivisions <= MAX_SUBDIVISIONS,
        "icosphere subdivisions {subdivisions}"
    );
    let phi = (1.0 + 5f32.sqrt()) / 2.0;
    let mut vertices: Vec<Vec3> = [
        (-1.0, phi, 0.0),
        (1.0, phi, 0.0),
        (-1.0, -phi, 0.0),
        (1.0, -phi, 0.0),
        (0.0, -1.0, phi),
        (0.0, 1.0, phi),
        (0.0, -1.0, -phi),
        (0.0, 1.0, -phi),
        (phi, 0.0, -1.0),
        (phi, 0.0, 1.0),
        (-phi, 0.0, -1.0),
        (-phi, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, vertices: &mut Vec<Vec3>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                vertices.push(((vertices[a as usize] + vertices[b as usize]) * 0.5).normalize());
                vertices.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = midpoint(a, b, &mut vertices);
            let bc = midpoint(b, c, &mut vertices);
            let ca = midpoint(c, a, &mut vertices);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    (vertices, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_are_closed_outward_and_on_the_sphere() {
        for s in 0..=4 {
            let (v, t) = unit_icosphere(s);
            assert_eq!(t.len(), 20 * 4usize.pow(s));
            assert_eq!(v.len(), 10 * 4usize.pow(s) + 2);
            assert!(v.iter().all(|p| (p.length() - 1.0).abs() < 1e-6));
            // Every edge is shared by exactly two triangles, once in each direction.
            let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
            for tri in &t {
                for k in 0..3 {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    *edges.entry((a.min(b), a.max(b))).or_default() += if a < b { 1 } else { -1 };
                }
                // Counter-clockwise from outside: the face normal points away from the centre.
                let [a, b, c] = tri.map(|i| v[i as usize]);
                assert!((b - a).cross(c - a).dot(a + b + c) > 0.0, "level {s}: {tri:?}");
            }
            assert!(
                edges.values().all(|&n| n == 0),
                "level {s}: an edge is not shared by two triangles"
            );
            assert_eq!(edges.len(), 30 * 4usize.pow(s));
        }
    }
}
