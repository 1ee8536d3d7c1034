//! The scene model both renderers load: camera, film, shapes, materials, lights, environment.
//!
//! Conventions (docs/ARCHITECTURE.md, "Conventions"): right-handed, +Y up, metres; linear Rec.709 RGB;
//! the camera looks down −Z in its own frame; pixel (i, j) covers the raster square
//! [i, i+1]×[j, j+1] with row 0 at the top. Every quantity here is in world space: loaders
//! bake node and `transform` chains into the geometry, so renderers never see a scene graph.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Affine3A, Quat, Vec2, Vec3};

use crate::pixel_filter::PixelFilter;
use crate::texture::Texture;
pub use crate::texture::WrapMode;

/// Linear Rec.709 RGB triple (radiance, reflectance, …).
pub type Rgb = Vec3;

/// Largest magnitude of a world coordinate, metres. Loaders refuse positions, lengths and
/// bounds beyond it, so that the renderers' products of coordinates (edge cross products,
/// squared distances: up to (2·10¹⁵)² = 4·10³⁰) stay far inside f32's 3.4·10³⁸.
pub const MAX_COORD: f32 = 1e15;

/// Largest radiance, intensity or irradiance component a scene may declare (W, m, sr units
/// as the scene's). The sun's radiance is about 2·10⁷ W m⁻² sr⁻¹; the cap leaves 18 orders of
/// magnitude between a light and f32 overflow for the BSDF, cosine and pdf factors a sample
/// multiplies it by.
pub const MAX_RADIANCE: f32 = 1e20;

/// Longest shape or light name, characters.
pub const MAX_NAME_CHARS: usize = 64;

/// Whether `name` can label an AOV channel (`visibility.<name>.Y`) and a file: 1 to
/// [`MAX_NAME_CHARS`] ASCII letters, digits, `_` and `-` (no `.`, the EXR layer separator;
/// no `/`, `:`, `*`, spaces, control or bidirectional characters).
pub fn is_identifier(name: &str) -> bool {
    (1..=MAX_NAME_CHARS).contains(&name.len())
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
}

/// `name` made an identifier ([`is_identifier`]): every other character becomes `_`, the
/// result is cut to [`MAX_NAME_CHARS`], and an empty name is `unnamed`.
pub fn to_identifier(name: &str) -> String {
    let s: String = name
        .chars()
        .take(MAX_NAME_CHARS)
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        "unnamed".into()
    } else {
        s
    }
}

/// Whether the box (`lo`, `hi`) is finite and within ±[`MAX_COORD`].
pub fn within_world(lo: Vec3, hi: Vec3) -> bool {
    lo.is_finite() && hi.is_finite() && lo.abs().max(hi.abs()).max_element() <= MAX_COORD
}

/// A whole scene, ready to render.
#[derive(Clone, Debug)]
pub struct Scene {
    /// File the scene was loaded from (for messages and report headers).
    pub source: PathBuf,
    /// The viewpoint.
    pub camera: Camera,
    /// Output raster size and render defaults.
    pub film: Film,
    /// Default render settings from the scene file (the CLI overrides them).
    pub render: RenderSettings,
    /// Image textures, referenced by index from [`TexRgb`]/[`TexScalar`].
    pub textures: Vec<Arc<Texture>>,
    /// Materials, referenced by index from [`Shape::material`].
    pub materials: Vec<Material>,
    /// Surfaces. A shape's object id (AOV) is its index + 1; 0 is the background.
    pub shapes: Vec<Shape>,
    /// Delta and distant lights. Area lights are emissive [`Shape`]s.
    pub lights: Vec<Light>,
    /// Distant environment, if any.
    pub environment: Option<Environment>,
    /// What loading took from the files beyond the model, or changed in them.
    pub provenance: Provenance,
}

/// What loading took from a scene's files beyond the model, or changed in them, for the
/// command line's notes and the renderers' EXR headers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Provenance {
    /// The aspect ratio (width / height) the camera was made for: a glTF camera's
    /// `aspectRatio`. A film of another shape keeps the vertical field of view.
    pub camera_aspect: Option<f32>,
    /// Environment-map texels whose negative components were set to 0
    /// (`[environment] negative = "clamp"`); the EXR headers of both renderers carry it as
    /// `environment_clamped_texels` when it is not 0.
    pub clamped_environment_texels: u64,
}

