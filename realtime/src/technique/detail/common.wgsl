// detail/common.wgsl — what every surface-detail technique shares: the frame of a displaced
// surface at a base point, heights in metres, the displaced normal, and the dispatcher.
//
// Technique: a shape displaced by p' = p + w(u, v)·n, w = k·s·h (scenes/src/displacement.rs;
// k the method's `height_scale`) is drawn as its base surface. At a fragment the base point p,
// its uv, the unit normal n and ∂p/∂u, ∂p/∂v form a frame in which a world direction
// d = a·∂p/∂u + b·∂p/∂v + c·n (Cramer's rule) moves uv by (a, b) and the height by c, so along
// the camera ray through p the point at height w has uv(w) = uv + w·(a, b)/c: exact over a
// planar base (a rectangle; one triangle of a mesh), which every technique assumes. The
// technique (detail/normal.wgsl, detail/parallax.wgsl, detail/ray_march.wgsl,
// detail/cone_step.wgsl) returns the uv' and height w' it believes the ray meets; the surface
// point is p + ∂p/∂u·Δu + ∂p/∂v·Δv + w'·n, shaded with the displaced surface's normal at uv',
// N' ∝ (∂p/∂u + w_u·n) × (∂p/∂v + w_v·n) (Blinn 1978, "Simulation of Wrinkled Surfaces",
// SIGGRAPH, §3; the curvature terms w·∂n/∂u vanish on a planar base), which is also its
// geometric normal: the displaced surface has no separate shading normal.
// Failure mode: nothing outside the base polygon is drawn, so the displaced silhouette is
// missing; on a heightfield patch (rectangle) a uv' outside [0, 1]² is discarded (the patch
// ends there; on meshes uv' is kept whatever it is); a base seen from behind is drawn flat;
// the shadow maps see the flat base. Authored normal maps are replaced by the detail normal.
// Inputs: a Differential from surface.wgsl, the shape's `detail` fields (upload.rs), the
// family's block of the frame uniform (`frame.families.detail`).

// The pipeline's surface-detail method: DETAIL_FLAT (0), DETAIL_NORMAL_MAPPING, …,
// DETAIL_CONE_STEP, generated from the method tables (technique/mod.rs `wgsl_codes`).
override DETAIL_METHOD: u32 = 0u;

// The family's block of the frame uniform (DetailUniforms in detail/mod.rs).
struct DetailUniforms {
    // k in w = k·s·h.
    height_scale: f32,
    // Parallax mapping's bias, in units of the height range.
    parallax_bias: f32,
    // Bump mapping's finite-difference step, texels.
    bump_delta: f32,
    // Azimuths of the horizon map (0: none).
    horizon_azimuths: u32,
    // Linear steps (POM: at normal incidence; cone stepping: its cone steps).
    steps: u32,
    // POM's steps at grazing incidence (the others: `steps`).
    max_steps: u32,
    // Halvings of the binary search (cone stepping: relaxed cones when > 0).
    binary_steps: u32,
    // POM's self-shadow samples (0: no self-shadowing).
    shadow_steps: u32,
}

// The displaced surface around one base point.
struct DetailFrame {
    p: vec3<f32>,
    uv: vec2<f32>,
    // Unit displacement direction.
    n: vec3<f32>,
    dpdu: vec3<f32>,
    dpdv: vec3<f32>,
    // Height texture and its channel.
    tex: u32,
    channel: u32,
    // k·s: metres per unit of h.
    scale: f32,
    // Range of w over the texels, metres.
    lo: f32,
    hi: f32,
}

// What a technique found: uv' and the height w' it takes the ray to meet there; keep = false
// discards the fragment.
struct DetailHit {
    keep: bool,
    uv: vec2<f32>,
    w: f32,
}

fn detail_frame(f: FrameUniforms, d: Differential, s: Shape) -> DetailFrame {
    let k = f.families.detail.height_scale;
    let a = s.detail_range.y * k;
    let b = s.detail_range.z * k;
    return DetailFrame(d.p, d.uv, d.ns, d.dpdu, d.dpdv, s.detail.x, s.detail.y, s.detail_range.x * k, min(a, b), max(a, b));
}

