// shading/vertex.wgsl — lighting at the vertices (technique/shading.rs). SHADING_FREQUENCY
// chooses what the forward pass's meshes do with it: SHADING_GOURAUD interpolates the vertex
// colours across each triangle (Gouraud 1971); SHADING_FLAT keeps the provoking vertex's
// colour, lit with the face normal, over the whole triangle (OpenGL's flat shade model).
// Every light, quadrature and environment term is the per-pixel method's own (shade_surface),
// only evaluated at the vertex, seen from the camera along the vertex's own view direction.
// Failure mode: a highlight narrower than a triangle is lost between vertices or smeared from
// one; texture detail finer than the triangles is averaged away with it (the vertex's texels
// light the triangle).

override SHADING_FREQUENCY: u32 = 0u;

struct VertexLitVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) shape: u32,
    @location(2) normal: vec3<f32>,
    @location(3) albedo: vec3<f32>,
    // Gouraud: the vertex colours, interpolated.
    @location(4) lit: vec3<f32>,
    // Flat: the provoking vertex's colour, lit with the face normal.
    @location(5) @interpolate(flat) lit_flat: vec3<f32>,
}

@vertex
fn vs_mesh_vertex_lit(v: MeshVertexIn) -> VertexLitVarying {
    var out: VertexLitVarying;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.shape = v.shape;
    out.normal = v.normal;
    let wo = normalize(frame.cam_pos.xyz - v.position);
    // Gouraud lights the vertex with its own normal, flat with the face's.
    let n = select(v.normal, v.ng, SHADING_FREQUENCY == SHADING_FLAT);
    let lit = shade_surface(frame, SurfacePoint(v.position, v.ng, n, v.uv, v.shape), wo, vec2<f32>(0.0));
    out.lit = lit.color;
    out.lit_flat = lit.color;
    out.albedo = lit.albedo;
    return out;
}

@fragment
fn fs_mesh_vertex_lit(in: VertexLitVarying) -> ShadedOut {
    let color = select(in.lit, in.lit_flat, SHADING_FREQUENCY == SHADING_FLAT);
    let n = normalize(in.normal);
    return ShadedOut(
        vec4<f32>(color, 1.0),
        vec4<f32>(n, view_depth(frame, in.world)),
        vec4<f32>(in.albedo, f32(in.shape + 1u)),
    );
}