/// Pinhole camera (docs/ARCHITECTURE.md "Camera"): `to_world` maps the camera frame (looking down −Z,
/// +Y up) to world space; `fov_y_deg` is the full vertical field of view in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Rigid camera-to-world transform (no scale).
    pub to_world: Affine3A,
    /// Full vertical field of view, degrees, in (0, 180).
    pub fov_y_deg: f32,
}

impl Camera {
    /// Camera at `eye` looking at `target` with the given `up` hint.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, fov_y_deg: f32) -> Self {
        // look_at_rh builds world→view; invert to get view→world.
        let view = Affine3A::look_at_rh(eye, target, up);
        Camera {
            to_world: view.inverse(),
            fov_y_deg,
        }
    }

    /// Camera position in world space.
    pub fn position(&self) -> Vec3 {
        self.to_world.translation.into()
    }

    /// Unit view direction (the camera's −Z axis) in world space.
    pub fn forward(&self) -> Vec3 {
        (-Vec3::from(self.to_world.matrix3.z_axis)).normalize()
    }

    /// The camera turned by `degrees` about world +Y through the point `distance` ahead of it
    /// (an orbit about what it looks at); 0° is this camera bit for bit.
    pub fn orbited(&self, degrees: f32, distance: f32) -> Camera {
        if degrees == 0.0 {
            return *self;
        }
        let pivot = self.position() + self.forward() * distance;
        let turn = Affine3A::from_translation(pivot)
            * Affine3A::from_quat(Quat::from_rotation_y(degrees.to_radians()))
            * Affine3A::from_translation(-pivot);
        Camera {
            to_world: turn * self.to_world,
            fov_y_deg: self.fov_y_deg,
        }
    }

    /// World-space direction of the ray through raster position (x, y) of a `width`×`height`
    /// film; (0, 0) is the top-left corner of pixel (0, 0), (width, height) the bottom-right
    /// corner of the last pixel. Normalised. This is the one projection both renderers use:
    /// x_cam = (2x/W − 1)·tan(fov/2)·W/H, y_cam = (1 − 2y/H)·tan(fov/2), z_cam = −1.
    pub fn ray_direction(&self, x: f32, y: f32, width: u32, height: u32) -> Vec3 {
        self.projection(width, height).ray_direction(x, y)
    }

    /// [`Camera::ray_direction`]'s projection for a `width`×`height` film, its per-film
    /// constants (tan(fov/2), the aspect ratio) computed once for a render's many rays.
    pub fn projection(&self, width: u32, height: u32) -> RasterProjection {
        RasterProjection {
            to_world: self.to_world,
            tan_half: (self.fov_y_deg.to_radians() * 0.5).tan(),
            aspect: width as f32 / height as f32,
            width: width as f32,
            height: height as f32,
        }
    }
}

/// A camera's projection for one film size ([`Camera::projection`]).
#[derive(Clone, Copy, Debug)]
pub struct RasterProjection {
    to_world: Affine3A,
    tan_half: f32,
    /// Width / height.
    aspect: f32,
    width: f32,
    height: f32,
}

impl RasterProjection {
    /// [`Camera::ray_direction`] at raster position (x, y), bit for bit.
    pub fn ray_direction(&self, x: f32, y: f32) -> Vec3 {
        let xc = (2.0 * x / self.width - 1.0) * self.tan_half * self.aspect;
        let yc = (1.0 - 2.0 * y / self.height) * self.tan_half;
        self.to_world
            .transform_vector3(Vec3::new(xc, yc, -1.0))
            .normalize()
    }
}

/// Output raster.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Film {
    /// Width in pixels (1..=16384).
    pub width: u32,
    /// Height in pixels (1..=16384).
    pub height: u32,
}

impl Film {
    /// Whether the film has the shape `aspect` (width / height) up to the rounding of one
    /// side to whole pixels: width = round(height·aspect), or height = round(width / aspect).
    pub fn fits_aspect(&self, aspect: f32) -> bool {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let a = f64::from(aspect);
        (w - h * a).abs() <= 0.5 || (h - w / a).abs() <= 0.5
    }
}

/// Which light-transport quantity the oracle computes (docs/ARCHITECTURE.md "Ground truth").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum IntegratorKind {
    /// Full path tracing up to `max_depth` (Mitsuba's meaning: 1 = emitters seen directly,
    /// 2 = direct illumination, −1 = unbounded).
    #[default]
    Path,
    /// Emission + one bounce of direct light + perfect-specular chains.
    Direct,
    /// As `Direct`, with visibility ignored: every light is seen unoccluded (light sampling
    /// only, no shadow rays). The ground truth for unshadowed real-time shading.
    DirectUnshadowed,
    /// Ambient occlusion with a radius: fraction of unoccluded cosine-weighted directions.
    Ao,
}

