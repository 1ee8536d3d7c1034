// envmap/filter.wgsl — building the environment maps of the environment-mapping methods from
// the six captured views: the radiance cube and its box mips, the prefiltered specular levels
// (GGX or normalized Phong), the cosine-convolved irradiance cube, the 9 spherical-harmonic
// irradiance coefficients, the warps into a sphere map and a dual-paraboloid map, and the
// split-sum BRDF table; level 0's alpha is each texel's distance from the capture point (the
// distance impostors), and a refractor's map holds normals and distances. Compute entry
// points; appended to the main module (it reuses the BSDF and frame helpers), with its own
// bindings at group 0, bindings 10–17.
//
// Cube faces follow the Vulkan/WebGPU cube-map convention (Vulkan spec, "Cube Map Face
// Selection"): layer f = +X, −X, +Y, −Y, +Z, −Z, texel (s, t) of face f looks along
// `cube_direction`. The captured views come from right-handed cameras, so each is copied with
// its columns mirrored (realtime/src/technique/envmap/build.rs, "Capture").
//
// Technique:
// - GGX prefiltering: Karis 2013, "Real Shading in Unreal Engine 4" (SIGGRAPH course notes),
//   `PrefilterEnvMap`: N = V = R, GGX-importance-sampled half vectors, radiance weighted by
//   n·l. Phong prefiltering: the lobe (n+1)/(2π)·cosⁿα about R sampled exactly (Heidrich &
//   Seidel 1999, "Realistic, Hardware-accelerated Shading and Lighting", §4: the prefiltered
//   map is the environment convolved with the lobe, without the cosine). Both sample mip
//   levels by the sample's solid angle (filtered importance sampling, Křivánek & Colbert
//   2008, "Real-time Shading with Filtered Importance Sampling", EGSR, eq. 13), with
//   Hammersley points (Wong, Luk & Heng 1997).
// - Irradiance: E(n) = Σ L·max(0, n·ω)·ΔΩ over every texel of a coarse level; ΔΩ the exact
//   solid angle of a cube texel, from ∫∫ du dv/(1 + u² + v²)^{3/2} whose antiderivative is
//   atan(uv/√(1 + u² + v²)).
// - SH9: L_lm = Σ L·Y_lm(ω)·ΔΩ, stored times Â_0 = π, Â_1 = 2π/3, Â_2 = π/4, so that
//   E(n) = Σ L_lm·Y_lm(n) (Ramamoorthi & Hanrahan 2001, "An Efficient Representation for
//   Irradiance Environment Maps", SIGGRAPH, eqs. 3, 8, 12).
// - Sphere map: the image of a mirror ball seen from the map's view direction z, texel
//   (x, y) ∈ unit disk ↔ normal (x, y, √(1 − x² − y²)) ↔ R = 2(n·z)n − z (Miller & Hoffman
//   1984, "Illumination and Reflection Maps", SIGGRAPH course notes; OpenGL 2.1 §2.11.4).
// - Dual paraboloid: Heidrich & Seidel 1998, "View-independent Environment Maps" (Graphics
//   Hardware), (x, y) = (R_x, R_y)/(1 ± R_z), one map per hemisphere of the map frame's z.
// - BRDF table: Karis 2013 `IntegrateBRDF`: A = ∫(1 − F_c)·G_vis, B = ∫F_c·G_vis over GGX
//   samples, F_c = (1 − v·h)⁵, with this project's Smith G2 (bsdf.wgsl), one layer per
//   masking function.
// Failure mode: box mips ignore the solid-angle variation across a face (texels near face
// corners are ~5× smaller than at the centre); filtered importance sampling trades noise for
// blur; the sphere map's rim holds the single direction −z (its singularity); outside the
// paraboloid's unit disk the texels are the other hemisphere's directions (`seam` fill) or
// black (`seam` none, the unhandled seam).

