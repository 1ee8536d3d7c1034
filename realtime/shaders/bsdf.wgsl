// bsdf.wgsl — the BSDFs of docs/ARCHITECTURE.md "BSDFs", the same closed forms as oracle/src/bsdf/*.rs.
//
// Technique: direct evaluation of f(ωo, ωi)·|cos θi| in world space (every reflector here is
// isotropic, so only angles to the normal and between directions matter):
// - Lambert: ρ|cos θi|/π (Lambert 1760).
// - Normalized Phong lobe: ks·(n + 2)/(2π)·cosⁿα·|cos θi|, α the angle between ωi and the mirror
//   direction of ωo (Lafortune & Willems 1994, "Using the modified Phong reflectance model for
//   physically based rendering", KU Leuven CW197).
// - GGX: k·F(ωi·h)·D(h)·G2/(4|cos θo|), Schlick F = f0 + (1 − f0)(1 − cos θd)⁵ (Schlick 1994,
//   CGF 13(3)) or a conductor's exact F (`conductor_fresnel`); D and Λ of Walter, Marschner, Li & Torrance 2007, "Microfacet Models for
//   Refraction through Rough Surfaces" (EGSR), eqs. 33–34; G2 height-correlated
//   1/(1 + Λo + Λi) or separable G1·G1 (Heitz 2014, "Understanding the Masking-Shadowing
//   Function in Microfacet-Based BRDFs", JCGT 3(2), eq. 99 and §6); α = roughness² ≥ 10⁻³.
// - glTF metallic-roughness: glTF 2.0 specification, Appendix B §B.3.5 (as corrected in
//   KhronosGroup/glTF#2392): w = (1 − |ωo·h|)⁵, diffuse (1 − m)(1 − F_d)·c/π, specular
//   ((1 − m)F_d + m(c + (1 − c)w))·D·G2/(4 cos θo cos θi), F_d = 0.04 + 0.96w.
// Two-sided: reflection needs ωo, ωi on the same side of the shading normal; both are then
// taken on the upper side. Mirror and dielectric are Dirac deltas: eval = 0.
// Failure mode: none beyond the models' own (GGX loses energy at high roughness: no multiple
// scattering, as the oracle's `scattering = "single"`; the energy/*.wgsl methods add an
// approximation of the rest). f32 throughout; sin²θ terms use |n × ω|², which keeps digits
// near the normal where 1 − cos²θ loses them.
// Inputs: the resolved `Bsdf` (material inputs already looked up at the surface's uv).

// Smallest GGX α (oracle microfacet.rs MIN_ALPHA): keeps D finite in f32.
const MIN_ALPHA: f32 = 1e-3;
// Dielectric f0 of the glTF model (η = 1.5, glTF 2.0 Appendix B).
const GLTF_DIELECTRIC_F0: f32 = 0.04;

struct Bsdf {
    kind: u32,
    masking: u32,
    // GGX Fresnel: 0 Schlick's with f0, 1 a conductor's exact one of index f0 + i·k.
    fresnel: u32,
    // Albedo (Lambert), ks (Phong), reflectance (GGX, mirror), base colour (metal-rough).
    color: vec3<f32>,
    // Schlick's f0, or a conductor's η.
    f0: vec3<f32>,
    // A conductor's extinction coefficient.
    k: vec3<f32>,
    // GGX / metal-rough α.
    alpha: f32,
    metallic: f32,
    // Phong exponent n.
    exponent: f32,
    // Dielectric η = int_ior/ext_ior.
    eta: f32,
}

// f·|cos θi| split into its diffuse and specular parts (the representative-point method
// points them at different directions).
struct BsdfValue {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

fn sanitize_rgb(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(positive_or_zero(c.x), positive_or_zero(c.y), positive_or_zero(c.z));
}

fn sanitize_unit(x: f32) -> f32 {
    return min(positive_or_zero(x), 1.0);
}

// α = roughness², at least MIN_ALPHA (TrowbridgeReitz::from_roughness).
fn ggx_alpha(roughness: f32) -> f32 {
    let a = roughness * roughness;
    return select(MIN_ALPHA, a, a > MIN_ALPHA);
}

// When ≥ 0, the grey that replaces every material's base colour (albedo, ks, reflectance,
// base colour) in resolve_bsdf: Gouraud shading's texture variants (shading/vertex.wgsl)
// light a vertex with a white and a black base colour and apply the texture per pixel.
var<private> base_color_override: f32 = -1.0;

// The BSDF of material `m` at texture coordinate `uv`, inputs sanitised as Bsdf::from_material.
fn resolve_bsdf(m: Material, uv: vec2<f32>) -> Bsdf {
    var b = Bsdf(m.kind, m.masking, 0u, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), MIN_ALPHA, 0.0, 0.0, 1.0);
    switch m.kind {
        case MAT_DIFFUSE, MAT_PHONG: {
            b.color = sanitize_rgb(eval_tex_rgb(m.color_tex, m.color.xyz, uv));
            b.exponent = positive_or_zero(m.scalars.x);
        }
        case MAT_GGX: {
            b.color = sanitize_rgb(eval_tex_rgb(m.color_tex, m.color.xyz, uv));
            b.fresnel = m.fresnel;
            // η and k were checked when the scene loaded (η in (0, 100], k in [0, 100]).
            b.f0 = select(sanitize_rgb(m.f0.xyz), m.f0.xyz, m.fresnel == 1u);
            b.k = m.k.xyz;
            let r = eval_tex_scalar(m.roughness_tex, m.roughness_channel, m.scalars.x, uv);
            b.alpha = ggx_alpha(sanitize_unit(r));
        }
        case MAT_METAL_ROUGH: {
            b.color = sanitize_rgb(eval_tex_rgb(m.color_tex, m.color.xyz, uv));
            let r = eval_tex_scalar(m.roughness_tex, m.roughness_channel, m.scalars.x, uv);
            b.alpha = ggx_alpha(sanitize_unit(r));
            b.metallic = sanitize_unit(eval_tex_scalar(m.metallic_tex, m.metallic_channel, m.scalars.y, uv));
        }
        case MAT_MIRROR: {
            b.color = sanitize_rgb(m.color.xyz);
        }
        default: {
            // Dielectric: η = int/ext, 1 when not a positive finite number.
            let eta = m.scalars.z / m.scalars.w;
            b.eta = select(1.0, eta, eta > 0.0 && eta < 1e30);
            b.color = vec3<f32>(1.0);
        }
    }
    if base_color_override >= 0.0 && m.kind != MAT_DIELECTRIC {
        b.color = vec3<f32>(base_color_override);
    }
    return b;
}