impl IntegratorKind {
    /// Every spelling read wherever an integrator is named (scene TOML `integrator`, study
    /// `[ground_truth] integrator`, `verity render --integrator`): the one Verity prints
    /// ([`IntegratorKind::name`]) and the scene format's older `direct_unshadowed`.
    pub const SPELLINGS: [(&'static str, IntegratorKind); 5] = [
        ("path", IntegratorKind::Path),
        ("direct", IntegratorKind::Direct),
        ("direct-unshadowed", IntegratorKind::DirectUnshadowed),
        ("direct_unshadowed", IntegratorKind::DirectUnshadowed),
        ("ao", IntegratorKind::Ao),
    ];

    /// The one spelling Verity prints (metrics.json, EXR headers, reports, help):
    /// `path`, `direct`, `direct-unshadowed`, `ao`.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Path => "path",
            IntegratorKind::Direct => "direct",
            IntegratorKind::DirectUnshadowed => "direct-unshadowed",
            IntegratorKind::Ao => "ao",
        }
    }
}

/// How the oracle draws its random numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SamplerKind {
    /// Owen-scrambled Sobol points (Burley 2020): stratified, converges at least as 1/spp;
    /// each pixel's samples are dealt to independently scrambled replicates, whose spread
    /// estimates the variance of the pixel mean (oracle/src/sampler.rs).
    #[default]
    Sobol,
    /// Independent uniform samples: the plain Monte Carlo estimator, error exactly ∝ 1/spp.
    Independent,
}

/// Render defaults a scene file may carry; every one can be overridden on the command line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Samples per pixel.
    pub spp: u32,
    /// Light-transport mode.
    pub integrator: IntegratorKind,
    /// Path depth, Mitsuba semantics; −1 = unbounded.
    pub max_depth: i32,
    /// Depth at which Russian roulette starts (Mitsuba's `rr_depth`).
    pub rr_depth: u32,
    /// Ambient-occlusion radius in metres (`ao` integrator).
    pub ao_radius: f32,
    /// Seed of the sampler's scrambling.
    pub seed: u64,
    /// Random-number generator.
    pub sampler: SamplerKind,
    /// Where the camera rays cross each pixel: its area (box) or its (sub-)pixel centres.
    pub pixel_filter: PixelFilter,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            spp: 64,
            integrator: IntegratorKind::Path,
            max_depth: 6,
            rr_depth: 5,
            ao_radius: 1.0,
            seed: 0,
            sampler: SamplerKind::Sobol,
            pixel_filter: PixelFilter::Box,
        }
    }
}

/// An RGB material input: a constant, or a texture times a factor (glTF's convention).
#[derive(Clone, Debug, PartialEq)]
pub enum TexRgb {
    /// Same value everywhere.
    Constant(Rgb),
    /// `factor` × texture(uv); the texture is an index into [`Scene::textures`].
    Image {
        /// Index into [`Scene::textures`].
        texture: usize,
        /// Multiplier applied to the texel (linear RGB).
        factor: Rgb,
    },
}

/// A scalar material input: a constant, or one channel of a texture times a factor.
#[derive(Clone, Debug, PartialEq)]
pub enum TexScalar {
    /// Same value everywhere.
    Constant(f32),
    /// `factor` × texture(uv)[channel].
    Image {
        /// Index into [`Scene::textures`].
        texture: usize,
        /// Channel 0..=3 (glTF: roughness is G = 1, metallic is B = 2).
        channel: usize,
        /// Multiplier.
        factor: f32,
    },
}

/// Smith masking-shadowing variant for GGX (docs/ARCHITECTURE.md "BSDFs").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Masking {
    /// Height-correlated Smith G2 (Heitz 2014, eq. 99), as glTF specifies.
    #[default]
    HeightCorrelated,
    /// Separable Smith G1(wo)·G1(wi), as Mitsuba's `roughconductor` uses.
    Separable,
}

/// A conductor's complex index of refraction η + ik per colour channel, relative to the
/// medium outside (air): the exact Fresnel reflectance of a metal (Born & Wolf, "Principles of
/// Optics", §14.2), as Mitsuba 3's `roughconductor` takes it (`eta`, `k`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplexIor {
    /// Real part η (> 0).
    pub eta: Rgb,
    /// Imaginary part k, the extinction coefficient (≥ 0).
    pub k: Rgb,
}