// What one dispatch does (envmap/build.rs `FilterParams`).
struct FilterParams {
    // Output side, output level's roughness r (lobe width), source side at level 0, mode.
    size: u32,
    roughness: f32,
    source_size: u32,
    mode: u32,
    // Samples per texel, the source level read, output layer count, flag (seam fill).
    samples: u32,
    source_level: u32,
    layers: u32,
    flag: u32,
    // The map frame (sphere map: z towards the viewer; paraboloid: z the axis).
    frame_x: vec4<f32>,
    frame_y: vec4<f32>,
    frame_z: vec4<f32>,
}

// FilterParams.mode values.
const FILTER_GGX: u32 = 0u;
const FILTER_PHONG: u32 = 1u;
const WARP_SPHERE: u32 = 0u;
const WARP_PARABOLOID: u32 = 1u;

@group(0) @binding(10) var filter_src_2d: texture_2d<f32>;
@group(0) @binding(11) var filter_src_array: texture_2d_array<f32>;
@group(0) @binding(12) var filter_src_cube: texture_cube<f32>;
@group(0) @binding(13) var filter_sampler: sampler;
@group(0) @binding(14) var filter_dst: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(15) var<uniform> filter_params: FilterParams;
@group(0) @binding(16) var<storage, read_write> filter_sh: array<vec4<f32>, 9>;
// The captured view's normal + view depth (cs_face_copy).
@group(0) @binding(17) var filter_src_depth: texture_2d<f32>;

// The direction through face `face` at (a, b) ∈ [−1, 1]², a along s and b along t.
fn cube_direction(face: u32, a: f32, b: f32) -> vec3<f32> {
    switch face {
        case 0u: { return vec3<f32>(1.0, -b, -a); }
        case 1u: { return vec3<f32>(-1.0, -b, a); }
        case 2u: { return vec3<f32>(a, 1.0, b); }
        case 3u: { return vec3<f32>(a, -1.0, -b); }
        case 4u: { return vec3<f32>(a, -b, 1.0); }
        default: { return vec3<f32>(-a, -b, -1.0); }
    }
}

// Unit direction through the centre of texel (x, y) of face `face` of a side-`size` face.
fn texel_direction(face: u32, x: u32, y: u32, size: u32) -> vec3<f32> {
    let a = 2.0 * (f32(x) + 0.5) / f32(size) - 1.0;
    let b = 2.0 * (f32(y) + 0.5) / f32(size) - 1.0;
    return normalize(cube_direction(face, a, b));
}

fn solid_angle_corner(x: f32, y: f32) -> f32 {
    return atan2(x * y, sqrt(x * x + y * y + 1.0));
}

// Exact solid angle of texel (x, y) of a side-`size` face.
fn texel_solid_angle(x: u32, y: u32, size: u32) -> f32 {
    let inv = 2.0 / f32(size);
    let x0 = f32(x) * inv - 1.0;
    let y0 = f32(y) * inv - 1.0;
    let x1 = x0 + inv;
    let y1 = y0 + inv;
    return solid_angle_corner(x0, y0) - solid_angle_corner(x0, y1) - solid_angle_corner(x1, y0)
        + solid_angle_corner(x1, y1);
}

// Point i of n of the Hammersley set: (i/n, radical inverse of i in base 2).
fn hammersley(i: u32, n: u32) -> vec2<f32> {
    return vec2<f32>(f32(i) / f32(n), f32(reverseBits(i)) * 2.3283064365386963e-10);
}

// The distance stored for what the capture point does not see (the background): the largest
// f16, "infinitely far" to the distance impostors.
const BACKGROUND_DISTANCE: f32 = 65504.0;
// FilterParams.mode of cs_face_copy.
const COPY_RADIANCE: u32 = 0u;
const COPY_NORMAL: u32 = 1u;

