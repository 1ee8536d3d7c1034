// projection.wgsl — a spot light's projected texture (a cookie or gobo): projective texture
// mapping (Segal, Korobkin, van Widenfelt, Foran & Haeberli 1992, "Fast Shadows and Lighting
// Effects Using Texture Mapping", SIGGRAPH, §3), the light a projector whose texture
// coordinates are the shaded point in its frame, divided by depth.
//
// uv = (½ + ½·(r·q)/((a·q)·tan θc), ½ − ½·(t·q)/((a·q)·tan θc)), q = p − the light's position,
// a its axis, r its right axis, t = r × a (scenes::projection, where the oracle evaluates
// the same uv exactly). The texture is read through the method's texture filter over the
// footprint of uv in the pixel: ∂uv/∂x = J·∂p/∂x, ∂uv/∂y = J·∂p/∂y with ∂p from ray
// differentials on the tangent plane (texture/filter.wgsl `pixel_differentials`; never
// hardware derivatives: the light loop is not uniform control flow) and the Jacobian
// ∂u/∂q = s·(r − (r·q)/(a·q)·a), ∂v/∂q = −s·(t − (t·q)/(a·q)·a), s = ½/((a·q)·tan θc).
// Failure modes: the filters' own (minified cookies alias under nearest and bilinear, grazing
// projections stretch the footprint past max_anisotropy); the tangent plane stands in for
// the surface over the pixel.
// Inputs: `Light.projection_tex`, `Light.projection` (r, tan θc), the texture buffers.

// The projected colour T(uv) reaching the surface point `sp` from light `l` (1 for a light
// without a projected texture, 0 behind a projecting spot).
fn projected_texture(f: FrameUniforms, l: Light, sp: SurfacePoint) -> vec3<f32> {
    if l.kind != LIGHT_SPOT || l.projection_tex == NONE {
        return vec3<f32>(1.0);
    }
    let a = l.direction.xyz;
    let r = l.projection.xyz;
    let t = cross(r, a);
    let q = sp.p - l.position.xyz;
    let z = dot(a, q);
    if !(z > 0.0) {
        return vec3<f32>(0.0);
    }
    let s = 0.5 / (z * l.projection.w);
    let uv = vec2<f32>(0.5 + s * dot(r, q), 0.5 - s * dot(t, q));
    let saved = uv_footprint;
    if filter_reads_footprint() {
        let du = s * (r - (dot(r, q) / z) * a);
        let dv = -s * (t - (dot(t, q) / z) * a);
        let pd = pixel_differentials(f, sp.p, sp.ng);
        let fp = vec4<f32>(dot(du, pd.dpx), dot(dv, pd.dpx), dot(du, pd.dpy), dot(dv, pd.dpy));
        uv_footprint = select(vec4<f32>(0.0), fp, all(abs(fp) < vec4<f32>(1e30)));
    }
    let c = texture_filtered(l.projection_tex, uv).xyz;
    uv_footprint = saved;
    return c;
}