/// How light scatters on a microfacet surface (docs/ARCHITECTURE.md "BSDFs").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Scattering {
    /// One reflection off the microsurface: the closed-form microfacet BRDF (Walter et al.
    /// 2007), which loses the energy of light that hits the surface more than once.
    #[default]
    Single,
    /// Every order of reflection, by a random walk on the microsurface (Heitz, Hanika, d'Eon &
    /// Dachsbacher 2016, "Multiple-Scattering Microfacet BSDFs with the Smith Model"): the
    /// exact ground truth of the Smith microsurface. Implies height-correlated masking.
    Multiple,
}

/// Materials (docs/ARCHITECTURE.md "BSDFs"). All are two-sided except the dielectric, which has an
/// inside and an outside.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian diffuse: f = albedo/π.
    Diffuse {
        /// Albedo ρ ∈ [0, 1].
        albedo: TexRgb,
    },
    /// Normalized Phong lobe around the mirror direction: f = ks·(n+2)/(2π)·cosⁿα (the
    /// integrand adds cosθi), α the angle between ωi and the mirror of ωo (Lafortune &
    /// Willems 1994, "Using the modified Phong reflectance model for physically based rendering").
    Phong {
        /// Specular reflectance ks ∈ [0, 1].
        reflectance: TexRgb,
        /// Exponent n ≥ 0.
        exponent: f32,
    },
    /// GGX / Trowbridge-Reitz microfacet reflection (Walter et al. 2007) with Schlick Fresnel
    /// F = f0 + (1 − f0)(1 − cosθd)⁵ (f0 = 1 gives F ≡ 1, Mitsuba's `roughconductor` with
    /// `material="none"`), or a conductor's exact Fresnel, times `reflectance`. alpha = roughness².
    Ggx {
        /// Multiplier on the lobe (Mitsuba's `specular_reflectance`).
        reflectance: TexRgb,
        /// Schlick's normal-incidence reflectance (unused with `conductor`).
        f0: Rgb,
        /// The exact Fresnel reflectance of a conductor of this index instead of Schlick's.
        conductor: Option<ComplexIor>,
        /// Perceptual roughness in [0, 1]; alpha = roughness².
        roughness: TexScalar,
        /// Smith masking variant.
        masking: Masking,
        /// Single or multiple scattering on the microsurface.
        scattering: Scattering,
    },
    /// glTF 2.0 metallic-roughness material (glTF 2.0 spec, Appendix B): Lambert diffuse and
    /// GGX specular mixed by Schlick Fresnel (f0 = 0.04 dielectric, base colour for metals).
    MetalRough {
        /// Base colour (sRGB texture decoded to linear).
        base_color: TexRgb,
        /// Metalness in [0, 1].
        metallic: TexScalar,
        /// Perceptual roughness in [0, 1].
        roughness: TexScalar,
        /// Single or multiple scattering on the metal's microsurface (the dielectric layer
        /// stays single-scattering).
        scattering: Scattering,
    },
    /// Ideal specular reflection, f = reflectance·δ(ωi − mirror(ωo)) / cosθi.
    Mirror {
        /// Reflectance.
        reflectance: Rgb,
    },
    /// Ideal smooth dielectric interface (exact Fresnel, Snell refraction).
    Dielectric {
        /// Interior index of refraction.
        int_ior: f32,
        /// Exterior index of refraction.
        ext_ior: f32,
    },
}

/// Optional per-shape normal map (tangent space, MikkTSpace convention as glTF).
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    /// Index into [`Scene::textures`] (a linear texture).
    pub texture: usize,
    /// glTF `normalTexture.scale`: multiplies the tangent-space X and Y.
    pub scale: f32,
}

/// Light emitted by a surface (an area light). Radiance in W·m⁻²·sr⁻¹.
#[derive(Clone, Debug, PartialEq)]
pub struct Emission {
    /// Emitted radiance (may be textured, e.g. glTF emissiveTexture × factor × strength).
    pub radiance: TexRgb,
    /// Emit from both sides; default false = front side only (the side the geometric normal
    /// points to), as Mitsuba's `area` emitter.
    pub two_sided: bool,
}

