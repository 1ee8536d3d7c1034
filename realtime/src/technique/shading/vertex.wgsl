// shading/vertex.wgsl — lighting at the vertices (technique/shading.rs). SHADING_FREQUENCY
// chooses what the forward pass's meshes do with it: SHADING_GOURAUD interpolates the vertex
// colours across each triangle (Gouraud 1971); SHADING_FLAT keeps the provoking vertex's
// colour, lit with the face normal, over the whole triangle (OpenGL's flat shade model).
// Every light, quadrature and environment term is the per-pixel method's own (shade_surface),
// only evaluated at the vertex, seen from the camera along the vertex's own view direction.
// Failure mode: a highlight narrower than a triangle is lost between vertices or smeared from
// one; texture detail finer than the triangles is averaged away with it (the vertex's texels
// light the triangle) unless VERTEX_ALBEDO applies the base colour per pixel:
// VERTEX_ALBEDO_MODULATE multiplies the interpolated colour, lit with a white base colour, by
// the texture (OpenGL's GL_MODULATE: the highlights are darkened and tinted with it);
// VERTEX_ALBEDO_SEPARATE_SPECULAR interpolates the diffuse term (white base colour) and the
// specular term (black base colour) apart and adds the specular after the texture (OpenGL 1.2
// §3.9, GL_SEPARATE_SPECULAR_COLOR). Both read the split off two lightings of the vertex, exact
// where the specular term does not depend on the base colour (dielectrics: Lambert, glTF
// metal-rough with metallic 0); a metal's specular colour is the texture's, so theirs is wrong.

override SHADING_FREQUENCY: u32 = 0u;
override VERTEX_ALBEDO: u32 = 0u;

struct VertexLitVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) shape: u32,
    @location(2) normal: vec3<f32>,
    @location(3) albedo: vec3<f32>,
    // Gouraud: the vertex colours (with a white base colour under VERTEX_ALBEDO_MODULATE, the
    // diffuse term alone under VERTEX_ALBEDO_SEPARATE_SPECULAR), interpolated.
    @location(4) lit: vec3<f32>,
    // Flat: the provoking vertex's colour, lit with the face normal.
    @location(5) @interpolate(flat) lit_flat: vec3<f32>,
    // Gouraud under VERTEX_ALBEDO_SEPARATE_SPECULAR: the specular term, interpolated.
    @location(6) specular: vec3<f32>,
    @location(7) uv: vec2<f32>,
}

@vertex
fn vs_mesh_vertex_lit(v: MeshVertexIn) -> VertexLitVarying {
    var out: VertexLitVarying;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.shape = v.shape;
    out.normal = v.normal;
    out.uv = v.uv;
    let wo = normalize(frame.cam_pos.xyz - v.position);
    // Gouraud lights the vertex with its own normal, flat with the face's.
    let n = select(v.normal, v.ng, SHADING_FREQUENCY == SHADING_FLAT);
    let sp = SurfacePoint(v.position, v.ng, n, v.uv, v.shape);
    let per_pixel_albedo = SHADING_FREQUENCY == SHADING_GOURAUD && VERTEX_ALBEDO != VERTEX_ALBEDO_VERTEX;
    if per_pixel_albedo {
        base_color_override = 1.0;
    }
    let lit = shade_surface(frame, sp, wo, vec2<f32>(0.0));
    out.lit = lit.color;
    out.lit_flat = lit.color;
    out.albedo = lit.albedo;
    out.specular = vec3<f32>(0.0);
    if per_pixel_albedo && VERTEX_ALBEDO == VERTEX_ALBEDO_SEPARATE_SPECULAR {
        // With a black base colour only the specular term (and emission) is left.
        base_color_override = 0.0;
        out.specular = shade_surface(frame, sp, wo, vec2<f32>(0.0)).color;
        out.lit = lit.color - out.specular;
    }
    base_color_override = -1.0;
    return out;
}

@fragment
fn fs_mesh_vertex_lit(in: VertexLitVarying) -> ShadedOut {
    var color = select(in.lit, in.lit_flat, SHADING_FREQUENCY == SHADING_FLAT);
    var albedo = in.albedo;
    if SHADING_FREQUENCY == SHADING_GOURAUD && VERTEX_ALBEDO != VERTEX_ALBEDO_VERTEX {
        // The base colour at this pixel, as resolve_bsdf reads it (the albedo AOV was the
        // white base colour's).
        let m = materials[shapes[in.shape].material];
        let base = sanitize_rgb(eval_tex_rgb(m.color_tex, m.color.xyz, in.uv));
        color = base * color + in.specular;
        albedo = in.albedo * base;
    }
    let n = normalize(in.normal);
    return ShadedOut(
        vec4<f32>(color, 1.0),
        vec4<f32>(n, view_depth(frame, in.world)),
        vec4<f32>(albedo, f32(in.shape + 1u)),
    );
}