// Dirac-delta BSDFs (no light from lights; environment reflection only).
fn bsdf_is_delta(b: Bsdf) -> bool {
    return b.kind == MAT_MIRROR || b.kind == MAT_DIELECTRIC;
}

// Schlick's weight (1 − cos θ)⁵ with cos θ clamped to [0, 1] (fresnel.rs `schlick_weight`).
fn schlick_weight(cos_theta: f32) -> f32 {
    let m = max(1.0 - clamp(cos_theta, 0.0, 1.0), 0.0);
    let m2 = m * m;
    return m2 * m2 * m;
}

// The exact unpolarised Fresnel reflectance of a conductor of complex index η + ik at cos θ
// (Born & Wolf, "Principles of Optics", §14.2; oracle fresnel.rs `conductor`, the same real
// arithmetic): with a² + b² = √((η² − k² − sin²θ)² + 4η²k²), a = √((a² + b² + η² − k² − sin²θ)/2),
// R_s = (a² + b² + cos²θ − 2a cos θ)/(a² + b² + cos²θ + 2a cos θ) and
// R_p = R_s (cos²θ(a² + b²) + sin⁴θ − 2a cos θ sin²θ)/(cos²θ(a² + b²) + sin⁴θ + 2a cos θ sin²θ).
fn conductor_fresnel(cos_theta: f32, eta: vec3<f32>, k: vec3<f32>) -> vec3<f32> {
    let c = clamp(cos_theta, 0.0, 1.0);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let t0 = eta * eta - k * k - s2;
    let a2b2 = sqrt(t0 * t0 + 4.0 * eta * eta * k * k);
    let a = sqrt(max(0.5 * (a2b2 + t0), vec3<f32>(0.0)));
    let t1 = a2b2 + c2;
    let t2 = 2.0 * a * c;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = c2 * a2b2 + s2 * s2;
    let t4 = t2 * s2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    return clamp(0.5 * (rs + rp), vec3<f32>(0.0), vec3<f32>(1.0));
}

// The GGX material's Fresnel at cos θd: Schlick's with f0, or the conductor's.
fn ggx_fresnel(b: Bsdf, cos_d: f32) -> vec3<f32> {
    if b.fresnel == 1u {
        return conductor_fresnel(cos_d, b.f0, b.k);
    }
    return b.f0 + (1.0 - b.f0) * schlick_weight(cos_d);
}

// D(m) = α²/(π(α²cos²θm + sin²θm)²) for cos θm > 0 (Walter et al. 2007, eq. 33).
fn ggx_d(alpha: f32, cos_m: f32, sin2_m: f32) -> f32 {
    if cos_m <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = a2 * cos_m * cos_m + sin2_m;
    return a2 / (PI * t * t);
}

// Smith Λ(ω) = (√(1 + α²tan²θ) − 1)/2 (Heitz 2014 §5; Walter et al. 2007, eq. 34).
fn smith_lambda(alpha: f32, cos_w: f32, sin2_w: f32) -> f32 {
    let cos2 = cos_w * cos_w;
    if cos2 == 0.0 {
        return 1e30;
    }
    let a2_tan2 = alpha * alpha * (sin2_w / cos2);
    return 0.5 * (sqrt(1.0 + a2_tan2) - 1.0);
}

// G2: height-correlated 1/(1 + Λo + Λi) (Heitz 2014, eq. 99) or separable G1(ωo)·G1(ωi).
fn smith_g2(alpha: f32, masking: u32, n: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let co = cross(n, wo);
    let ci = cross(n, wi);
    let lo = smith_lambda(alpha, dot(n, wo), dot(co, co));
    let li = smith_lambda(alpha, dot(n, wi), dot(ci, ci));
    if masking == 1u {
        return 1.0 / ((1.0 + lo) * (1.0 + li));
    }
    return 1.0 / (1.0 + lo + li);
}

