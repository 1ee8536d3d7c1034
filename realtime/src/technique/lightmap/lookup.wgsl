// lightmap/lookup.wgsl — diffuse lighting of static surfaces from a baked irradiance atlas
// (technique/lightmap.rs; the atlas and its charts: scenes/src/lightmap.rs).
//
// Technique: light maps (Quake, 1996; Abrash 1997, "Graphics Programming Black Book" ch. 68):
// the irradiance E of every texel centre of a surface's chart, baked offline (here by the
// oracle's path tracer, direct and indirect), looked up at the shading point and multiplied
// by the diffuse albedo: L_o = ρ/π · E (Lambert). A rectangle's or disk's chart coordinate is
// c = ((s + 1)/2, (t + 1)/2) of its local (s, t); the chart's texel (i, j) is centred at
// c = ((i + ½)/W, (j + ½)/H), so a lookup at atlas texel x + c_u·W − ½ reads it back exactly.
// A mesh's chart coordinate is its interpolated second uv set (glTF TEXCOORD_1; a box's
// faces in the cells of a 3 × 2 grid).
// LIGHTMAP_BILINEAR weighs the 2×2 nearest texels bilinearly; LIGHTMAP_BICUBIC the 4×4 by
// the cubic B-spline (Sigg & Hadwiger 2005, "Fast Third-Order Texture Filtering", GPU Gems 2
// ch. 20, eq. 1 — here as 16 fetches, not their 4 bilinear ones, since the atlas is read from
// the texel buffer), C² across texels but not interpolating: (E₋₁ + 4E₀ + E₊₁)/6 at a centre.
// Failure modes: detail finer than a texel is blurred; a map baked at texel corners shifts
// everything by half a texel; across a chart's border a lookup reads dilated padding (seams);
// a texel spanning a thin wall averages both sides (leaks); only the diffuse part of a
// material is in the map — specular lobes of static surfaces are lost unless `specular =
// direct` adds every light's direct specular per pixel (unshadowed, and without the specular
// of indirect light); dynamic shapes have no chart and are lit per pixel by direct light
// (shade.wgsl).
// Inputs: the shape's `lightmap` record (atlas texture, chart origin and size), the texel buffer.

override LIGHTMAP_METHOD: u32 = 0u;
// 1: add the specular lobes' direct light per pixel (`specular = direct`), 0: none.
override LIGHTMAP_SPECULAR: u32 = 0u;

// A mesh fragment's light-map chart coordinates (its interpolated uv1), set by the forward
// pass's mesh entry point: SurfacePoint carries one uv set, and only this lookup reads the
// second. The deferred pipeline, whose G-buffer has no room for it, refuses light-mapped
// meshes (RasterSettings::check).
var<private> mesh_lightmap_uv: vec2<f32>;

// Whether the shape is lit from the light map (a lightmap method, and the shape has a chart).
fn is_lightmapped(s: Shape) -> bool {
    return LIGHTMAP_METHOD != LIGHTMAP_NONE && s.lightmap.x != NONE;
}

// The cubic B-spline's weights of the four texels around fraction t ∈ [0, 1) (Sigg &
// Hadwiger 2005, eq. 1: w0 = (1 − t)³/6, w1 = (3t³ − 6t² + 4)/6, w2 = (−3t³ + 3t² + 3t + 1)/6,
// w3 = t³/6).
fn bspline_weights(t: f32) -> vec4<f32> {
    let t2 = t * t;
    let t3 = t2 * t;
    let u = 1.0 - t;
    return vec4<f32>(u * u * u, 3.0 * t3 - 6.0 * t2 + 4.0, -3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0, t3) / 6.0;
}

// Irradiance E (W/m²) at point p of the rectangle or disk `s` from its chart.
fn lightmap_irradiance(s: Shape, p: vec3<f32>) -> vec3<f32> {
    let info = texture_infos[s.lightmap.x];
    let size = vec2<f32>(f32(s.lightmap.w & 0xffffu), f32(s.lightmap.w >> 16u));
    var c = mesh_lightmap_uv;
    if s.kind != SHAPE_MESH {
        c = (plane_local(s, p) + 1.0) * 0.5;
    }
    c = clamp(c, vec2<f32>(0.0), vec2<f32>(1.0));
    // Atlas texel coordinates with texel centres at integers.
    let a = vec2<f32>(f32(s.lightmap.y), f32(s.lightmap.z)) + c * size - 0.5;
    let base = floor(a);
    let t = a - base;
    let i = i32(base.x);
    let j = i32(base.y);
    if LIGHTMAP_METHOD == LIGHTMAP_BICUBIC {
        let wx = bspline_weights(t.x);
        let wy = bspline_weights(t.y);
        var e = vec3<f32>(0.0);
        for (var dy = 0; dy < 4; dy++) {
            var row = vec3<f32>(0.0);
            for (var dx = 0; dx < 4; dx++) {
                row += wx[dx] * texel_wrapped(info, i + dx - 1, j + dy - 1).xyz;
            }
            e += wy[dy] * row;
        }
        return max(e, vec3<f32>(0.0));
    }
    let top = mix(texel_wrapped(info, i, j).xyz, texel_wrapped(info, i + 1, j).xyz, t.x);
    let bottom = mix(texel_wrapped(info, i, j + 1).xyz, texel_wrapped(info, i + 1, j + 1).xyz, t.x);
    return mix(top, bottom, t.y);
}

// The part of a BSDF the light map lights: the diffuse albedo ρ (Lambert's; glTF
// metal-roughness's (1 − metallic)·base colour, its diffuse lobe without the Fresnel
// weight). Phong lobes, GGX conductors, mirrors and glass have none.
fn lightmap_albedo(b: Bsdf) -> vec3<f32> {
    switch b.kind {
        case MAT_DIFFUSE: {
            return b.color;
        }
        case MAT_METAL_ROUGH: {
            return (1.0 - b.metallic) * b.color;
        }
        default: {
            return vec3<f32>(0.0);
        }
    }
}