// (a, b, c) with v = a·∂p/∂u + b·∂p/∂v + c·n.
fn frame_coords(fr: DetailFrame, v: vec3<f32>) -> vec3<f32> {
    let det = dot(fr.dpdu, cross(fr.dpdv, fr.n));
    if det == 0.0 {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(
        dot(v, cross(fr.dpdv, fr.n)),
        dot(v, cross(fr.n, fr.dpdu)),
        dot(v, cross(fr.dpdu, fr.dpdv)),
    ) / det;
}

// w = k·s·h at uv (one bilinear lookup: 4 fetches).
fn detail_height(fr: DetailFrame, uv: vec2<f32>) -> f32 {
    return texture_sample(fr.tex, uv)[fr.channel] * fr.scale;
}

// Unit normal of the displaced surface from the height gradient (w_u, w_v) (Blinn 1978 §3).
fn displaced_normal(fr: DetailFrame, grad: vec2<f32>) -> vec3<f32> {
    var m = cross(fr.dpdu + fr.n * grad.x, fr.dpdv + fr.n * grad.y);
    if dot(m, fr.n) < 0.0 {
        m = -m;
    }
    let l2 = dot(m, m);
    if !(l2 > 0.0 && l2 < 1e30) {
        return fr.n;
    }
    return m * inverseSqrt(l2);
}

// The surface point a fragment of shape `s` (index `shape`) with base differential `d` shows
// under the pipeline's DETAIL_METHOD; `hit` false: discard. Shapes without displacement, and
// every shape under DETAIL_FLAT, keep their base surface.
fn detailed_surface(f: FrameUniforms, d: Differential, s: Shape, shape: u32) -> AnalyticHit {
    // The texture filters' footprint from ray differentials at the base surface (analytic
    // derivatives only; texture/filter.wgsl).
    set_analytic_footprint(f, d.p, d.ng, d.dpdu, d.dpdv);
    if DETAIL_METHOD == DETAIL_FLAT || s.detail.x == NONE {
        return AnalyticHit(true, surface_point(d, s, shape));
    }
    let fr = detail_frame(f, d, s);
    // The camera ray's direction at the base point (pinhole: from the eye through p).
    let dir = normalize(d.p - f.cam_pos.xyz);
    let v = frame_coords(fr, dir);
    if !(v.z < 0.0) {
        return AnalyticHit(true, surface_point(d, s, shape));
    }
    let duv_dw = v.xy / v.z;
    let cos_theta = clamp(-dot(dir, fr.n), 0.0, 1.0);
    var hit = DetailHit(true, fr.uv, 0.0);
    switch DETAIL_METHOD {
        case DETAIL_PARALLAX: {
            hit = parallax_offset(f, fr, duv_dw, 1.0);
        }
        case DETAIL_PARALLAX_OFFSET_LIMITED: {
            hit = parallax_offset(f, fr, duv_dw, cos_theta);
        }
        case DETAIL_STEEP_PARALLAX, DETAIL_RELIEF_MAPPING, DETAIL_POM: {
            hit = ray_march(f, fr, duv_dw, cos_theta);
        }
        case DETAIL_CONE_STEP: {
            hit = cone_step(f, fr, s, duv_dw);
        }
        default: {}
    }
    let outside = any(hit.uv < vec2<f32>(0.0)) || any(hit.uv > vec2<f32>(1.0));
    if !hit.keep || (s.kind == SHAPE_RECTANGLE && outside) {
        return AnalyticHit(false, SurfacePoint(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec2<f32>(0.0), 0u));
    }
    var grad: vec2<f32>;
    if DETAIL_METHOD == DETAIL_BUMP_MAPPING {
        grad = bump_gradient(f, fr, hit.uv);
    } else {
        grad = normal_map_gradient(fr, s, hit.uv);
    }
    let n = displaced_normal(fr, grad);
    let delta = hit.uv - fr.uv;
    let p = fr.p + fr.dpdu * delta.x + fr.dpdv * delta.y + fr.n * hit.w;
    return AnalyticHit(true, SurfacePoint(p, n, n, hit.uv, shape));
}