// Capture: copy a rendered view into its cube face, columns mirrored. Alpha: the distance from
// the capture point, view depth × |(a, b, 1)| at the texel's (a, b) ∈ [−1, 1]² (a 90° view's
// ray through (a, b) is (a, b, 1) in camera space), BACKGROUND_DISTANCE where nothing was
// drawn. Rgb: the radiance (COPY_RADIANCE) or the shading normal (COPY_NORMAL, a refractor's map).
@compute @workgroup_size(8, 8)
fn cs_face_copy(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = filter_params.size;
    if id.x >= n || id.y >= n {
        return;
    }
    let src = vec2<i32>(i32(n - 1u - id.x), i32(id.y));
    let c = textureLoad(filter_src_2d, src, 0);
    let nd = textureLoad(filter_src_depth, src, 0);
    let a = 2.0 * (f32(id.x) + 0.5) / f32(n) - 1.0;
    let b = 2.0 * (f32(id.y) + 0.5) / f32(n) - 1.0;
    let distance = select(BACKGROUND_DISTANCE, nd.w * sqrt(1.0 + a * a + b * b), nd.w > 0.0);
    let rgb = select(c.xyz, nd.xyz, filter_params.mode == COPY_NORMAL);
    textureStore(filter_dst, vec2<i32>(id.xy), 0, vec4<f32>(rgb, distance));
}

// A sphere refractor's map, from its centre: normal = the texel's direction, distance = the
// radius (FilterParams.roughness).
@compute @workgroup_size(8, 8)
fn cs_refractor_sphere(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = filter_params.size;
    if id.x >= n || id.y >= n || id.z >= 6u {
        return;
    }
    let d = texel_direction(id.z, id.x, id.y, n);
    textureStore(filter_dst, vec2<i32>(id.xy), i32(id.z), vec4<f32>(d, filter_params.roughness));
}

// Box mips: level k + 1 as the mean of 2×2 texels of level k, face by face (alpha 1: only
// level 0 keeps the distances).
@compute @workgroup_size(8, 8)
fn cs_downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = filter_params.size;
    if id.x >= n || id.y >= n || id.z >= filter_params.layers {
        return;
    }
    let p = vec2<i32>(id.xy) * 2;
    let l = i32(id.z);
    let lv = i32(filter_params.source_level);
    let c = textureLoad(filter_src_array, p, l, lv) + textureLoad(filter_src_array, p + vec2<i32>(1, 0), l, lv)
        + textureLoad(filter_src_array, p + vec2<i32>(0, 1), l, lv) + textureLoad(filter_src_array, p + vec2<i32>(1, 1), l, lv);
    textureStore(filter_dst, vec2<i32>(id.xy), l, vec4<f32>(c.xyz * 0.25, 1.0));
}

// The mip level of the radiance cube whose texels subtend the solid angle 1/(N·pdf) of one
// of N samples (Křivánek & Colbert 2008, eq. 13, with their +1 bias omitted).
fn sample_level(pdf: f32, samples: u32, source_size: u32) -> f32 {
    let omega_s = 1.0 / (f32(samples) * max(pdf, 1e-8));
    let omega_p = 4.0 * PI / (6.0 * f32(source_size * source_size));
    return max(0.5 * log2(omega_s / omega_p), 0.0);
}

