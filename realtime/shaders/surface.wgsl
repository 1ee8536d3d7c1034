// surface.wgsl — the surface point a pixel sees: mesh interpolants, analytic shapes ray
// traced on their proxies, and tangent-space normal mapping.
//
// Technique: triangles are rasterised and their attributes interpolated perspective-correctly,
// which at a pixel centre gives the barycentrics of the camera ray's hit (the oracle's
// watertight ray/triangle test). Spheres, rectangles and disks are drawn as proxies (the
// sphere's bounding box, back faces; the rectangle itself; the disk's circumscribed
// parallelogram) and ray traced per fragment with the oracle's formulas, so silhouettes, depth
// and normals are exact rather than tessellated: Haines, Günther & Akenine-Möller 2019,
// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7) for spheres;
// the plane frame and dual basis of oracle/src/geometry/plane.rs for rectangles and disks.
// Normal maps: glTF 2.0 `normalTexture` (MikkTSpace tangent frame), as
// oracle/src/geometry/normal_map.rs.
// `intersect_analytic` is shared with the shadow pass, which traces rays from a light through
// its map's texels on the same proxies (passes.wgsl `fs_shadow_analytic`).
// Failure mode: proxies write `frag_depth`, which turns off early depth testing for them;
// a camera inside a sphere's bounding box but in front of the near plane is fine, one closer
// than the near plane (1e-4 × the scene radius) to a surface clips it.
// Inputs: interpolants from the vertex stage, `shapes` (via explicit arguments), the camera.

// Differential geometry at a hit before the shading frame (oracle geometry::Surface).
struct Differential {
    p: vec3<f32>,
    // Unit front-side geometric normal.
    ng: vec3<f32>,
    // Unit interpolated shading normal (ng when none).
    ns: vec3<f32>,
    uv: vec2<f32>,
    dpdu: vec3<f32>,
    dpdv: vec3<f32>,
    // Authored tangent (xyz) and handedness (w = ±1); w = 0: none.
    tangent: vec4<f32>,
}

// What shading needs of a surface point (the G-buffer holds exactly this).
struct SurfacePoint {
    p: vec3<f32>,
    ng: vec3<f32>,
    // Shading normal with the normal map applied, not flipped (the normal AOV).
    ns: vec3<f32>,
    uv: vec2<f32>,
    shape: u32,
}

// Interpolated mesh attributes at a fragment (oracle triangle.rs `interpolate_attributes`:
// the shading normal normalize(Σ bᵢnᵢ), ng where the triangle has no usable vertex normals,
// which the vertex data encodes by giving all three vertices ng).
fn mesh_differential(
    p: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
    tangent: vec4<f32>,
    ng: vec3<f32>,
    dpdu: vec3<f32>,
    dpdv: vec3<f32>,
    has_tangents: bool,
) -> Differential {
    let l2 = dot(normal, normal);
    let ns = select(ng, normal * inverseSqrt(l2), l2 > 0.0);
    var t = vec4<f32>(0.0);
    if has_tangents && dot(tangent.xyz, tangent.xyz) > 0.0 {
        t = vec4<f32>(tangent.xyz, select(1.0, -1.0, tangent.w < 0.0));
    }
    return Differential(p, ng, ns, uv, dpdu, dpdv, t);
}

// Nearest t > t_min (t_min ≥ 0) where the ray o + t·d meets the sphere, or −1 (Haines et
// al. 2019: the discriminant from the line's distance to the centre, roots without
// cancellation).
fn intersect_sphere(c: vec3<f32>, r: f32, o: vec3<f32>, d: vec3<f32>, t_min: f32) -> f32 {
    let f = o - c;
    let a = dot(d, d);
    let b = -dot(f, d);
    let l = f + d * (b / a);
    let r2 = r * r;
    let disc = r2 - dot(l, l);
    if !(disc >= 0.0) {
        return -1.0;
    }
    let cc = dot(f, f) - r2;
    let q = b + select(-1.0, 1.0, b >= 0.0) * sqrt(a * disc);
    if q == 0.0 {
        return -1.0;
    }
    let t0 = cc / q;
    let t1 = q / a;
    let near = min(t0, t1);
    let far = max(t0, t1);
    if near > t_min {
        return near;
    }
    if far > t_min {
        return far;
    }
    return -1.0;
}