/// A triangle mesh in world space.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (unit), or empty for flat shading.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates, or empty.
    pub uvs: Vec<Vec2>,
    /// Per-vertex second texture coordinates (glTF `TEXCOORD_1`; boxes: one cell per face),
    /// or empty: the mesh's light-map chart, in [0, 1]² and not overlapping itself
    /// (scenes::lightmap).
    pub uv1: Vec<Vec2>,
    /// Per-vertex tangents (xyz unit, w = handedness ±1), or empty.
    pub tangents: Vec<glam::Vec4>,
    /// Triangle vertex indices, counter-clockwise seen from the front.
    pub indices: Vec<[u32; 3]>,
}

/// Geometry of a shape, in world space.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// Analytic sphere. uv follows Mitsuba's `sphere` in world axes: for the unit offset
    /// d = (p − center)/radius, u = φ/2π with φ = atan2(d.y, d.x) ∈ [0, 2π), v = acos(d.z)/π.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius > 0.
        radius: f32,
    },
    /// Parallelogram `center + s·half_u + t·half_v`, s, t ∈ [−1, 1]; front normal
    /// normalize(half_u × half_v). This is Mitsuba's `rectangle` ([-1,1]², normal +Z) under
    /// the affine map with columns (half_u, half_v, n, center). uv = ((s+1)/2, (t+1)/2).
    Rectangle {
        /// Centre.
        center: Vec3,
        /// Half edge along the first axis.
        half_u: Vec3,
        /// Half edge along the second axis.
        half_v: Vec3,
    },
    /// Ellipse `center + r·(cos φ·half_u + sin φ·half_v)`, r ∈ [0, 1]; front normal
    /// normalize(half_u × half_v) (Mitsuba's `disk` under the same affine map).
    Disk {
        /// Centre.
        center: Vec3,
        /// First semi-axis.
        half_u: Vec3,
        /// Second semi-axis.
        half_v: Vec3,
    },
    /// Triangle mesh (boxes are loaded as 12-triangle meshes with outward normals).
    Mesh(Arc<Mesh>),
}

/// A surface in the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// Name (unique within the scene; names the `visibility.<name>` AOV of emissive shapes).
    pub name: String,
    /// World-space geometry.
    pub geometry: Geometry,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Emission, making this shape an area light.
    pub emission: Option<Emission>,
    /// Optional tangent-space normal map.
    pub normal_map: Option<NormalMap>,
    /// Optional true displacement of the surface (rectangles and meshes only; never on an
    /// emitting shape). See [`Displacement`].
    pub displacement: Option<Displacement>,
}

/// True displacement p' = p + scale·h(u, v)·n of a shape's surface (docs/ARCHITECTURE.md "Ground truth":
/// surface detail), h one channel of a height texture at the surface's texture coordinates.
///
/// - On a [`Geometry::Rectangle`] (a heightfield patch) n is the front normal and h is
///   bilinear between texel centres, as [`Texture::sample`] reads it, so the surface is a
///   grid of bilinear patches ([`crate::displacement::HeightGrid`]).
/// - On a [`Geometry::Mesh`] (a displaced mesh, which needs uvs and vertex normals) n is the
///   interpolated vertex normal and the surface is the uniform micro-triangle tessellation of
///   [`crate::displacement::displace_mesh`].
///
/// The realtime renderer draws the undisplaced base surface (its surface-detail
/// techniques read the same height texture); the oracle traces the displaced one.
#[derive(Clone, Debug, PartialEq)]
pub struct Displacement {
    /// Index into [`Scene::textures`] (a linear texture: a file, or a procedural heightfield
    /// sampled at texel centres at load time).
    pub texture: usize,
    /// Channel 0..=3 holding h.
    pub channel: usize,
    /// Metres per unit of h (negative displaces against the normal).
    pub scale: f32,
}

/// What a spot light projects (a cookie or gobo; the geometry is [`crate::projection`]'s).
#[derive(Clone, Debug, PartialEq)]
pub struct Projection {
    /// The projected colour, an image (× factor) multiplying the intensity.
    pub texture: TexRgb,
    /// The image's up as seen from behind the light: a unit vector not along the axis.
    pub up: Vec3,
}

impl Projection {
    /// Right r and image-up t of the light with unit axis `axis`; None when `up` is along it.
    pub fn frame(&self, axis: Vec3) -> Option<(Vec3, Vec3)> {
        crate::projection::frame(axis, self.up)
    }
}

