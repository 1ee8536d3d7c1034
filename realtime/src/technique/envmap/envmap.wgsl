// envmap/envmap.wgsl — environment mapping: the reflector shaded from maps captured at one point
// (realtime/src/technique/envmap/mod.rs), in place of its environment quadrature and its area lights.
//
// Technique: classic environment mapping (Blinn & Newell 1976, CACM 19(10)), the map looked
// up along R = 2(n·ωo)n − ωo (and the refracted direction of Snell's law for a dielectric):
// - parameterization (ENVMAP_METHOD): a cube map (Greene 1986, "Environment Mapping and Other
//   Applications of World Projections", IEEE CG&A 6(11)), a sphere map for one view direction
//   (Miller & Hoffman 1984; s = R_x/m, t = R_y/m, m = √(R_x² + R_y² + (R_z + 1)²) in the map's
//   frame), or a dual-paraboloid map ((x, y) = (R_x, R_y)/(1 ± R_z), Heidrich & Seidel 1998);
// - glossy reflection: the prefiltered level of the material's width, trilinear. GGX and glTF
//   metal-rough take the split sum L ≈ L_pre(R, r)·(f0·A + B) (Karis 2013, "Real Shading in
//   Unreal Engine 4"), (A, B) from the BRDF table at (n·ωo, r); Phong takes
//   ks·(n+2)/(n+1)·(n·R)·L_pre(R, n) (the lobe convolution, Heidrich & Seidel 1999 §4, with
//   the BRDF's normalization and the cosine at the lobe's axis). Mip level = r·(levels − 1), r = √α and
//   α = √(2/(n + 2)) for Phong (Walter et al. 2007 §5.2);
// - diffuse reflection: ρ/π·E(n), E from the cosine-convolved irradiance cube or from nine
//   spherical-harmonic coefficients (Ramamoorthi & Hanrahan 2001, eq. 13);
// - delta lights (point, spot, zero-diameter directional) stay exact; what the map holds
//   (environment, sun disks, emitters, lit local objects) is taken from the map only.
// Failure mode: everything the map shows is assumed infinitely far (parallax of near objects
// is lost: the locality study's lower bounds); no self-reflection or occlusion; the split sum
// assumes n = v = r for the prefiltered lobe (no stretched reflections at grazing angles);
// the Phong lookup takes the cosine at the lobe's axis and keeps the lobe's part below the
// horizon; rough lobes
// lean towards the normal (off-specular), which `dominant_direction` approximates; the sphere map is
// valid for its own view only (the direction behind the ball is its rim singularity); the
// paraboloid's seam where R_z = 0 darkens under bilinear filtering unless its texels past the
// unit disk are filled; mip levels of high roughness are a few texels wide.
// Inputs: group 3 (the maps, the sampler, SH coefficients, `envmap` uniform), a resolved
// Bsdf, the shading normal turned to the geometric normal's side, ωo.

// ENVMAP_METHOD values ENVMAP_NONE (0), ENVMAP_CUBE, ENVMAP_SPHERE, ENVMAP_PARABOLOID:
// generated from the method tables (technique/mod.rs `wgsl_codes`).
override ENVMAP_METHOD: u32 = 0u;

// envmap.info.y: how diffuse reflection is looked up.
const IRRADIANCE_MAP: u32 = 0u;
const IRRADIANCE_SH9: u32 = 1u;

struct EnvMapUniforms {
    // The reflector's shape index, irradiance kind (IRRADIANCE_*), number of levels, glossy
    // lookups along the dominant direction (1) or R (0).
    info: vec4<u32>,
    // The map frame: sphere map z towards its viewer; paraboloid z its axis.
    frame_x: vec4<f32>,
    frame_y: vec4<f32>,
    frame_z: vec4<f32>,
    // Localization (distance_impostor/lookup.wgsl): mode (LOCAL_*), iterations or linear steps,
    // secant steps, double refraction (1) or not (0).
    local: vec4<u32>,
    // The capture point and the refractor's centre (its map's origin), world space.
    capture: vec4<f32>,
    refractor: vec4<f32>,
    // Layers of the environment's distance map (x; 1: envmap_cube alone, more: the further
    // ones in envmap_layers).
    layers: vec4<u32>,
}