// D(h)·G2/(4 cos θo): the microfacet specular BRDF times cos θi, without Fresnel.
fn ggx_specular_cos(alpha: f32, masking: u32, n: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>, h: vec3<f32>, cos_o: f32) -> f32 {
    let ch = cross(n, h);
    let d = ggx_d(alpha, dot(n, h), dot(ch, ch));
    return d * smith_g2(alpha, masking, n, wo, wi) / (4.0 * cos_o);
}

// f(ωo, ωi)·|cos θi| in parts; `n` is the shading normal (turned to the geometric normal's side).
fn bsdf_eval_split(b: Bsdf, n: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> BsdfValue {
    var v = BsdfValue(vec3<f32>(0.0), vec3<f32>(0.0));
    let co = dot(n, wo);
    let ci = dot(n, wi);
    if !(co * ci > 0.0) {
        return v;
    }
    // Both directions on the upper side of nn.
    let nn = select(n, -n, co < 0.0);
    let cos_o = abs(co);
    let cos_i = abs(ci);
    let hv = wo + wi;
    let h2 = dot(hv, hv);
    switch b.kind {
        case MAT_DIFFUSE: {
            v.diffuse = b.color * (cos_i * INV_PI);
        }
        case MAT_PHONG: {
            let cos_a = dot(wi, nn * (2.0 * cos_o) - wo);
            if cos_a > 0.0 {
                let norm = (b.exponent + 2.0) * (0.5 * INV_PI);
                v.specular = b.color * (norm * pow(cos_a, b.exponent) * cos_i);
            }
        }
        case MAT_GGX: {
            if h2 > 0.0 {
                let h = hv * inverseSqrt(h2);
                let f = ggx_fresnel(b, dot(wi, h));
                v.specular = b.color * f * ggx_specular_cos(b.alpha, b.masking, nn, wo, wi, h, cos_o);
                // The light single scattering loses, as the energy-compensation method adds it
                // back (energy/*.wgsl; microfacet reflectance k·F, a conductor's F taken as
                // Schlick's with its normal-incidence value, as engines take it).
                v.specular += energy_compensation(b.alpha, b.color, ggx_fresnel(b, 1.0), v.specular, cos_o, cos_i);
            }
        }
        case MAT_METAL_ROUGH: {
            if h2 > 0.0 {
                let h = hv * inverseSqrt(h2);
                let w = schlick_weight(abs(dot(wo, h)));
                let spec_cos = ggx_specular_cos(b.alpha, 0u, nn, wo, wi, h, cos_o);
                let f_d = GLTF_DIELECTRIC_F0 + (1.0 - GLTF_DIELECTRIC_F0) * w;
                let metal_f = b.color + (1.0 - b.color) * w;
                let m = b.metallic;
                v.diffuse = b.color * ((1.0 - m) * (1.0 - f_d) * INV_PI * cos_i);
                v.specular = (vec3<f32>((1.0 - m) * f_d) + metal_f * m) * spec_cos;
                // The metal's lobe alone is compensated (f0 = base colour), as the oracle's
                // multiple-scattering ground truth leaves the dielectric layer single.
                v.specular += m * energy_compensation(b.alpha, vec3<f32>(1.0), b.color, metal_f * spec_cos, cos_o, cos_i);
            }
        }
        default: {}
    }
    return v;
}

// When true, bsdf_eval returns the specular part alone: a light-mapped surface under
// `specular = direct` takes its diffuse light from the map and the lights' specular per pixel
// (shade.wgsl), through the same light loop and quadratures as every other surface.
var<private> bsdf_specular_only: bool = false;

fn bsdf_eval(b: Bsdf, n: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let v = bsdf_eval_split(b, n, wo, wi);
    if bsdf_specular_only {
        return v.specular;
    }
    return v.diffuse + v.specular;
}

// The GGX-equivalent width of the specular lobe, for the representative-point energy
// normalisation: α for GGX and metal-rough; √(2/(n + 2)) for Phong (the Phong–Beckmann
// correspondence n = 2α⁻² − 2, Walter et al. 2007 §5.2); 0 without a specular lobe.
fn specular_alpha(b: Bsdf) -> f32 {
    switch b.kind {
        case MAT_GGX, MAT_METAL_ROUGH: {
            return b.alpha;
        }
        case MAT_PHONG: {
            return sqrt(2.0 / (b.exponent + 2.0));
        }
        default: {
            return 0.0;
        }
    }
}

// The albedo AOV (Bsdf::albedo): ρ (Lambert), ks (Phong), k·f0 (GGX: the specular colour at
// normal incidence), base colour (metal-rough), reflectance (mirror), 1 (dielectric).
fn bsdf_albedo(b: Bsdf) -> vec3<f32> {
    if b.kind == MAT_GGX {
        return b.color * ggx_fresnel(b, 1.0);
    }
    return b.color;
}
