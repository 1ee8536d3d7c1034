// passes.wgsl — entry points of the forward pass, the G-buffer pass, the deferred lighting
// pass and the background.
//
// Technique: forward shading (shade in the fragment stage of the geometry pass) and deferred
// shading (Saito & Takahashi 1990, "Comprehensible Rendering of 3-D Shapes", SIGGRAPH: the
// G-buffer; then one full-screen lighting pass), sharing every function below the entry points,
// so the two give the same image: the G-buffer holds the surface point in f32 exactly as the
// forward pass computes it (position + object id, shading normal + u, geometric normal + v).
// Depth is reversed-Z with an infinite far plane (Reed 2015, "Depth Precision Visualized",
// NVIDIA developer blog), cleared to 0; the background is drawn where the depth is still 0.
// The lighting entry point is also the counting pass (counters_on.wgsl): it alone flushes the
// cost counters.
// Failure mode: none of its own. The G-buffer costs 48 bytes per sample (three Rgba32Float
// targets); adapters below that colour-attachment budget are refused up front.
// The shadow pass (Williams 1978, shadow/map_common.wgsl) renders depth only, one render pass
// per light: meshes rasterised, analytic shapes ray traced per texel on the same proxies with
// the same `intersect_analytic` as the camera passes, writing frag_depth. The visibility AOV
// pass is a full-screen pass over a G-buffer, untimed, that stores every light's V.
// Inputs: vertex buffers (meshes: de-indexed triangles with per-triangle flat data; analytic
// proxies: position + shape), group 0 (scene, shadow uniforms), group 1 (G-buffer: lighting
// and visibility AOV passes; the lighting's also the SSAO passes' obscurance), group 2 (shadow
// maps: every shading pass).

struct MeshVertexIn {
    @location(0) position: vec3<f32>,
    @location(1) shape: u32,
    @location(2) normal: vec3<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) tangent: vec4<f32>,
    @location(5) ng: vec3<f32>,
    @location(6) dpdu: vec3<f32>,
    @location(7) dpdv: vec3<f32>,
    @location(8) uv1: vec2<f32>,
}

struct MeshVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) shape: u32,
    @location(2) normal: vec3<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) tangent: vec4<f32>,
    @location(5) @interpolate(flat) ng: vec3<f32>,
    @location(6) @interpolate(flat) dpdu: vec3<f32>,
    @location(7) @interpolate(flat) dpdv: vec3<f32>,
    @location(8) uv1: vec2<f32>,
}

struct AnalyticVertexIn {
    @location(0) position: vec3<f32>,
    @location(1) shape: u32,
}

struct AnalyticVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) shape: u32,
}

// Shaded colour, normal AOV + depth AOV, albedo AOV + object id (shape index + 1).
struct ShadedOut {
    @location(0) color: vec4<f32>,
    @location(1) normal_depth: vec4<f32>,
    @location(2) albedo_id: vec4<f32>,
}

