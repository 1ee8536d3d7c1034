//! Binary little-endian PLY meshes for Mitsuba 3's `ply` shape (Turk 1994, "The PLY polygon
//! file format"; the property names Mitsuba 3's `ply` plugin reads: `x y z`, `nx ny nz`,
//! `u v`, and the face list `vertex_indices`).

use scenes::Mesh;

/// The mesh as a PLY file: positions, normals and uvs when the mesh has them, triangles.
pub fn encode(mesh: &Mesh) -> Vec<u8> {
    let has_normals = !mesh.normals.is_empty();
    let has_uvs = !mesh.uvs.is_empty();
    let mut header = String::from("ply\nformat binary_little_endian 1.0\ncomment written by verity\n");
    header += &format!("element vertex {}\n", mesh.positions.len());
    header += "property float x\nproperty float y\nproperty float z\n";
    if has_normals {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if has_uvs {
        header += "property float u\nproperty float v\n";
    }
    header += &format!("element face {}\n", mesh.indices.len());
    header += "property list uchar int vertex_indices\nend_header\n";

    let per_vertex = 4 * (3 + 3 * usize::from(has_normals) + 2 * usize::from(has_uvs));
    let mut out = header.into_bytes();
    out.reserve(mesh.positions.len() * per_vertex + mesh.indices.len() * 13);
    for (i, p) in mesh.positions.iter().enumerate() {
        let mut put = |x: f32| out.extend_from_slice(&x.to_le_bytes());
        p.to_array().into_iter().for_each(&mut put);
        if has_normals {
            mesh.normals[i].to_array().into_iter().for_each(&mut put);
        }
        if has_uvs {
            mesh.uvs[i].to_array().into_iter().for_each(&mut put);
        }
    }
    for tri in &mesh.indices {
        out.push(3);
        for &v in tri {
            // Indices were validated against the vertex count by the loader (< 2^31 here).
            out.extend_from_slice(&(v as i32).to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    #[test]
    fn header_and_payload_sizes() {
        let mesh = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y],
            tangents: vec![],
            indices: vec![[0, 1, 2]],
            uv1: Vec::new(),
        };
        let bytes = encode(&mesh);
        let text = String::from_utf8_lossy(&bytes);
        let end = text.find("end_header\n").expect("header end") + "end_header\n".len();
        let header = &text[..end];
        for line in [
            "element vertex 3",
            "property float nx",
            "property float u",
            "element face 1",
        ] {
            assert!(header.contains(line), "missing `{line}` in\n{header}");
        }
        assert_eq!(bytes.len() - end, 3 * 8 * 4 + 13, "payload size");
        // First vertex x (0.0) and last index (2) as stored.
        assert_eq!(&bytes[end..end + 4], &0f32.to_le_bytes());
        assert_eq!(&bytes[bytes.len() - 4..], &2i32.to_le_bytes());

        let flat = Mesh {
            normals: vec![],
            uvs: vec![],
            ..mesh
        };
        let flat_bytes = encode(&flat);
        let flat_text = String::from_utf8_lossy(&flat_bytes);
        assert!(!flat_text.contains("property float nx") && !flat_text.contains("property float u"));
    }
}