/// Delta and distant lights (area lights are emissive shapes).
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Isotropic point light; `intensity` in W/sr.
    Point {
        /// Name (for the `visibility.<name>` AOV).
        name: String,
        /// Position.
        position: Vec3,
        /// Radiant intensity, W/sr.
        intensity: Rgb,
    },
    /// Spot light with Mitsuba's falloff: full intensity inside `beam_width_deg`, falling
    /// linearly in angle to zero at `cutoff_deg` (Mitsuba 3 `spot`).
    Spot {
        /// Name.
        name: String,
        /// Position.
        position: Vec3,
        /// Unit direction the spot points to.
        direction: Vec3,
        /// Radiant intensity on the axis, W/sr.
        intensity: Rgb,
        /// Half-angle where the falloff reaches zero, degrees, (0, 90].
        cutoff_deg: f32,
        /// Half-angle of full intensity, degrees, [0, cutoff].
        beam_width_deg: f32,
        /// A projected texture (cookie), or None ([`crate::projection`]).
        projection: Option<Projection>,
    },
    /// Distant light. `irradiance` is measured on a surface facing the light (W/m²).
    /// With `angular_diameter_deg > 0` it is a uniform disk (the sun) of radiance
    /// L = E / (π·sin²(θmax)), θmax = diameter/2, so the irradiance is E at any size.
    Directional {
        /// Name.
        name: String,
        /// Unit direction the light travels to (Mitsuba's convention).
        direction: Vec3,
        /// Irradiance on a surface facing the light, W/m².
        irradiance: Rgb,
        /// Apparent diameter of the source, degrees, [0, 180); 0 = delta light.
        angular_diameter_deg: f32,
    },
}

impl Light {
    /// The light's name.
    pub fn name(&self) -> &str {
        match self {
            Light::Point { name, .. } | Light::Spot { name, .. } | Light::Directional { name, .. } => name,
        }
    }

    /// The light's name, to change it.
    pub fn name_mut(&mut self) -> &mut String {
        match self {
            Light::Point { name, .. } | Light::Spot { name, .. } | Light::Directional { name, .. } => name,
        }
    }
}

/// Distant environment (docs/ARCHITECTURE.md "Environment map"): equirectangular, Mitsuba's `envmap`
/// orientation: u = 0 faces −Z, u = 0.25 faces +X, u = 0.5 faces +Z; row 0 is +Y.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The same radiance from every direction.
    Constant {
        /// Radiance, W·m⁻²·sr⁻¹.
        radiance: Rgb,
    },
    /// An equirectangular image times `scale`.
    Map {
        /// Index into [`Scene::textures`] (a linear, usually EXR/HDR, texture).
        texture: usize,
        /// Radiance multiplier.
        scale: f32,
    },
}

/// Equirectangular direction ↔ uv mapping shared by both renderers (docs/ARCHITECTURE.md convention).
/// For unit direction d: φ = atan2(d.x, −d.z) wrapped to [0, 2π), u = φ/2π, v = acos(d.y)/π,
/// so u = 0 → −Z, u = 0.25 → +X, u = 0.5 → +Z and v = 0 (row 0) → +Y.
pub fn equirect_uv(d: Vec3) -> Vec2 {
    // φ measured from −Z towards +X: d = (sin φ sin θ, cos θ, −cos φ sin θ).
    let phi = d.x.atan2(-d.z); // (−π, π]
    let mut u = phi / std::f32::consts::TAU;
    if u < 0.0 {
        u += 1.0;
    }
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    Vec2::new(u, v)
}

/// Radiance of an equirectangular environment image towards unit direction `d`, with Mitsuba
/// 3's `envmap` texel placement (measured against Mitsuba 3.9.1 here): columns at texel
/// centres, u = (i + ½)/W, wrapping around; rows at v = j/(H − 1), so the first and last rows
/// sit exactly on the poles. Bilinear between those positions. Both renderers and the Mitsuba
/// exporter rely on this, so the same image means the same sky.
pub fn environment_lookup(texture: &Texture, d: Vec3) -> glam::Vec4 {
    environment_lookup_uv(texture, equirect_uv(d))
}

