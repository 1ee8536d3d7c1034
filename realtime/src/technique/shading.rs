//! Shading frequency: where on a tessellated surface the lighting is evaluated
//! (`shaders/shading/vertex.wgsl`). Every other method shades per pixel — Phong shading
//! (Phong 1975, "Illumination for Computer Generated Pictures", CACM 18(6)): the vertex
//! normals interpolated across each triangle and the lighting evaluated at every pixel.
//! Gouraud shading (Gouraud 1971, "Continuous Shading of Curved Surfaces", IEEE Trans. Comput.
//! C-20(6)) evaluates it at the vertices and interpolates the colours: a highlight smaller
//! than a triangle that falls between vertices is lost, and one that falls on a vertex is
//! smeared across its triangles. Flat shading evaluates it once per triangle (here at the
//! triangle's provoking vertex, with the face normal, as OpenGL's flat shade model): facets.
//!
//! Only triangle meshes (glTF meshes, boxes, icospheres) have vertices; the analytic shapes
//! stay per pixel under every shading frequency. Vertex lighting runs in the vertex stage of
//! the forward pass; the deferred pipeline, which lights the G-buffer per pixel, refuses it.
//!
//! Ground truth: the oracle rendering the same mesh with its interpolated normals
//! (`direct-unshadowed`), so the shading frequency alone is measured; the tessellation's own
//! error is the exact surface's (a `sphere` instead of the icosphere).

use super::param::MethodSpec;

/// Where the lighting of mesh surfaces is evaluated (WGSL `SHADING_FREQUENCY`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShadingFrequency {
    /// Per pixel, the normals interpolated (what every other method does).
    Pixel,
    /// Per vertex, the colours interpolated.
    Vertex,
    /// Per triangle, at its provoking vertex with the face normal.
    Triangle,
}

impl ShadingFrequency {
    /// The WGSL override `SHADING_FREQUENCY`: its index in [`METHODS`].
    pub fn shader_code(self) -> u32 {
        match self {
            ShadingFrequency::Pixel => 0,
            ShadingFrequency::Vertex => 1,
            ShadingFrequency::Triangle => 2,
        }
    }

    /// The method's row in [`METHODS`].
    pub fn spec(self) -> &'static MethodSpec<ShadingFrequency> {
        &METHODS[self.shader_code() as usize]
    }
}

/// The shading-frequency methods (every method's `n` and `env_n`, none of their own).
pub static METHODS: &[MethodSpec<ShadingFrequency>] = &[
    MethodSpec {
        name: "shading_phong",
        summary: "lighting at every pixel with the vertex normals interpolated (what every other method does)",
        source: "Phong 1975, \"Illumination for Computer Generated Pictures\", CACM 18(6)",
        default: || ShadingFrequency::Pixel,
        params: &[],
    },
    MethodSpec {
        name: "shading_gouraud",
        summary: "lighting at the vertices, colours interpolated: highlights between vertices are lost, those on a \
                  vertex smeared over its triangles",
        source: "Gouraud 1971, \"Continuous Shading of Curved Surfaces\", IEEE Trans. Computers C-20(6)",
        default: || ShadingFrequency::Vertex,
        params: &[],
    },
    MethodSpec {
        name: "shading_flat",
        summary: "lighting once per triangle (its provoking vertex, the face normal): facets",
        source: "OpenGL 4.6 §13.5 (flat shading: the provoking vertex's value over the primitive)",
        default: || ShadingFrequency::Triangle,
        params: &[],
    },
];