// Prefiltered specular: one level of the GGX (Karis 2013) or normalized-Phong lobe about
// each texel's direction R, sampled from the radiance cube's mips.
@compute @workgroup_size(8, 8)
fn cs_prefilter(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = filter_params;
    if id.x >= p.size || id.y >= p.size || id.z >= 6u {
        return;
    }
    let r = texel_direction(id.z, id.x, id.y, p.size);
    if p.roughness <= 0.0 {
        let c = textureSampleLevel(filter_src_cube, filter_sampler, r, 0.0);
        textureStore(filter_dst, vec2<i32>(id.xy), i32(id.z), vec4<f32>(c.xyz, 1.0));
        return;
    }
    let alpha = ggx_alpha(p.roughness);
    // Phong exponent of the same width: n = 2/α² − 2 (Walter et al. 2007 §5.2).
    let exponent = max(2.0 / (alpha * alpha) - 2.0, 0.0);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < p.samples; i++) {
        let xi = hammersley(i, p.samples);
        let phi = TAU * xi.y;
        if p.mode == FILTER_PHONG {
            // cos α = ξ^(1/(n+1)): pdf = (n+1)/(2π)·cosⁿα, the lobe itself (weights 1).
            let cos_a = pow(max(xi.x, 1e-12), 1.0 / (exponent + 1.0));
            let sin_a = sqrt(max(1.0 - cos_a * cos_a, 0.0));
            let l = to_world(r, vec3<f32>(sin_a * cos(phi), sin_a * sin(phi), cos_a));
            let pdf = (exponent + 1.0) * 0.5 * INV_PI * pow(cos_a, exponent);
            let lod = sample_level(pdf, p.samples, p.source_size);
            sum += textureSampleLevel(filter_src_cube, filter_sampler, l, lod).xyz;
            weight += 1.0;
        } else {
            // GGX half vector: cos²θh = (1 − ξ)/(1 + (α² − 1)ξ) (Walter et al. 2007, eq. 35).
            let a2 = alpha * alpha;
            let cos_h = sqrt((1.0 - xi.x) / (1.0 + (a2 - 1.0) * xi.x));
            let sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
            let h = to_world(r, vec3<f32>(sin_h * cos(phi), sin_h * sin(phi), cos_h));
            let l = 2.0 * dot(r, h) * h - r;
            let n_l = dot(r, l);
            if n_l > 0.0 {
                // pdf(l) = D(h)·(n·h)/(4 v·h) with v = n: D/4.
                let pdf = ggx_d(alpha, cos_h, sin_h * sin_h) * 0.25;
                let lod = sample_level(pdf, p.samples, p.source_size);
                sum += textureSampleLevel(filter_src_cube, filter_sampler, l, lod).xyz * n_l;
                weight += n_l;
            }
        }
    }
    textureStore(filter_dst, vec2<i32>(id.xy), i32(id.z), vec4<f32>(sum / max(weight, 1e-12), 1.0));
}

// Cosine-convolved irradiance E(n) from every texel of one radiance level.
@compute @workgroup_size(8, 8)
fn cs_irradiance(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = filter_params;
    if id.x >= p.size || id.y >= p.size || id.z >= 6u {
        return;
    }
    let n = texel_direction(id.z, id.x, id.y, p.size);
    let m = p.source_size;
    let lv = i32(p.source_level);
    var e = vec3<f32>(0.0);
    for (var face = 0u; face < 6u; face++) {
        for (var y = 0u; y < m; y++) {
            for (var x = 0u; x < m; x++) {
                let w = dot(n, texel_direction(face, x, y, m));
                if w > 0.0 {
                    let l = textureLoad(filter_src_array, vec2<i32>(i32(x), i32(y)), i32(face), lv).xyz;
                    e += l * (w * texel_solid_angle(x, y, m));
                }
            }
        }
    }
    textureStore(filter_dst, vec2<i32>(id.xy), i32(id.z), vec4<f32>(e, 1.0));
}

const SH_THREADS: u32 = 64u;
var<workgroup> sh_partial: array<array<vec3<f32>, 9>, 64>;

// SH9 irradiance coefficients of one radiance level (basis: envmap/envmap.wgsl sh9_basis): one workgroup, a strided sum per thread,
// then thread 0 adds the partial sums and applies the cosine lobe's Â_l.
@compute @workgroup_size(64)
fn cs_sh9(@builtin(local_invocation_index) t: u32) {
    let m = filter_params.source_size;
    let lv = i32(filter_params.source_level);
    var c: array<vec3<f32>, 9>;
    for (var k = 0u; k < 9u; k++) {
        c[k] = vec3<f32>(0.0);
    }
    for (var i = t; i < 6u * m * m; i += SH_THREADS) {
        let face = i / (m * m);
        let x = i % m;
        let y = (i / m) % m;
        let d = texel_direction(face, x, y, m);
        let l = textureLoad(filter_src_array, vec2<i32>(i32(x), i32(y)), i32(face), lv).xyz
            * texel_solid_angle(x, y, m);
        let y_lm = sh9_basis(d);
        for (var k = 0u; k < 9u; k++) {
            c[k] += l * y_lm[k];
        }
    }
    sh_partial[t] = c;
    workgroupBarrier();
    if t == 0u {
        let band = array<f32, 9>(PI, 2.0 * PI / 3.0, 2.0 * PI / 3.0, 2.0 * PI / 3.0, PI / 4.0, PI / 4.0, PI / 4.0, PI / 4.0, PI / 4.0);
        for (var k = 0u; k < 9u; k++) {
            var s = vec3<f32>(0.0);
            for (var j = 0u; j < SH_THREADS; j++) {
                s += sh_partial[j][k];
            }
            filter_sh[k] = vec4<f32>(s * band[k], 0.0);
        }
    }
}

