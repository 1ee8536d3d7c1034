//! Shading frequency: where on a tessellated surface the lighting is evaluated
//! (`technique/shading/vertex.wgsl`). Every other method shades per pixel — Phong shading
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

use super::method::{wgsl_method_codes, Family, Frame, Method, MethodInfo, Override, Row, Settings};
use super::param::{Kind, MethodSpec, Param, Value};

/// Where Gouraud shading takes a textured base colour (albedo) from (WGSL `VERTEX_ALBEDO`).
/// Fixed-function OpenGL lit vertices with the material's colour and applied the texture per
/// fragment (`GL_MODULATE`), which darkens and tints the highlights with the texture;
/// OpenGL 1.2's separate specular colour (`GL_SEPARATE_SPECULAR_COLOR`, OpenGL 1.2 §3.9) interpolates
/// the specular term apart and adds it after the texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VertexAlbedo {
    /// The whole material at the vertex, its textures sampled there: texture detail finer
    /// than the triangles is lost with the lighting.
    Vertex,
    /// The vertices lit with a white base colour, the interpolated colour multiplied by the
    /// texture at each pixel: the highlights are multiplied by it too.
    Modulate,
    /// The diffuse term (lit with a white base colour) and the specular term interpolated
    /// apart; each pixel takes texture × diffuse + specular.
    SeparateSpecular,
}

impl VertexAlbedo {
    /// The keywords, in WGSL code order.
    const NAMES: &'static [&'static str] = &["vertex", "modulate", "separate_specular"];

    fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    fn from_name(name: &str) -> Option<VertexAlbedo> {
        [
            VertexAlbedo::Vertex,
            VertexAlbedo::Modulate,
            VertexAlbedo::SeparateSpecular,
        ]
        .into_iter()
        .find(|a| a.name() == name)
    }
}

/// Where the lighting of mesh surfaces is evaluated (WGSL `SHADING_FREQUENCY`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShadingFrequency {
    /// Per pixel, the normals interpolated (what every other method does).
    Pixel,
    /// Per vertex, the colours interpolated.
    Vertex {
        /// Where a textured base colour is applied.
        albedo: VertexAlbedo,
    },
    /// Per triangle, at its provoking vertex with the face normal.
    Triangle,
}

impl ShadingFrequency {
    /// The WGSL override `SHADING_FREQUENCY`: its index in [`METHODS`].
    pub fn shader_code(self) -> u32 {
        match self {
            ShadingFrequency::Pixel => 0,
            ShadingFrequency::Vertex { .. } => 1,
            ShadingFrequency::Triangle => 2,
        }
    }

    /// The WGSL override `VERTEX_ALBEDO` (`VERTEX_ALBEDO_VERTEX` but for Gouraud's other
    /// variants).
    pub fn albedo_code(self) -> u32 {
        match self {
            ShadingFrequency::Vertex { albedo } => albedo as u32,
            _ => VertexAlbedo::Vertex as u32,
        }
    }

    /// The method's row in [`METHODS`].
    pub fn spec(self) -> &'static MethodSpec<ShadingFrequency> {
        &METHODS[self.shader_code() as usize]
    }

    /// Its parameter rows.
    pub fn rows(&self) -> impl Iterator<Item = &'static Param<ShadingFrequency>> {
        self.spec().params.iter()
    }
}

/// The WGSL constants of `VERTEX_ALBEDO` (`VERTEX_ALBEDO_MODULATE` …), in code order.
pub fn wgsl_codes() -> String {
    VertexAlbedo::NAMES
        .iter()
        .enumerate()
        .map(|(i, n)| format!("const VERTEX_ALBEDO_{}: u32 = {i}u;\n", n.to_uppercase()))
        .collect()
}

const GOURAUD_ALBEDO: Param<ShadingFrequency> = Param {
    name: "albedo",
    kind: Kind::Keyword(VertexAlbedo::NAMES),
    unit: "",
    doc: "a textured base colour: sampled at the vertices with the rest of the material (`vertex`), applied per \
          pixel to the interpolated colour, highlights included (`modulate`), or per pixel to the diffuse term \
          alone with the specular interpolated apart and added after (`separate_specular`)",
    source: "OpenGL 1.2 §3.9 (GL_MODULATE; GL_SEPARATE_SPECULAR_COLOR)",
    unset: "",
    get: |s| match s {
        ShadingFrequency::Vertex { albedo } => Some(Value::Keyword(albedo.name())),
        _ => None,
    },
    set: |s, v| match s {
        ShadingFrequency::Vertex { albedo } => {
            *albedo = VertexAlbedo::from_name(v.keyword()?)?;
            Some(())
        }
        _ => None,
    },
};

/// The shading-frequency methods (every method's `n` and `env_n`; Gouraud's `albedo`).
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
        default: || ShadingFrequency::Vertex {
            albedo: VertexAlbedo::Vertex,
        },
        params: &[GOURAUD_ALBEDO],
    },
    MethodSpec {
        name: "shading_flat",
        summary: "lighting once per triangle (its provoking vertex, the face normal): facets",
        source: "OpenGL 4.6 §13.5 (flat shading: the provoking vertex's value over the primitive)",
        default: || ShadingFrequency::Triangle,
        params: &[],
    },
];

/// The shading-frequency family.
pub struct ShadingFrequencies;

impl Family for ShadingFrequencies {
    fn title(&self) -> &'static str {
        "Shading frequency"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(METHODS)
    }

    /// Over N×N quadrature (n = 8, env_n = 8), unshadowed.
    fn method(&self, name: &str) -> Option<Method> {
        Method::from_table(METHODS, name, 8)
    }

    /// `SHADING_*` and `VERTEX_ALBEDO_*`.
    fn wgsl_codes(&self) -> String {
        wgsl_method_codes("SHADING_", None, METHODS) + &wgsl_codes()
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[("shading/vertex.wgsl", include_str!("vertex.wgsl"))]
    }
}

impl Settings for ShadingFrequency {
    fn method_name(&self) -> &'static str {
        self.spec().name
    }

    fn rows(&self) -> Vec<Row> {
        Row::all(ShadingFrequency::rows(self))
    }

    /// `SHADING_FREQUENCY` and `VERTEX_ALBEDO` (a vertex-lit frequency also picks the forward
    /// mesh pipeline's vertex-lit entry points, pipelines.rs).
    fn overrides(&self) -> Vec<Override> {
        vec![
            Override::shading("SHADING_FREQUENCY", self.shader_code()),
            Override::shading("VERTEX_ALBEDO", self.albedo_code()),
        ]
    }

    fn check(&self, method: &Method, frame: &Frame<'_>) -> Result<(), String> {
        if self.shader_code() != 0 && frame.deferred {
            return Err(format!(
                "method {method}: vertex lighting runs in the forward pass's vertex stage; the deferred pipeline lights \
                 every pixel of its G-buffer"
            ));
        }
        Ok(())
    }
}