struct ShadedDepthOut {
    @location(0) color: vec4<f32>,
    @location(1) normal_depth: vec4<f32>,
    @location(2) albedo_id: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

// G-buffer: position + object id, shading normal + u, geometric normal + v.
struct GBufferOut {
    @location(0) g0: vec4<f32>,
    @location(1) g1: vec4<f32>,
    @location(2) g2: vec4<f32>,
}

struct GBufferDepthOut {
    @location(0) g0: vec4<f32>,
    @location(1) g1: vec4<f32>,
    @location(2) g2: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@group(1) @binding(0) var gbuffer0: texture_2d<f32>;
@group(1) @binding(1) var gbuffer1: texture_2d<f32>;
@group(1) @binding(2) var gbuffer2: texture_2d<f32>;
// The G-buffer under deferred MSAA (aa_msaa): `samples` samples per pixel.
@group(1) @binding(3) var gbuffer_ms0: texture_multisampled_2d<f32>;
@group(1) @binding(4) var gbuffer_ms1: texture_multisampled_2d<f32>;
@group(1) @binding(5) var gbuffer_ms2: texture_multisampled_2d<f32>;
// Ambient obscurance 1 − AO per pixel, written by the SSAO passes (ssao/*.wgsl); zero, so
// nothing occluded, where no SSAO method ran.
@group(1) @binding(6) var ao_obscurance: texture_2d<f32>;

@vertex
fn vs_mesh(v: MeshVertexIn) -> MeshVarying {
    var out: MeshVarying;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.shape = v.shape;
    out.normal = v.normal;
    out.uv = v.uv;
    out.tangent = v.tangent;
    out.ng = v.ng;
    out.dpdu = v.dpdu;
    out.dpdv = v.dpdv;
    out.uv1 = v.uv1;
    return out;
}

@vertex
fn vs_analytic(v: AnalyticVertexIn) -> AnalyticVarying {
    return AnalyticVarying(frame.view_proj * vec4<f32>(v.position, 1.0), v.shape);
}

// Vertex i of one triangle covering the target, at the far plane (depth 0, reversed-Z).
fn fullscreen_vertex(i: u32) -> vec4<f32> {
    let x = f32(i32(i & 1u) * 4 - 1);
    let y = f32(i32(i >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 0.0, 1.0);
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_vertex(i);
}

// The surface point of a mesh fragment, after surface detail (`hit` false: discard).
fn mesh_surface(in: MeshVarying, s: Shape) -> AnalyticHit {
    let d = mesh_differential(in.world, in.normal, in.uv, in.tangent, in.ng, in.dpdu, in.dpdv, s.emission_info.w != 0u);
    return detailed_surface(frame, d, s, in.shape);
}

// Shading and AOVs of a surface point seen through target pixel `frag`.
fn shaded_output(f: FrameUniforms, sp: SurfacePoint, frag: vec2<f32>) -> ShadedOut {
    let xy = film_position(f, frag);
    let wo = -camera_ray_direction(f, xy.x, xy.y);
    let sh = shade_surface(f, sp, wo, frag);
    return ShadedOut(
        vec4<f32>(sh.color, 1.0),
        vec4<f32>(sp.ns, view_depth(f, sp.p)),
        vec4<f32>(sh.albedo, f32(sp.shape + 1u)),
    );
}

// The background seen through target pixel `frag`: AOVs zero (the oracle's background).
fn background_output(f: FrameUniforms, frag: vec2<f32>) -> ShadedOut {
    let xy = film_position(f, frag);
    let l = distant_radiance(f, camera_ray_direction(f, xy.x, xy.y));
    return ShadedOut(vec4<f32>(l, 1.0), vec4<f32>(0.0), vec4<f32>(0.0));
}

fn gbuffer_output(sp: SurfacePoint) -> GBufferOut {
    // Toksvig's |n̄| travels as the stored normal's length (lit_sample divides it out).
    let ns = select(sp.ns, sp.ns * normal_map_length, SPECULAR_AA == 2u);
    return GBufferOut(
        vec4<f32>(sp.p, gbuffer_tag(sp.shape)),
        vec4<f32>(ns, sp.uv.x),
        vec4<f32>(sp.ng, sp.uv.y),
    );
}

// Depth peeling of a layered distance map's capture (Everitt 2001, "Interactive
// Order-Independent Transparency", NVIDIA: each layer keeps the nearest surface behind the
// previous one). With envmap.local.x = LOCAL_PEEL, envmap_flat holds the previous layer's cube
// face (columns mirrored, as cs_face_copy writes it; alpha: distance from the capture point,
// which is the camera): what lies no further than that, by a relative 2⁻⁹ (four f16 ulps of
// the stored distance), is peeled away. 0 otherwise: nothing is.
fn peel_distance(frag: vec2<f32>) -> f32 {
    if envmap.local.x != LOCAL_PEEL {
        return 0.0;
    }
    let n = i32(textureDimensions(envmap_flat).x);
    let px = vec2<i32>(frag);
    let previous = textureLoad(envmap_flat, vec2<i32>(n - 1 - px.x, px.y), 0, 0).w;
    return previous * (1.0 + 1.0 / 512.0);
}

// The uv of the undetailed surface of analytic shape `s` seen through target pixel `frag`
// (the plane or sphere extended past the shape's edge), as rectangle_differential,
// disk_differential and sphere_differential give it.
fn analytic_base_uv(f: FrameUniforms, s: Shape, frag: vec2<f32>) -> vec2<f32> {
    let xy = film_position(f, frag);
    let o = f.cam_pos.xyz;
    let d = camera_ray_direction(f, xy.x, xy.y);
    let st = plane_local(s, o + d * intersect_plane(s, o, d));
    let rectangle = (clamp(st, vec2<f32>(-1.0), vec2<f32>(1.0)) + 1.0) * 0.5;
    let disk = vec2<f32>(min(length(st), 1.0), fract(atan2(st.y, st.x) / TAU + 1.0));
    let oc = o - s.center.xyz;
    let b = dot(oc, d);
    let t = -b - sqrt(max(b * b - dot(oc, oc) + s.center.w * s.center.w, 0.0));
    let n = normalize(oc + d * t);
    let sphere = vec2<f32>(fract(atan2(n.y, n.x) / TAU + 1.0), acos(clamp(n.z, -1.0, 1.0)) / PI);
    return select(select(rectangle, disk, s.kind == SHAPE_DISK), sphere, s.kind == SHAPE_SPHERE);
}

// The texture filters' hardware footprint of an analytic shape's fragment: the fine quad
// derivatives (the difference to the quad's other pixel in x and in y) of the shape's uv,
// evaluated in this invocation rather than read from the quad's helper invocations, which
// lavapipe does not run reliably for these proxies (a line of over-blurred pixels followed
// the proxy's triangle edge). A GPU computing dpdxFine/dpdyFine of the same uv gets the same.
fn set_analytic_shape_footprint(in: AnalyticVarying) {
    if filter_reads_footprint() && TEXTURE_DERIVATIVES == 0u {
        let s = shapes[in.shape];
        let px = vec2<i32>(floor(in.clip.xy));
        let step = select(vec2<f32>(1.0), vec2<f32>(-1.0), (px & vec2<i32>(1)) == vec2<i32>(1));
        let uv = analytic_base_uv(frame, s, in.clip.xy);
        let dx = (analytic_base_uv(frame, s, in.clip.xy + vec2<f32>(step.x, 0.0)) - uv) * step.x;
        let dy = (analytic_base_uv(frame, s, in.clip.xy + vec2<f32>(0.0, step.y)) - uv) * step.y;
        let fp = vec4<f32>(dx, dy);
        uv_footprint = select(vec4<f32>(0.0), fp, all(abs(fp) < vec4<f32>(1e30)));
    }
}

// Geometric specular AA's normal change of an analytic shape's fragment: the shading normal's
// differences to the quad's other pixel in x and in y, traced in this invocation (as
// set_analytic_shape_footprint, for the same reason); an axis whose neighbour misses the
// shape counts no change.
fn set_analytic_normal_change(in: AnalyticVarying, n: vec3<f32>) {
    if SPECULAR_AA != 1u {
        return;
    }
    let s = shapes[in.shape];
    let px = vec2<i32>(floor(in.clip.xy));
    let step = select(vec2<f32>(1.0), vec2<f32>(-1.0), (px & vec2<i32>(1)) == vec2<i32>(1));
    let hx = trace_analytic(frame, s, in.shape, in.clip.xy + vec2<f32>(step.x, 0.0), 0.0);
    let hy = trace_analytic(frame, s, in.shape, in.clip.xy + vec2<f32>(0.0, step.y), 0.0);
    let dx = select(vec3<f32>(0.0), hx.surface.ns - n, hx.hit);
    let dy = select(vec3<f32>(0.0), hy.surface.ns - n, hy.hit);
    // The neighbours' normal-map lookups overwrote the pixel's own |n̄|; Toksvig is not this method.
    set_normal_differences(dx, dy);
}

// The texture filters' hardware footprint of a mesh fragment (uniform control flow).
fn set_mesh_footprint(in: MeshVarying) {
    if filter_reads_footprint() && TEXTURE_DERIVATIVES == 0u {
        set_hardware_footprint(in.uv);
    }
}

@fragment
fn fs_mesh_forward(in: MeshVarying) -> ShadedOut {
    set_mesh_footprint(in);
    mesh_lightmap_uv = in.uv1;
    let hit = mesh_surface(in, shapes[in.shape]);
    set_normal_derivatives(hit.surface.ns);
    if !hit.hit || distance(hit.surface.p, frame.cam_pos.xyz) <= peel_distance(in.clip.xy) {
        discard;
    }
    return shaded_output(frame, hit.surface, in.clip.xy);
}

@fragment
fn fs_analytic_forward(in: AnalyticVarying) -> ShadedDepthOut {
    set_analytic_shape_footprint(in);
    let hit = trace_analytic(frame, shapes[in.shape], in.shape, in.clip.xy, peel_distance(in.clip.xy));
    if !hit.hit {
        discard;
    }
    set_analytic_normal_change(in, hit.surface.ns);
    let out = shaded_output(frame, hit.surface, in.clip.xy);
    return ShadedDepthOut(out.color, out.normal_depth, out.albedo_id, depth_of(frame, hit.surface.p));
}

@fragment
fn fs_background(@builtin(position) pos: vec4<f32>) -> ShadedOut {
    return background_output(frame, pos.xy);
}

@fragment
fn fs_mesh_gbuffer(in: MeshVarying) -> GBufferOut {
    set_mesh_footprint(in);
    let hit = mesh_surface(in, shapes[in.shape]);
    if !hit.hit {
        discard;
    }
    return gbuffer_output(hit.surface);
}

@fragment
fn fs_analytic_gbuffer(in: AnalyticVarying) -> GBufferDepthOut {
    set_analytic_shape_footprint(in);
    let hit = trace_analytic(frame, shapes[in.shape], in.shape, in.clip.xy, 0.0);
    if !hit.hit {
        discard;
    }
    let out = gbuffer_output(hit.surface);
    return GBufferDepthOut(out.g0, out.g1, out.g2, depth_of(frame, hit.surface.p));
}

// One G-buffer sample lit (or the background where it holds no surface).
fn lit_sample(g0: vec4<f32>, g1: vec4<f32>, g2: vec4<f32>, pos: vec2<f32>) -> ShadedOut {
    if g0.w < 0.5 {
        return background_output(frame, pos);
    }
    var ns = g1.xyz;
    if SPECULAR_AA == 2u {
        normal_map_length = length(ns);
        ns /= normal_map_length;
    }
    let sp = SurfacePoint(g0.xyz, g2.xyz, ns, vec2<f32>(g1.w, g2.w), gbuffer_shape(g0.w));
    return shaded_output(frame, sp, pos);
}

@fragment
fn fs_lighting(@builtin(position) pos: vec4<f32>) -> ShadedOut {
    let px = vec2<i32>(pos.xy);
    let g0 = textureLoad(gbuffer0, px, 0);
    let g1 = textureLoad(gbuffer1, px, 0);
    let g2 = textureLoad(gbuffer2, px, 0);
    // The texture filters' footprint: the stored uv differenced over the quad (wrong at
    // silhouettes, where a neighbour is another surface or the background). Analytic
    // derivatives are not stored, so this pass uses these in the counting frame too.
    if filter_reads_footprint() {
        set_hardware_footprint(vec2<f32>(g1.w, g2.w));
    }
    set_normal_derivatives(g1.xyz);
    ambient_occlusion = clamp(1.0 - textureLoad(ao_obscurance, px, 0).r, 0.0, 1.0);
    var out = lit_sample(g0, g1, g2, pos.xy);
    // An SSAO method's `output = ao`: the AO factor itself, 0 on the background (the oracle's
    // `ao` integrator).
    if frame.families.ambient_occlusion.output == 1u {
        out.color = vec4<f32>(vec3<f32>(select(0.0, ambient_occlusion, g0.w >= 0.5)), 1.0);
    }
    flush_counters(u32(pos.y));
    return out;
}

// Deferred MSAA: the G-buffer holds every coverage sample, and the lighting decides per pixel
// how often to shade — once, from sample 0, where all samples see one surface (same shape tag,
// normals within 8°), else every sample, averaged: the per-sample lighting of edge pixels that
// keeps deferred MSAA's cost near forward MSAA's (Lauritzen 2010, "Deferred Rendering for
// Current and Future Rendering Pipelines", SIGGRAPH course, §MSAA). The object id is sample
// 0's, as the forward resolve's. Sample positions are not the pixel centre, but every sample
// is lit with the centre's view direction (the standard shortcut).
@fragment
fn fs_lighting_msaa(@builtin(position) pos: vec4<f32>) -> ShadedOut {
    let px = vec2<i32>(pos.xy);
    let n = textureNumSamples(gbuffer_ms0);
    let g0 = textureLoad(gbuffer_ms0, px, 0);
    let g1 = textureLoad(gbuffer_ms1, px, 0);
    let g2 = textureLoad(gbuffer_ms2, px, 0);
    if filter_reads_footprint() {
        set_hardware_footprint(vec2<f32>(g1.w, g2.w));
    }
    set_normal_derivatives(g1.xyz);
    var edge = false;
    for (var s = 1u; s < n; s += 1u) {
        let t0 = textureLoad(gbuffer_ms0, px, i32(s));
        let t1 = textureLoad(gbuffer_ms1, px, i32(s));
        if t0.w != g0.w || dot(t1.xyz, g1.xyz) < 0.99 {
            edge = true;
        }
    }
    var out = lit_sample(g0, g1, g2, pos.xy);
    if edge {
        for (var s = 1u; s < n; s += 1u) {
            let o = lit_sample(
                textureLoad(gbuffer_ms0, px, i32(s)),
                textureLoad(gbuffer_ms1, px, i32(s)),
                textureLoad(gbuffer_ms2, px, i32(s)),
                pos.xy,
            );
            out.color += o.color;
            out.normal_depth += o.normal_depth;
            out.albedo_id = vec4<f32>(out.albedo_id.rgb + o.albedo_id.rgb, out.albedo_id.w);
        }
        let inv = 1.0 / f32(n);
        out.color *= inv;
        out.normal_depth *= inv;
        out.albedo_id = vec4<f32>(out.albedo_id.rgb * inv, out.albedo_id.w);
    }
    flush_counters(u32(pos.y));
    return out;
}

// ---- The shadow pass: depth from each light, one render pass per map layer ----
// The map layer (a light slot's, or one of its cascades) is the instance index: each draw is
// `draw(0..n, layer..layer + 1)`.

struct ShadowVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) shape: u32,
    @location(1) @interpolate(flat) layer: u32,
}

@vertex
fn vs_shadow_mesh(@location(0) position: vec3<f32>, @builtin(instance_index) layer: u32) -> @builtin(position) vec4<f32> {
    return shadow.layers[layer].view_proj * vec4<f32>(position, 1.0);
}

// Analytic proxies; the light's own shape collapses to a point outside the clip volume, so an
// emitter never shadows its own light (meshes are never lights here).
@vertex
fn vs_shadow_analytic(v: AnalyticVertexIn, @builtin(instance_index) layer: u32) -> ShadowVarying {
    let sl = shadow.layers[layer];
    var clip = sl.view_proj * vec4<f32>(v.position, 1.0);
    if v.shape == sl.own_shape {
        clip = vec4<f32>(0.0, 0.0, 2.0, 1.0);
    }
    return ShadowVarying(clip, v.shape, layer);
}

// The ray from the light through the texel centre, traced with the camera passes'
// `intersect_analytic`; the depth of its hit.
@fragment
fn fs_shadow_analytic(in: ShadowVarying) -> @builtin(frag_depth) f32 {
    let sl = shadow.layers[in.layer];
    let side = shadow.settings.map_side;
    let ndc = vec2<f32>(2.0 * in.clip.x / side - 1.0, 1.0 - 2.0 * in.clip.y / side);
    let ray = shadow_ray(sl, ndc);
    let t = intersect_analytic(shapes[in.shape], ray.o, ray.d, 0.0);
    if !(t > 0.0) {
        discard;
    }
    return shadow_project(sl, ray.o + ray.d * t).z;
}

// ---- The visibility AOV pass: V of every light slot at every G-buffer sample ----

// Target width, light slots per chunk, light slots in all, target pixels (visibility.rs).
struct AovInfo {
    dims: vec4<u32>,
}

@group(1) @binding(3) var<storage, read_write> visibility_out: array<f32>;
@group(1) @binding(4) var<uniform> aov: AovInfo;

struct ChunkVarying {
    @builtin(position) pos: vec4<f32>,
    @location(0) @interpolate(flat) chunk: u32,
}

// The full-screen triangle; the instance index is the chunk of light slots.
@vertex
fn vs_fullscreen_chunk(@builtin(vertex_index) i: u32, @builtin(instance_index) chunk: u32) -> ChunkVarying {
    return ChunkVarying(fullscreen_vertex(i), chunk);
}

// Writes slot j's value of this sample at visibility_out[(j − first)·pixels + pixel].
@fragment
fn fs_visibility(in: ChunkVarying) {
    let px = vec2<i32>(in.pos.xy);
    let g0 = textureLoad(gbuffer0, px, 0);
    let pixel = u32(px.y) * aov.dims.x + u32(px.x);
    let first = in.chunk * aov.dims.y;
    let last = min(first + aov.dims.y, aov.dims.z);
    var sp = SurfacePoint(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec2<f32>(0.0), 0u);
    if g0.w >= 0.5 {
        let g1 = textureLoad(gbuffer1, px, 0);
        let g2 = textureLoad(gbuffer2, px, 0);
        sp = SurfacePoint(g0.xyz, g2.xyz, g1.xyz, vec2<f32>(g1.w, g2.w), gbuffer_shape(g0.w));
    }
    for (var j = first; j < last; j++) {
        var v = 0.0;
        if g0.w >= 0.5 {
            v = light_slot_visibility(frame, sp, j, in.pos.xy);
        }
        visibility_out[(j - first) * aov.dims.w + pixel] = v;
    }
}