/// [`environment_lookup`] at texture coordinates `uv` = [`equirect_uv`]`(d)`, for callers that
/// need the coordinates for something else too.
pub fn environment_lookup_uv(texture: &Texture, uv: Vec2) -> glam::Vec4 {
    let (w, h) = (texture.width as i64, texture.height as i64);
    let x = uv.x * w as f32 - 0.5;
    let y = if h > 1 { uv.y * (h - 1) as f32 } else { 0.0 };
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    // Columns wrap: one remainder, its neighbour wrapped by a compare (i64 division is slow).
    let i0 = (x0 as i64).rem_euclid(w);
    let i1 = if i0 + 1 == w { 0 } else { i0 + 1 };
    let j = (y0 as i64).clamp(0, h - 1);
    let j1 = (j + 1).min(h - 1);
    let texel = |i: i64, j: i64| texture.texels[(j * w + i) as usize];
    let top = texel(i0, j) * (1.0 - fx) + texel(i1, j) * fx;
    let bottom = texel(i0, j1) * (1.0 - fx) + texel(i1, j1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// The direction of environment texel (i, j) under [`environment_lookup`]'s placement.
pub fn environment_texel_direction(i: u32, j: u32, width: u32, height: u32) -> Vec3 {
    let v = if height > 1 {
        j as f32 / (height - 1) as f32
    } else {
        0.5
    };
    equirect_direction(Vec2::new((i as f32 + 0.5) / width as f32, v))
}

/// Inverse of [`equirect_uv`]: the unit direction at texture coordinate (u, v).
pub fn equirect_direction(uv: Vec2) -> Vec3 {
    let phi = uv.x * std::f32::consts::TAU;
    let theta = uv.y * std::f32::consts::PI;
    let (sp, cp) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    Vec3::new(sp * st, ct, -cp * st)
}

impl Scene {
    /// Appends another scene's textures, materials, shapes and lights, re-indexing its
    /// references; keeps this scene's camera, film, settings and environment (a TOML file
    /// that includes a glTF file adds camera, lights and environment around it). A texture
    /// both scenes hold (the same `Arc`: an asset included twice) is kept once.
    pub fn merge(&mut self, other: Scene) {
        let mat_off = self.materials.len();
        let held: std::collections::HashMap<*const Texture, usize> = self
            .textures
            .iter()
            .enumerate()
            .map(|(i, t)| (Arc::as_ptr(t), i))
            .collect();
        let mut tex_index = Vec::with_capacity(other.textures.len());
        for t in other.textures {
            tex_index.push(held.get(&Arc::as_ptr(&t)).copied().unwrap_or_else(|| {
                self.textures.push(t);
                self.textures.len() - 1
            }));
        }
        let fix = |texture: &mut usize| *texture = tex_index[*texture];
        let fix_rgb = |t: &mut TexRgb| {
            if let TexRgb::Image { texture, .. } = t {
                fix(texture);
            }
        };
        let fix_scalar = |t: &mut TexScalar| {
            if let TexScalar::Image { texture, .. } = t {
                fix(texture);
            }
        };
        for mut m in other.materials {
            match &mut m {
                Material::Diffuse { albedo } => fix_rgb(albedo),
                Material::Phong { reflectance, .. } => fix_rgb(reflectance),
                Material::Ggx {
                    reflectance,
                    roughness,
                    ..
                } => {
                    fix_rgb(reflectance);
                    fix_scalar(roughness);
                }
                Material::MetalRough {
                    base_color,
                    metallic,
                    roughness,
                    ..
                } => {
                    fix_rgb(base_color);
                    fix_scalar(metallic);
                    fix_scalar(roughness);
                }
                Material::Mirror { .. } | Material::Dielectric { .. } => {}
            }
            self.materials.push(m);
        }
        for mut s in other.shapes {
            s.material += mat_off;
            if let Some(e) = &mut s.emission {
                fix_rgb(&mut e.radiance);
            }
            if let Some(n) = &mut s.normal_map {
                fix(&mut n.texture);
            }
            if let Some(d) = &mut s.displacement {
                fix(&mut d.texture);
            }
            self.shapes.push(s);
        }
        self.lights.extend(other.lights);
        if self.environment.is_none() {
            if let Some(mut env) = other.environment {
                if let Environment::Map { texture, .. } = &mut env {
                    fix(texture);
                }
                self.environment = Some(env);
            }
        }
    }

    /// Names of all lights in AOV order: emissive shapes first (scene order), then
    /// [`Scene::lights`]. The environment is not a named light.
    pub fn light_names(&self) -> Vec<String> {
        let area = self
            .shapes
            .iter()
            .filter(|s| s.emission.is_some())
            .map(|s| s.name.clone());
        area.chain(self.lights.iter().map(|l| l.name().to_string()))
            .collect()
    }
}

impl TexRgb {
    /// Value at texture coordinate `uv`.
    pub fn eval(&self, uv: Vec2, textures: &[Arc<Texture>]) -> Rgb {
        match self {
            TexRgb::Constant(c) => *c,
            TexRgb::Image { texture, factor } => textures[*texture].sample(uv).truncate() * *factor,
        }
    }

    /// Mean value over the texture (for light power estimates and AOV defaults).
    pub fn mean(&self, textures: &[Arc<Texture>]) -> Rgb {
        match self {
            TexRgb::Constant(c) => *c,
            TexRgb::Image { texture, factor } => {
                let t = &textures[*texture];
                let sum: glam::Vec4 = t.texels.iter().copied().sum();
                sum.truncate() / t.texels.len().max(1) as f32 * *factor
            }
        }
    }
}

impl TexScalar {
    /// Value at texture coordinate `uv`.
    pub fn eval(&self, uv: Vec2, textures: &[Arc<Texture>]) -> f32 {
        match self {
            TexScalar::Constant(c) => *c,
            TexScalar::Image {
                texture,
                channel,
                factor,
            } => textures[*texture].sample(uv)[*channel] * *factor,
        }
    }
}

impl Geometry {
    /// World-space axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match self {
            Geometry::Sphere { center, radius } => {
                (*center - Vec3::splat(*radius), *center + Vec3::splat(*radius))
            }
            Geometry::Rectangle {
                center,
                half_u,
                half_v,
            } => {
                let e = half_u.abs() + half_v.abs();
                (*center - e, *center + e)
            }
            Geometry::Disk {
                center,
                half_u,
                half_v,
            } => {
                // Extent of an ellipse along each axis: sqrt(u_i² + v_i²).
                let s = *half_u * *half_u + *half_v * *half_v;
                let e = Vec3::new(s.x.sqrt(), s.y.sqrt(), s.z.sqrt());
                (*center - e, *center + e)
            }
            Geometry::Mesh(m) => m
                .positions
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(*p), hi.max(*p))
                }),
        }
    }
}