// Sphere differential geometry at the hit o + t·d (oracle sphere.rs `surface`: re-projected
// point, Mitsuba's uv in world axes, ∂p/∂u = 2πr(−d.y, d.x, 0), ∂p/∂v = πr(cosθcosφ, cosθsinφ, −sinθ)).
fn sphere_differential(s: Shape, o: vec3<f32>, d: vec3<f32>, t: f32) -> Differential {
    let c = s.center.xyz;
    let r = s.center.w;
    let v = o + d * t - c;
    let l2 = dot(v, v);
    let dir = select(-d, v * inverseSqrt(l2), l2 > 0.0);
    let p = c + dir * r;
    var phi = atan2(dir.y, dir.x);
    if phi < 0.0 {
        phi += TAU;
    }
    let cos_theta = clamp(dir.z, -1.0, 1.0);
    let theta = acos(cos_theta);
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    let dpdu = vec3<f32>(-dir.y, dir.x, 0.0) * (TAU * r);
    let dpdv = vec3<f32>(cos_theta * cos(phi), cos_theta * sin(phi), -sin_theta) * (PI * r);
    return Differential(p, dir, dir, vec2<f32>(phi / TAU, theta / PI), dpdu, dpdv, vec4<f32>(0.0));
}

// Ray parameter of the hit with the plane of a rectangle or disk (oracle plane.rs `hit`).
fn intersect_plane(s: Shape, o: vec3<f32>, d: vec3<f32>) -> f32 {
    return dot(s.center.xyz - o, s.normal.xyz) / dot(d, s.normal.xyz);
}

// Local (s, t) of a point of the plane by the dual basis.
fn plane_local(s: Shape, p: vec3<f32>) -> vec2<f32> {
    let r = p - s.center.xyz;
    return vec2<f32>(dot(r, s.dual_u.xyz), dot(r, s.dual_v.xyz));
}

// Rectangle differential geometry (oracle rectangle.rs: (s, t) clamped to [−1, 1]²,
// uv = ((s + 1)/2, (t + 1)/2), ∂p/∂u = 2h_u, ∂p/∂v = 2h_v).
fn rectangle_differential(s: Shape, q: vec3<f32>) -> Differential {
    let st = clamp(plane_local(s, q), vec2<f32>(-1.0), vec2<f32>(1.0));
    let p = s.center.xyz + s.half_u.xyz * st.x + s.half_v.xyz * st.y;
    let n = s.normal.xyz;
    return Differential(p, n, n, (st + 1.0) * 0.5, s.half_u.xyz * 2.0, s.half_v.xyz * 2.0, vec4<f32>(0.0));
}

// Disk differential geometry (oracle disk.rs: uv = (r, φ/2π), ∂p/∂u radial, ∂p/∂v azimuthal).
fn disk_differential(s: Shape, q: vec3<f32>) -> Differential {
    var xy = plane_local(s, q);
    var r = length(xy);
    if r > 1.0 {
        xy /= r;
        r = 1.0;
    }
    var cs = vec2<f32>(1.0, 0.0);
    if r > 0.0 {
        cs = xy / r;
    }
    var phi = atan2(xy.y, xy.x);
    if phi < 0.0 {
        phi += TAU;
    }
    let p = s.center.xyz + s.half_u.xyz * xy.x + s.half_v.xyz * xy.y;
    let n = s.normal.xyz;
    let dpdu = s.half_u.xyz * cs.x + s.half_v.xyz * cs.y;
    let dpdv = s.half_v.xyz * cs.x - s.half_u.xyz * cs.y;
    return Differential(p, n, n, vec2<f32>(r, phi / TAU), dpdu, dpdv, vec4<f32>(0.0));
}

// Unit `v` made orthogonal to unit `n` (Gram–Schmidt), or an arbitrary tangent of `n`.
fn orthogonal_tangent(v: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let t = v - n * dot(n, v);
    let l2 = dot(t, t);
    if l2 > 0.0 && l2 < 1e30 {
        return t * inverseSqrt(l2);
    }
    return basis_t(n);
}