@group(3) @binding(0) var envmap_cube: texture_cube<f32>;
@group(3) @binding(1) var envmap_flat: texture_2d_array<f32>;
@group(3) @binding(2) var envmap_irradiance_cube: texture_cube<f32>;
@group(3) @binding(3) var envmap_brdf: texture_2d_array<f32>;
@group(3) @binding(4) var envmap_sampler: sampler;
@group(3) @binding(5) var<storage, read> envmap_sh: array<vec4<f32>, 9>;
@group(3) @binding(6) var<uniform> envmap: EnvMapUniforms;
// The refractor's distance map: outward normal (xyz) and distance from its centre (w).
@group(3) @binding(7) var envmap_refractor: texture_cube<f32>;
// Layers 1, 2, … of a layered distance map (radiance, distance), depth-peeled behind level 0
// of envmap_cube (distance_impostor/lookup.wgsl).
@group(3) @binding(8) var envmap_layers: texture_cube_array<f32>;

// Whether shape `shape` is the environment-mapped reflector.
fn is_envmapped(shape: u32) -> bool {
    return ENVMAP_METHOD != ENVMAP_NONE && shape == envmap.info.x;
}

// One filtered lookup: 4 fetches, 8 between two levels.
fn count_filtered(level: f32) {
    count_fetches(select(8u, 4u, fract(level) == 0.0));
}

// Radiance along unit d from the map at mip level `level` (0: the captured radiance).
fn envmap_radiance(d: vec3<f32>, level: f32) -> vec3<f32> {
    count_filtered(level);
    let rm = vec3<f32>(dot(d, envmap.frame_x.xyz), dot(d, envmap.frame_y.xyz), dot(d, envmap.frame_z.xyz));
    switch ENVMAP_METHOD {
        case ENVMAP_SPHERE: {
            let m = 2.0 * sqrt(rm.x * rm.x + rm.y * rm.y + (rm.z + 1.0) * (rm.z + 1.0));
            let uv = vec2<f32>(rm.x / m + 0.5, 0.5 - rm.y / m);
            return textureSampleLevel(envmap_flat, envmap_sampler, uv, 0, level).xyz;
        }
        case ENVMAP_PARABOLOID: {
            let back = rm.z < 0.0;
            let xy = rm.xy / (1.0 + abs(rm.z));
            let uv = vec2<f32>(0.5 + 0.5 * xy.x, 0.5 - 0.5 * xy.y);
            return textureSampleLevel(envmap_flat, envmap_sampler, uv, select(0, 1, back), level).xyz;
        }
        default: {
            return textureSampleLevel(envmap_cube, envmap_sampler, d, level).xyz;
        }
    }
}

// The nine real spherical harmonics Y_lm(d), bands 0–2 (Ramamoorthi & Hanrahan 2001, eq. 3);
// envmap/filter.wgsl projects onto the same basis.
fn sh9_basis(d: vec3<f32>) -> array<f32, 9> {
    return array<f32, 9>(
        0.282095,
        0.488603 * d.y,
        0.488603 * d.z,
        0.488603 * d.x,
        1.092548 * d.x * d.y,
        1.092548 * d.y * d.z,
        0.315392 * (3.0 * d.z * d.z - 1.0),
        1.092548 * d.x * d.z,
        0.546274 * (d.x * d.x - d.y * d.y),
    );
}

// Irradiance E(n) at the capture point.
fn envmap_irradiance(n: vec3<f32>) -> vec3<f32> {
    if envmap.info.y == IRRADIANCE_SH9 {
        count_fetches(9u);
        let y = sh9_basis(n);
        var e = vec3<f32>(0.0);
        for (var k = 0u; k < 9u; k++) {
            e += envmap_sh[k].xyz * y[k];
        }
        return max(e, vec3<f32>(0.0));
    }
    count_fetches(4u);
    return textureSampleLevel(envmap_irradiance_cube, envmap_sampler, n, 0.0).xyz;
}

// The mip level of a lobe of GGX-equivalent width α: r·(levels − 1), r = √α.
fn envmap_level(alpha: f32) -> f32 {
    return sqrt(clamp(alpha, 0.0, 1.0)) * f32(max(envmap.info.z, 1u) - 1u);
}

// Where a glossy lobe of width α about R is looked up: R, or its dominant direction
// lerp(n, R, s), s = (1 − α)(√(1 − α) + α) (Lagarde & de Rousiers 2014, "Moving Frostbite to
// Physically Based Rendering", §4.9.3: rough lobes lean towards the normal).
fn glossy_direction(n: vec3<f32>, r: vec3<f32>, alpha: f32) -> vec3<f32> {
    if envmap.info.w == 0u {
        return r;
    }
    let smooth_ = clamp(1.0 - alpha, 0.0, 1.0);
    return normalize(mix(n, r, smooth_ * (sqrt(smooth_) + alpha)));
}