impl Shape {
    /// World-space bounds (min, max) of the surface as rendered by the oracle: the geometry's
    /// bounds grown by the largest displacement |scale·h| when the shape is displaced (h over
    /// every texel: bilinear lookups stay within the texels' range). Conservative.
    pub fn bounds(&self, textures: &[Arc<Texture>]) -> (Vec3, Vec3) {
        let (lo, hi) = self.geometry.bounds();
        let Some(d) = &self.displacement else {
            return (lo, hi);
        };
        let reach = textures.get(d.texture).map_or(0.0, |t| {
            let height = |texel: &glam::Vec4| texel.to_array().get(d.channel).map_or(0.0, |h| h.abs());
            t.texels.iter().fold(0.0f32, |m, texel| m.max(height(texel)))
        }) * d.scale.abs();
        (lo - Vec3::splat(reach), hi + Vec3::splat(reach))
    }
}

impl Scene {
    /// World-space bounds of all shapes (displacement included), or a unit box at the origin
    /// for an empty scene.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let (lo, hi) = self
            .shapes
            .iter()
            .map(|s| s.bounds(&self.textures))
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (a, b)| {
                (lo.min(a), hi.max(b))
            });
        if lo.x > hi.x {
            (Vec3::splat(-1.0), Vec3::ONE)
        } else {
            (lo, hi)
        }
    }

    /// Centre and radius of a sphere enclosing [`Scene::bounds`] (for distant lights).
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        Self::sphere_around(self.bounds())
    }

    /// Centre and radius (at least 1 mm) of the sphere through the corners of the box (lo, hi).
    pub fn sphere_around((lo, hi): (Vec3, Vec3)) -> (Vec3, f32) {
        ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-3))
    }
}

/// ∂p/∂u and ∂p/∂v of a triangle from its vertex positions and uvs (pbrt-v4 §6.5.3), shared by
/// both renderers' tangent frames; None when the uv map is degenerate.
pub fn triangle_uv_derivatives(p: [Vec3; 3], uv: [Vec2; 3]) -> Option<(Vec3, Vec3)> {
    let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    let inv = 1.0 / det;
    if !(det != 0.0 && inv.is_finite()) {
        return None;
    }
    let dpdu = (dp02 * duv12.y - dp12 * duv02.y) * inv;
    let dpdv = (dp12 * duv02.x - dp02 * duv12.x) * inv;
    let c = dpdu.cross(dpdv);
    (c.is_finite() && c.length_squared() > 0.0).then_some((dpdu, dpdv))
}