// Shading normal at `d` with the shape's normal map applied (oracle normal_map.rs `shading`):
// T = authored tangent or ∂p/∂u, Gram–Schmidt against N; B = w·(N × T) with w the authored
// handedness or −1 when (N × ∂p/∂u)·∂p/∂v > 0; n_ts = 2c − 1, xy × scale, renormalised;
// n = normalize(T·n_ts.x + B·n_ts.y + N·n_ts.z).
fn shading_normal(d: Differential, map: u32, scale: f32) -> vec3<f32> {
    let n = d.ns;
    if map == NONE {
        return n;
    }
    var t = d.dpdu;
    var w = select(1.0, -1.0, dot(cross(n, d.dpdu), d.dpdv) > 0.0);
    if d.tangent.w != 0.0 {
        t = d.tangent.xyz;
        w = d.tangent.w;
    }
    t = orthogonal_tangent(t, n);
    let b = cross(n, t) * w;
    var n_ts = texture_filtered(map, d.uv).xyz * 2.0 - 1.0;
    n_ts = vec3<f32>(n_ts.xy * scale, n_ts.z);
    let l2 = dot(n_ts, n_ts);
    if !(l2 > 0.0) {
        return n;
    }
    normal_map_length = sqrt(l2);
    n_ts *= inverseSqrt(l2);
    let m = t * n_ts.x + b * n_ts.y + n * n_ts.z;
    let m2 = dot(m, m);
    if !(m2 > 0.0) {
        return n;
    }
    return m * inverseSqrt(m2);
}

fn surface_point(d: Differential, s: Shape, shape: u32) -> SurfacePoint {
    return SurfacePoint(d.p, d.ng, shading_normal(d, s.normal_map, s.normal_scale), d.uv, shape);
}

// A fragment's surface point: of an analytic proxy, the camera ray through `frag` (target pixel
// coordinates) traced against shape `s` (index `shape`); of either kind, after surface detail
// (detail/common.wgsl). `hit` is false where the ray misses (the fragment is discarded).
// Analytic hits are taken beyond ray parameter t_min (unit camera rays: a distance).
struct AnalyticHit {
    hit: bool,
    surface: SurfacePoint,
}

// Ray parameter t > t_min (0, or a depth-peeled layer's distance: passes.wgsl
// `peel_distance`) of the nearest hit of the ray o + t·d with analytic shape `s`, or −1
// where it misses: the one intersection routine of the camera passes and the shadow pass.
// Rectangles take their coverage from the rasteriser (the proxy is the rectangle itself);
// disks test the dual-basis radius, spheres the Haines et al. quadratic.
fn intersect_analytic(s: Shape, o: vec3<f32>, d: vec3<f32>, t_min: f32) -> f32 {
    switch s.kind {
        case SHAPE_SPHERE: {
            let t = intersect_sphere(s.center.xyz, s.center.w, o, d, t_min);
            if !(t > 0.0) {
                return -1.0;
            }
            return t;
        }
        case SHAPE_RECTANGLE: {
            let t = intersect_plane(s, o, d);
            if !(t > t_min && t < 1e30) {
                return -1.0;
            }
            return t;
        }
        case SHAPE_DISK: {
            let t = intersect_plane(s, o, d);
            if !(t > t_min && t < 1e30) {
                return -1.0;
            }
            let st = plane_local(s, o + d * t);
            if dot(st, st) > 1.0 {
                return -1.0;
            }
            return t;
        }
        default: {
            return -1.0;
        }
    }
}

// Differential geometry of analytic shape `s` at the hit o + t·d that `intersect_analytic` found.
fn analytic_differential(s: Shape, o: vec3<f32>, d: vec3<f32>, t: f32) -> Differential {
    if s.kind == SHAPE_SPHERE {
        return sphere_differential(s, o, d, t);
    }
    if s.kind == SHAPE_DISK {
        return disk_differential(s, o + d * t);
    }
    return rectangle_differential(s, o + d * t);
}

fn trace_analytic(f: FrameUniforms, s: Shape, shape: u32, frag: vec2<f32>, t_min: f32) -> AnalyticHit {
    let xy = film_position(f, frag);
    let o = f.cam_pos.xyz;
    let d = camera_ray_direction(f, xy.x, xy.y);
    let t = intersect_analytic(s, o, d, t_min);
    if !(t > 0.0) {
        return AnalyticHit(false, SurfacePoint(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec2<f32>(0.0), 0u));
    }
    return detailed_surface(f, analytic_differential(s, o, d, t), s, shape);
}

// Depth-buffer value of world point p (reversed-Z, infinite far plane).
fn depth_of(f: FrameUniforms, p: vec3<f32>) -> f32 {
    let clip = f.view_proj * vec4<f32>(p, 1.0);
    return clip.z / clip.w;
}

// Camera-space distance along the view axis (the depth AOV, as the oracle's film).
fn view_depth(f: FrameUniforms, p: vec3<f32>) -> f32 {
    return dot(p - f.cam_pos.xyz, f.cam_forward.xyz);
}