// Warps one prefiltered cube level into the same level of a sphere map (one layer) or a dual
// paraboloid map (layer 0: the +z hemisphere of the frame, layer 1: −z).
@compute @workgroup_size(8, 8)
fn cs_warp(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = filter_params;
    if id.x >= p.size || id.y >= p.size || id.z >= p.layers {
        return;
    }
    let x = 2.0 * (f32(id.x) + 0.5) / f32(p.size) - 1.0;
    let y = 1.0 - 2.0 * (f32(id.y) + 0.5) / f32(p.size);
    var rm: vec3<f32>;
    if p.mode == WARP_SPHERE {
        // Outside the disk: the rim's direction, −z.
        let q = vec2<f32>(x, y) / max(length(vec2<f32>(x, y)), 1.0);
        let nz = sqrt(max(1.0 - dot(q, q), 0.0));
        rm = vec3<f32>(2.0 * nz * q.x, 2.0 * nz * q.y, 2.0 * nz * nz - 1.0);
    } else {
        let r2 = x * x + y * y;
        if r2 > 1.0 && p.flag == 0u {
            textureStore(filter_dst, vec2<i32>(id.xy), i32(id.z), vec4<f32>(0.0, 0.0, 0.0, 1.0));
            return;
        }
        let side = select(1.0, -1.0, id.z == 1u);
        rm = vec3<f32>(2.0 * x, 2.0 * y, side * (1.0 - r2)) / (1.0 + r2);
    }
    let r = p.frame_x.xyz * rm.x + p.frame_y.xyz * rm.y + p.frame_z.xyz * rm.z;
    let c = textureSampleLevel(filter_src_cube, filter_sampler, r, f32(p.source_level));
    textureStore(filter_dst, vec2<i32>(id.xy), i32(id.z), vec4<f32>(c.xyz, 1.0));
}

// The split-sum BRDF table (Karis 2013): texel (i, j) at cos θo = (i + ½)/size, roughness
// (j + ½)/size; layer 0 height-correlated Smith, layer 1 separable; (A, B) in (x, y).
@compute @workgroup_size(8, 8)
fn cs_brdf_lut(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = filter_params;
    if id.x >= p.size || id.y >= p.size || id.z >= 2u {
        return;
    }
    let cos_o = (f32(id.x) + 0.5) / f32(p.size);
    let alpha = ggx_alpha((f32(id.y) + 0.5) / f32(p.size));
    let n = vec3<f32>(0.0, 0.0, 1.0);
    let wo = vec3<f32>(sqrt(1.0 - cos_o * cos_o), 0.0, cos_o);
    var ab = vec2<f32>(0.0);
    for (var i = 0u; i < p.samples; i++) {
        let xi = hammersley(i, p.samples);
        let a2 = alpha * alpha;
        let cos_h = sqrt((1.0 - xi.x) / (1.0 + (a2 - 1.0) * xi.x));
        let sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
        let phi = TAU * xi.y;
        let h = vec3<f32>(sin_h * cos(phi), sin_h * sin(phi), cos_h);
        let v_h = dot(wo, h);
        let wi = 2.0 * v_h * h - wo;
        if wi.z > 0.0 && v_h > 0.0 {
            // f·cos/pdf with pdf = D·(n·h)/(4 v·h): G2·(v·h)/((n·h)(n·v)).
            let g_vis = smith_g2(alpha, id.z, n, wo, wi) * v_h / (cos_h * cos_o);
            let fc = schlick_weight(v_h);
            ab += vec2<f32>((1.0 - fc) * g_vis, fc * g_vis);
        }
    }
    textureStore(filter_dst, vec2<i32>(id.xy), i32(id.z), vec4<f32>(ab / f32(p.samples), 0.0, 1.0));
}