// The split-sum table (A, B) at cos θo and α, for the material's masking function.
fn envmap_split_sum(cos_o: f32, alpha: f32, masking: u32) -> vec2<f32> {
    count_fetches(4u);
    let uv = vec2<f32>(cos_o, sqrt(alpha));
    return textureSampleLevel(envmap_brdf, envmap_sampler, uv, i32(min(masking, 1u)), 0.0).xy;
}

// Light reflected (and, through a dielectric, refracted) towards ωo at world point p from
// the maps; mirror and dielectric lookups localized by the distance impostors' search.
fn envmap_shading(b: Bsdf, p: vec3<f32>, n: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let c = dot(n, wo);
    let nn = select(n, -n, c < 0.0);
    let cos_o = min(abs(c), 1.0);
    let r = nn * (2.0 * cos_o) - wo;
    switch b.kind {
        case MAT_MIRROR: {
            return b.color * localized_radiance(p, r);
        }
        case MAT_DIELECTRIC: {
            let eta = select(1.0 / b.eta, b.eta, c >= 0.0);
            let fr = fresnel_dielectric(cos_o, eta);
            var l = fr.x * localized_radiance(p, r);
            if fr.x < 1.0 {
                let t = normalize(-wo / eta + nn * (cos_o / eta - fr.y));
                if envmap.local.w == 1u && c >= 0.0 {
                    l += (1.0 - fr.x) * double_refracted_radiance(p, t, eta);
                } else {
                    l += (1.0 - fr.x) * localized_radiance(p, t);
                }
            }
            return l;
        }
        case MAT_DIFFUSE: {
            return b.color * INV_PI * envmap_irradiance(nn);
        }
        case MAT_PHONG: {
            // ks·(n+2)/(2π)∫cosⁿα·cos θi·L dω ≈ ks·(n+2)/(n+1)·(n·R)·L_pre(R): the map holds the
            // lobe normalized as (n+1)/(2π)·cosⁿα, and cos θi is taken at the lobe's axis
            // (exact as n → ∞; our approximation).
            let alpha = specular_alpha(b);
            let cos_r = max(dot(nn, r), 0.0);
            let norm = (b.exponent + 2.0) / (b.exponent + 1.0) * cos_r;
            return b.color * norm * envmap_radiance(glossy_direction(nn, r, alpha), envmap_level(alpha));
        }
        case MAT_GGX: {
            let ab = envmap_split_sum(cos_o, b.alpha, b.masking);
            let l = envmap_radiance(glossy_direction(nn, r, b.alpha), envmap_level(b.alpha));
            // A conductor's exact Fresnel enters the split sum as Schlick's with its value at
            // normal incidence (Karis 2013's f0·A + B; exact only at normal incidence).
            return b.color * (ggx_fresnel(b, 1.0) * ab.x + ab.y) * l;
        }
        default: {
            // glTF metal-rough: Schlick with f0 = (1 − m)·0.04 + m·c for the specular lobe;
            // the diffuse lobe's (1 − F_d) taken at n·ωo.
            let m = b.metallic;
            let f0 = vec3<f32>((1.0 - m) * GLTF_DIELECTRIC_F0) + m * b.color;
            let ab = envmap_split_sum(cos_o, b.alpha, 0u);
            let spec = (f0 * ab.x + ab.y) * envmap_radiance(glossy_direction(nn, r, b.alpha), envmap_level(b.alpha));
            let f_d = GLTF_DIELECTRIC_F0 + (1.0 - GLTF_DIELECTRIC_F0) * schlick_weight(cos_o);
            return spec + b.color * ((1.0 - m) * (1.0 - f_d) * INV_PI) * envmap_irradiance(nn);
        }
    }
}

// The environment-mapped reflector at sp: its emission, the delta lights exactly, the rest
// from the maps.
fn shade_envmapped(f: FrameUniforms, sp: SurfacePoint, b: Bsdf, n: vec3<f32>, wo: vec3<f32>, emitted: vec3<f32>) -> vec3<f32> {
    var color = emitted + envmap_shading(b, sp.p, n, wo);
    if bsdf_is_delta(b) {
        return color;
    }
    for (var i = 0u; i < f.counts.x; i++) {
        count_iteration();
        let l = lights[i];
        if !is_sun_disk(l) {
            let inc = punctual_incident(l, sp.p);
            if any(inc.li > vec3<f32>(0.0)) {
                color += bsdf_eval(b, n, wo, inc.wi) * inc.li;
            }
        }
    }
    return color;
}
