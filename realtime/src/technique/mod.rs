//! The real-time techniques: one module per family, each holding its methods, their
//! parameter tables ([`param`]), their GPU resources and (under `shaders/<family>/`) their
//! WGSL; and [`Method`], the one method a render uses, composed of the families' settings.
//!
//! | family | module | methods | ground truth (oracle) |
//! |---|---|---|---|
//! | area lights | [`area`] | `area_quadrature`, `area_representative_point` | `direct-unshadowed` |
//! | shadow maps | [`shadow`] | `shadow_hard`, `pcf_hw_2x2`, `pcf_box`, `pcf_poisson`, `pcss` | `direct`, `visibility.<light>.Y` |
//! | surface detail | [`detail`] | `normal_mapping` … `cone_step` (8) | `direct` of the displaced surface |
//! | environment mapping | [`envmap`] | `envmap_cube`, `envmap_sphere`, `envmap_paraboloid` | `direct` with the reflector's exact reflection |
//! | distance impostors | [`distance_impostor`] | `distance_impostor`, `distance_search` | as environment mapping |
//! | texture filtering | [`texture`] | `tex_nearest` … `tex_anisotropic` (9) | the pixel's box filter over level 0 |
//! | shading frequency | [`shading`] | `shading_phong`, `shading_gouraud`, `shading_flat` | `direct-unshadowed` of the same mesh |
//! | anti-aliasing | [`antialias`] | `aa_none`, `aa_ssaa`, `aa_msaa`, `aa_fxaa`, `aa_mlaa`, `aa_taa` | the pixel's box filter |
//! | light maps | [`lightmap`] | `lightmap_bilinear`, `lightmap_bicubic` | `path` with the bake's `max_depth` |
//! | ambient occlusion | [`ssao`] | `ssao_crytek`, `ssao_hemisphere`, `ssao_hbao`, `ssao_gtao` | `ao` with the same radius |
//! | energy compensation | [`energy`] | `energy_none`, `energy_kulla_conty`, `energy_turquin`, `energy_fdez_aguera` | the same scene with `scattering = "multiple"` |
//!
//! Every method takes [`COMMON`]'s `n` (N×N quadrature of each area light and sun disk; not
//! `area_representative_point`), `env_n` (`env_n`×`env_n` cosine-weighted midpoint
//! quadrature of the environment, 0: none; the environment is never shadowed) and `mesh_n`
//! (`mesh_n`×`mesh_n` midpoint quadrature of each emissive mesh triangle, unshadowed; unset, 0:
//! emissive meshes light nothing), then its
//! family's shared parameters, then its own. [`markdown`] writes all of it as
//! docs/methods.md, [`param_help`] as `verity raster --help`'s.

pub mod antialias;
pub mod area;
pub mod detail;
pub mod distance_impostor;
pub mod energy;
pub mod envmap;
pub mod lightmap;
pub mod param;
pub mod shading;
pub mod shadow;
pub mod ssao;
pub mod texture;

use std::fmt;

use antialias::AntiAliasing;
use area::AreaMethod;
use detail::Detail;
use energy::EnergyCompensation;
use envmap::localization::Localization;
use envmap::EnvMapping;
use lightmap::LightMapMethod;
use param::{spec_named, Kind, MethodSpec, Param, Value};
use shading::ShadingFrequency;
use shadow::Shadow;
use ssao::AmbientOcclusion;
use texture::TextureFilter;

/// Largest `n` / `env_n` accepted (N² samples per light per pixel).
pub const MAX_QUADRATURE_N: u32 = 64;

/// A method with its parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Method {
    /// How area lights and sun disks are shaded.
    pub area: AreaMethod,
    /// N of the N×N area quadrature (ignored by the representative point).
    pub area_n: u32,
    /// N of the N×N environment quadrature; 0 = no environment lighting.
    pub env_n: u32,
    /// N of the N×N quadrature of each emissive mesh triangle; 0 = emissive meshes light
    /// nothing.
    pub mesh_n: u32,
    /// Shadow mapping, or None: every light unoccluded.
    pub shadow: Option<Shadow>,
    /// Surface detail on displaced shapes, or None: they are drawn flat (their base surface).
    pub detail: Option<Detail>,
    /// Environment mapping of one reflector, or None: no maps are captured.
    pub envmap: Option<EnvMapping>,
    /// The texture filter of a `tex_*` method, or None: bilinear at level 0
    /// ([`TextureFilter::BILINEAR`]), the lookup of every other method.
    pub texture: Option<TextureFilter>,
    /// The anti-aliasing of an `aa_*` method, or None: one sample at each pixel's centre
    /// (the raster's `ssaa` apart).
    pub antialias: Option<AntiAliasing>,
    /// The shading frequency of a `shading_*` method, or None: per pixel.
    pub shading: Option<ShadingFrequency>,
    /// The light map of a `lightmap_*` method, or None: every surface lit per pixel.
    pub lightmap: Option<LightMapMethod>,
    /// The screen-space AO of an `ssao_*` method, or None: the environment unoccluded.
    pub ssao: Option<AmbientOcclusion>,
    /// The energy compensation of an `energy_*` method, or None: single scattering.
    pub energy: Option<EnergyCompensation>,
}

impl Default for Method {
    /// `area_quadrature` with n = 16, env_n = 8.
    fn default() -> Self {
        Method {
            area: AreaMethod::Quadrature,
            area_n: 16,
            env_n: 8,
            mesh_n: 0,
            shadow: None,
            detail: None,
            envmap: None,
            texture: None,
            antialias: None,
            shading: None,
            lightmap: None,
            ssao: None,
            energy: None,
        }
    }
}

/// The parameters every method has (`n` only where the area lights are integrated by
/// quadrature).
pub static COMMON: &[Param<Method>] = &[
    Param {
        name: "n",
        kind: Kind::Whole(1, MAX_QUADRATURE_N),
        unit: "",
        doc: "N of the N×N midpoint quadrature of each area light and sun disk",
        source: "",
        unset: "",
        get: |m| Some(Value::Whole(m.area_n)),
        set: |m, v| {
            m.area_n = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "env_n",
        kind: Kind::Whole(0, MAX_QUADRATURE_N),
        unit: "",
        doc: "N of the N×N cosine-weighted quadrature of the environment (0: no environment lighting)",
        source: "",
        unset: "",
        get: |m| Some(Value::Whole(m.env_n)),
        set: |m, v| {
            m.env_n = v.whole()?;
            Some(())
        },
    },
    Param {
        name: "mesh_n",
        kind: Kind::Whole(0, MAX_QUADRATURE_N),
        unit: "",
        doc: "N of the N×N midpoint quadrature of each emissive mesh triangle (uniform in area), unshadowed; its \
              cost is triangles × N² per pixel",
        source: "Shirley 1992, \"Nonuniform Random Point Sets via Warping\", Graphics Gems III (the triangle warp)",
        unset: "0: emissive meshes light nothing",
        get: |m| (m.mesh_n > 0).then_some(Value::Whole(m.mesh_n)),
        set: |m, v| {
            m.mesh_n = v.whole()?;
            Some(())
        },
    },
];

/// The values of an environment map's `detail`: `none`, then every detail method.
const DETAIL_CHOICES: [&str; 1 + detail::METHODS.len()] = {
    let mut names = ["none"; 1 + detail::METHODS.len()];
    let mut i = 0;
    while i < detail::METHODS.len() {
        names[i + 1] = detail::METHODS[i].name;
        i += 1;
    }
    names
};

/// `detail` of the environment-mapping methods: a detail method, with its parameters.
static ENVMAP_DETAIL: Param<Method> = Param {
    name: "detail",
    kind: Kind::Keyword(&DETAIL_CHOICES),
    unit: "",
    doc: "lookups along the normals a surface-detail method perturbs (environment-mapped normal mapping), \
          with that method's parameters; none: the reflector's own normals",
    source: "",
    unset: "",
    get: |m| Some(Value::Keyword(m.detail.map_or("none", |d| d.technique.name()))),
    set: |m, v| {
        m.detail = match v.keyword()? {
            "none" => None,
            name => Some(Detail::by_name(name)?),
        };
        Some(())
    },
};

/// The family a method belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// [`area`].
    Area,
    /// [`shadow`].
    Shadow,
    /// [`detail`].
    Detail,
    /// [`envmap`].
    EnvMap,
    /// [`distance_impostor`].
    DistanceImpostor,
    /// [`texture`].
    Texture,
    /// [`shading`].
    Shading,
    /// [`antialias`].
    AntiAliasing,
    /// [`lightmap`].
    LightMap,
    /// [`ssao`].
    AmbientOcclusion,
    /// [`energy`].
    Energy,
}

impl Family {
    /// Every family, in the order the docs list them.
    pub const ALL: [Family; 11] = [
        Family::Area,
        Family::Shadow,
        Family::Detail,
        Family::EnvMap,
        Family::DistanceImpostor,
        Family::Texture,
        Family::Shading,
        Family::AntiAliasing,
        Family::LightMap,
        Family::AmbientOcclusion,
        Family::Energy,
    ];

    /// Its heading in the docs.
    pub fn title(self) -> &'static str {
        match self {
            Family::Area => "Area lights",
            Family::Shadow => "Shadow maps",
            Family::Detail => "Surface detail",
            Family::EnvMap => "Environment mapping",
            Family::DistanceImpostor => "Distance impostors",
            Family::Texture => "Texture filtering",
            Family::Shading => "Shading frequency",
            Family::AntiAliasing => "Anti-aliasing",
            Family::LightMap => "Light maps",
            Family::AmbientOcclusion => "Screen-space ambient occlusion",
            Family::Energy => "Energy compensation",
        }
    }

    /// Its methods' names, summaries and papers.
    pub fn methods(self) -> Vec<MethodInfo> {
        fn infos<T>(specs: &'static [MethodSpec<T>]) -> Vec<MethodInfo> {
            specs
                .iter()
                .map(|s| MethodInfo {
                    name: s.name,
                    summary: s.summary,
                    source: s.source,
                })
                .collect()
        }
        match self {
            Family::Area => infos(area::METHODS),
            Family::Shadow => infos(shadow::METHODS),
            Family::Detail => infos(detail::METHODS),
            Family::EnvMap => infos(envmap::METHODS),
            Family::DistanceImpostor => infos(distance_impostor::METHODS),
            Family::Texture => infos(texture::METHODS),
            Family::Shading => infos(shading::METHODS),
            Family::AntiAliasing => infos(antialias::METHODS),
            Family::LightMap => infos(lightmap::METHODS),
            Family::AmbientOcclusion => infos(ssao::METHODS),
            Family::Energy => infos(energy::METHODS),
        }
    }

    /// The rows its methods share after [`COMMON`] (shown with the defaults of `first`, the
    /// family's first method).
    fn shared_rows(self) -> Vec<Row> {
        match self {
            Family::Area | Family::Texture | Family::Shading | Family::AntiAliasing | Family::Energy => {
                Vec::new()
            }
            Family::Shadow => shadow::COMMON.iter().map(Row::Shadow).collect(),
            Family::LightMap => lightmap::COMMON.iter().map(Row::LightMap).collect(),
            Family::AmbientOcclusion => ssao::COMMON.iter().map(Row::Ssao).collect(),
            Family::Detail => detail::COMMON.iter().map(Row::Detail).collect(),
            Family::EnvMap | Family::DistanceImpostor => envmap::COMMON
                .iter()
                .map(Row::EnvMap)
                .chain([Row::Method(&ENVMAP_DETAIL)])
                .collect(),
        }
    }
}

/// A method's name, what it does and its paper.
#[derive(Clone, Copy, Debug)]
pub struct MethodInfo {
    /// `--method NAME`.
    pub name: &'static str,
    /// One line: what it does per pixel.
    pub summary: &'static str,
    /// Its paper.
    pub source: &'static str,
}

/// One row of a method's table, whichever part of the method it reads and writes.
#[derive(Clone, Copy)]
pub enum Row {
    /// A row of the method itself ([`COMMON`], `detail`).
    Method(&'static Param<Method>),
    /// A row of its shadow mapping.
    Shadow(&'static Param<Shadow>),
    /// A row of its surface detail.
    Detail(&'static Param<Detail>),
    /// A row of its environment mapping (distance impostors included).
    EnvMap(&'static Param<EnvMapping>),
    /// A row of its texture filter.
    Texture(&'static Param<TextureFilter>),
    /// A row of its anti-aliasing.
    AntiAlias(&'static Param<AntiAliasing>),
    /// A row of its shading frequency.
    Shading(&'static Param<ShadingFrequency>),
    /// A row of its light map.
    LightMap(&'static Param<LightMapMethod>),
    /// A row of its screen-space AO.
    Ssao(&'static Param<AmbientOcclusion>),
    /// A row of its energy compensation.
    Energy(&'static Param<EnergyCompensation>),
}

/// The same field of whichever table a row is from.
macro_rules! row_field {
    ($row:expr, $field:ident) => {
        match $row {
            Row::Method(p) => p.$field,
            Row::Shadow(p) => p.$field,
            Row::Detail(p) => p.$field,
            Row::EnvMap(p) => p.$field,
            Row::Texture(p) => p.$field,
            Row::AntiAlias(p) => p.$field,
            Row::Shading(p) => p.$field,
            Row::LightMap(p) => p.$field,
            Row::Ssao(p) => p.$field,
            Row::Energy(p) => p.$field,
        }
    };
}

impl Row {
    /// `--param NAME=…`.
    pub fn name(&self) -> &'static str {
        row_field!(self, name)
    }

    /// What it accepts.
    pub fn kind(&self) -> Kind {
        row_field!(self, kind)
    }

    /// Unit of its values.
    pub fn unit(&self) -> &'static str {
        row_field!(self, unit)
    }

    /// One line: what it does.
    pub fn doc(&self) -> &'static str {
        row_field!(self, doc)
    }

    /// Its paper, or "".
    pub fn source(&self) -> &'static str {
        row_field!(self, source)
    }

    /// What an unset optional parameter means, or "".
    pub fn unset(&self) -> &'static str {
        row_field!(self, unset)
    }

    /// Its value in `m` (None: unset, or not a row of `m`).
    pub fn get(&self, m: &Method) -> Option<Value> {
        match self {
            Row::Method(p) => (p.get)(m),
            Row::Shadow(p) => m.shadow.as_ref().and_then(|s| (p.get)(s)),
            Row::Detail(p) => m.detail.as_ref().and_then(|d| (p.get)(d)),
            Row::EnvMap(p) => m.envmap.as_ref().and_then(|e| (p.get)(e)),
            Row::Texture(p) => m.texture.as_ref().and_then(|t| (p.get)(t)),
            Row::AntiAlias(p) => m.antialias.as_ref().and_then(|a| (p.get)(a)),
            Row::Shading(p) => m.shading.as_ref().and_then(|s| (p.get)(s)),
            Row::LightMap(p) => m.lightmap.as_ref().and_then(|l| (p.get)(l)),
            Row::Ssao(p) => m.ssao.as_ref().and_then(|a| (p.get)(a)),
            Row::Energy(p) => m.energy.as_ref().and_then(|e| (p.get)(e)),
        }
    }

    /// Stores `value` (already accepted by its kind) in `m`; None if `m` cannot take it.
    fn set(&self, m: &mut Method, value: Value) -> Option<()> {
        match self {
            Row::Method(p) => (p.set)(m, value),
            Row::Shadow(p) => (p.set)(m.shadow.as_mut()?, value),
            Row::Detail(p) => (p.set)(m.detail.as_mut()?, value),
            Row::EnvMap(p) => (p.set)(m.envmap.as_mut()?, value),
            Row::Texture(p) => (p.set)(m.texture.as_mut()?, value),
            Row::AntiAlias(p) => (p.set)(m.antialias.as_mut()?, value),
            Row::Shading(p) => (p.set)(m.shading.as_mut()?, value),
            Row::LightMap(p) => (p.set)(m.lightmap.as_mut()?, value),
            Row::Ssao(p) => (p.set)(m.ssao.as_mut()?, value),
            Row::Energy(p) => (p.set)(m.energy.as_mut()?, value),
        }
    }
}

/// The environment-mapping or distance-impostor method `e` is.
fn envmap_spec(e: &EnvMapping) -> &'static MethodSpec<EnvMapping> {
    match e.localization {
        Localization::Distant => &envmap::METHODS[e.parameterization.shader_code() as usize - 1],
        Localization::Iterations(_) => &distance_impostor::METHODS[0],
        Localization::Search { .. } => &distance_impostor::METHODS[1],
    }
}

impl Method {
    /// Every method name `parse` accepts, family by family.
    pub fn names() -> Vec<&'static str> {
        Family::ALL
            .iter()
            .flat_map(|f| f.methods())
            .map(|m| m.name)
            .collect()
    }

    /// The method called `name` with its defaults.
    pub fn by_name(name: &str) -> Option<Method> {
        if let Some(s) = spec_named(area::METHODS, name) {
            let area = (s.default)();
            return Some(match area {
                AreaMethod::Quadrature => Method::default(),
                AreaMethod::RepresentativePoint => Method::representative_point(),
            });
        }
        if let Some(s) = spec_named(shadow::METHODS, name) {
            return Some(Method::shadowed((s.default)()));
        }
        if let Some(s) = spec_named(detail::METHODS, name) {
            return Some(Method::detailed((s.default)()));
        }
        if let Some(s) = spec_named(texture::METHODS, name) {
            return Some(Method::filtered((s.default)()));
        }
        if let Some(s) = spec_named(antialias::METHODS, name) {
            return Some(Method::antialiased((s.default)()));
        }
        if let Some(s) = spec_named(shading::METHODS, name) {
            return Some(Method {
                shading: Some((s.default)()),
                ..Method::quadrature_8()
            });
        }
        if let Some(s) = spec_named(ssao::METHODS, name) {
            return Some(Method {
                ssao: Some((s.default)()),
                ..Method::quadrature_8()
            });
        }
        if let Some(s) = spec_named(lightmap::METHODS, name) {
            return Some(Method {
                lightmap: Some((s.default)()),
                ..Method::quadrature_8()
            });
        }
        if let Some(s) = spec_named(energy::METHODS, name) {
            return Some(Method {
                energy: Some((s.default)()),
                ..Method::quadrature_8()
            });
        }
        spec_named(envmap::METHODS, name)
            .or_else(|| spec_named(distance_impostor::METHODS, name))
            .map(|s| Method::environment_mapped((s.default)()))
    }

    /// `area_quadrature` with the given N (environment N 8).
    pub fn quadrature(n: u32) -> Self {
        Method {
            area_n: n,
            ..Method::default()
        }
    }

    /// `area_representative_point` (environment N 8).
    pub fn representative_point() -> Self {
        Method {
            area: AreaMethod::RepresentativePoint,
            ..Method::default()
        }
    }

    /// The shadow method `shadow` over N×N quadrature with the shadow methods' defaults
    /// (n = 8, env_n = 0).
    pub fn shadowed(shadow: Shadow) -> Self {
        Method {
            area: AreaMethod::Quadrature,
            area_n: 8,
            env_n: 0,
            mesh_n: 0,
            shadow: Some(shadow),
            detail: None,
            envmap: None,
            texture: None,
            antialias: None,
            shading: None,
            lightmap: None,
            ssao: None,
            energy: None,
        }
    }

    /// N×N quadrature with n = 8, env_n = 8, unshadowed: what the detail, environment-mapping
    /// and texture-filtering methods are built on.
    fn quadrature_8() -> Self {
        Method {
            area_n: 8,
            ..Method::default()
        }
    }

    /// The surface-detail method `detail` over N×N quadrature (n = 8, env_n = 8), unshadowed.
    pub fn detailed(detail: Detail) -> Self {
        Method {
            detail: Some(detail),
            ..Method::quadrature_8()
        }
    }

    /// The environment-mapping method `envmap` over N×N quadrature (n = 8, env_n = 8),
    /// unshadowed, without surface detail.
    pub fn environment_mapped(envmap: EnvMapping) -> Self {
        Method {
            envmap: Some(envmap),
            ..Method::quadrature_8()
        }
    }

    /// The texture filter `texture` over N×N quadrature (n = 8, env_n = 8), unshadowed,
    /// without surface detail.
    pub fn filtered(texture: TextureFilter) -> Self {
        Method {
            texture: Some(texture),
            ..Method::quadrature_8()
        }
    }

    /// The anti-aliasing method `antialias` over N×N quadrature (n = 8, env_n = 8), unshadowed
    /// (`aa_specular_toksvig` with its textures filtered trilinearly).
    pub fn antialiased(antialias: AntiAliasing) -> Self {
        // Toksvig reads the shortening of MIP-filtered normals: its textures filter trilinearly.
        let texture = (antialias == AntiAliasing::SpecularToksvig)
            .then(|| TextureFilter::by_name("tex_trilinear"))
            .flatten();
        Method {
            antialias: Some(antialias),
            texture,
            ..Method::quadrature_8()
        }
    }

    /// The same method with environment quadrature N.
    pub fn with_env_n(self, env_n: u32) -> Self {
        Method { env_n, ..self }
    }

    /// Its parameter rows, in printing order: [`COMMON`], its family's shared rows, its own.
    pub fn rows(&self) -> Vec<Row> {
        let mut rows = Vec::new();
        if self.area == AreaMethod::Quadrature {
            rows.push(Row::Method(&COMMON[0]));
        }
        rows.push(Row::Method(&COMMON[1]));
        rows.push(Row::Method(&COMMON[2]));
        if let Some(s) = &self.shadow {
            rows.extend(s.rows().map(Row::Shadow));
        }
        if let Some(e) = &self.envmap {
            rows.extend(e.rows(envmap_spec(e)).map(Row::EnvMap));
            rows.push(Row::Method(&ENVMAP_DETAIL));
        }
        if let Some(d) = &self.detail {
            rows.extend(d.rows().map(Row::Detail));
        }
        if let Some(t) = &self.texture {
            rows.extend(t.rows().map(Row::Texture));
        }
        if let Some(a) = &self.antialias {
            rows.extend(a.rows().map(Row::AntiAlias));
        }
        if let Some(s) = &self.shading {
            rows.extend(s.rows().map(Row::Shading));
        }
        if let Some(l) = &self.lightmap {
            rows.extend(l.rows().map(Row::LightMap));
        }
        if let Some(a) = &self.ssao {
            rows.extend(a.rows().map(Row::Ssao));
        }
        if let Some(e) = &self.energy {
            rows.extend(e.rows().map(Row::Energy));
        }
        rows
    }

    /// Its row called `key`, if it has that parameter.
    pub fn row(&self, key: &str) -> Option<Row> {
        self.rows().into_iter().find(|r| r.name() == key)
    }

    /// The error for a parameter `key` it does not have, listing those it has.
    fn no_parameter(&self, key: &str) -> String {
        let names: Vec<&str> = self.rows().iter().map(Row::name).collect();
        format!(
            "method {} has no parameter `{key}`; parameters: {}",
            self.name(),
            names.join(", ")
        )
    }

    /// Sets parameter `key` to a typed `value`. Errors name the parameter and what it
    /// accepts (or the parameters this method has).
    pub fn set_param(&mut self, key: &str, value: Value) -> Result<(), String> {
        let row = self.row(key).ok_or_else(|| self.no_parameter(key))?;
        let refused = || format!("parameter {key} = `{value}`: expected {}", row.kind().describe());
        if !row.kind().accepts(&value) {
            return Err(refused());
        }
        row.set(self, value.clone()).ok_or_else(refused)
    }

    /// The method called `name` with `params` (`key`, `value`) applied over its defaults.
    /// Errors name the method or parameter and list what is accepted.
    pub fn parse(name: &str, params: &[(String, String)]) -> Result<Method, String> {
        let mut m = Method::by_name(name)
            .ok_or_else(|| format!("unknown method `{name}`; methods: {}", Method::names().join(", ")))?;
        // An environment map's `detail` first: it decides which detail parameters exist.
        let (first, rest): (Vec<_>, Vec<_>) = params.iter().partition(|(k, _)| k == "detail");
        for (key, text) in first.into_iter().chain(rest) {
            let row = m.row(key).ok_or_else(|| m.no_parameter(key))?;
            let value = row
                .kind()
                .parse(text)
                .ok_or_else(|| format!("parameter {key} = `{text}`: expected {}", row.kind().describe()))?;
            m.set_param(key, value)
                .map_err(|_| format!("parameter {key} = `{text}`: expected {}", row.kind().describe()))?;
        }
        Ok(m)
    }

    /// Checks every parameter against the ranges `parse` accepts (for methods built in code).
    pub fn validate(&self) -> Result<(), String> {
        for row in self.rows() {
            if let Some(value) = row.get(self) {
                if !row.kind().accepts(&value) {
                    return Err(format!(
                        "method {self}: parameter {} = {value}: expected {}",
                        row.name(),
                        row.kind().describe()
                    ));
                }
            }
        }
        Ok(())
    }

    /// The method's name.
    pub fn name(&self) -> &'static str {
        if let Some(e) = &self.energy {
            return e.spec().name;
        }
        if let Some(a) = &self.ssao {
            return a.spec().name;
        }
        if let Some(l) = &self.lightmap {
            return l.spec().name;
        }
        if let Some(s) = self.shading {
            return s.spec().name;
        }
        if let Some(a) = &self.antialias {
            return a.spec().name;
        }
        if let Some(t) = &self.texture {
            return t.spec().name;
        }
        if let Some(e) = &self.envmap {
            return envmap_spec(e).name;
        }
        if let Some(d) = &self.detail {
            return d.technique.name();
        }
        match (self.shadow, self.area) {
            (Some(s), _) => s.technique.name(),
            (None, area) => area::METHODS[area.shader_code() as usize].name,
        }
    }

    /// WGSL `ENERGY_METHOD` (and `frame.energy.x`): `ENERGY_NONE` … `ENERGY_FDEZ_AGUERA` (none:
    /// single scattering).
    pub fn energy_code(&self) -> u32 {
        self.energy.map_or(0, |e| e.shader_code())
    }

    /// WGSL `SHADING_FREQUENCY` (0: per pixel) in the low byte, `VERTEX_ALBEDO` above it.
    pub fn shading_code(&self) -> u32 {
        self.shading.map_or(0, |s| s.shader_code() | s.albedo_code() << 8)
    }

    /// The WGSL `LIGHTMAP_METHOD` of this method (0: no light map) in the low byte,
    /// `LIGHTMAP_SPECULAR` above it.
    pub fn lightmap_code(&self) -> u32 {
        self.lightmap.as_ref().map_or(0, LightMapMethod::pipeline_code)
    }

    /// The WGSL `SHADOW_METHOD` of this method (0: unshadowed).
    pub fn shadow_code(&self) -> u32 {
        self.shadow
            .map_or(shadow::SHADOW_NONE, |s| s.technique.shader_code())
    }

    /// The WGSL `DETAIL_METHOD` of this method (0: displaced shapes drawn flat).
    pub fn detail_code(&self) -> u32 {
        self.detail.map_or(0, |d| d.technique.shader_code())
    }

    /// The texture filter its lookups use.
    pub fn texture_filter(&self) -> TextureFilter {
        self.texture.unwrap_or(TextureFilter::BILINEAR)
    }

    /// The WGSL `ENVMAP_METHOD` of this method (0: no environment map).
    pub fn envmap_code(&self) -> u32 {
        self.envmap
            .as_ref()
            .map_or(0, |e| e.parameterization.shader_code())
    }

    /// Its parameters as `k=v` pairs (for headers and the timing line); unset optional
    /// parameters are left out.
    pub fn params(&self) -> Vec<(String, String)> {
        self.rows()
            .iter()
            .filter_map(|r| r.get(self).map(|v| (r.name().to_string(), v.to_string())))
            .collect()
    }
}

impl fmt::Display for Method {
    /// `name(k=v, …)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let params: Vec<String> = self.params().iter().map(|(k, v)| format!("{k}={v}")).collect();
        write!(f, "{}({})", self.name(), params.join(", "))
    }
}

/// The rows of `m` that are neither [`COMMON`]'s nor in its family's `shared`.
fn own_rows(m: &Method, shared: &[Row]) -> Vec<Row> {
    m.rows()
        .into_iter()
        .filter(|r| !matches!(r, Row::Method(p) if COMMON.iter().any(|c| std::ptr::eq(c, *p))))
        .filter(|r| !shared.iter().any(|s| s.name() == r.name()))
        .collect()
}

/// A row's default in `m` as a table cell: the value, or what unset means.
fn default_cell(row: &Row, m: &Method) -> String {
    match row.get(m) {
        Some(v) => format!("`{v}`"),
        None => row.unset().to_string(),
    }
}

/// One table row of parameter `row` with its default in `m`.
fn markdown_row(row: &Row, m: &Method) -> String {
    let what = match row.source() {
        "" => row.doc().to_string(),
        source => format!("{} ({source})", row.doc()),
    };
    format!(
        "| `{}` | {} | {} | {} | {} |\n",
        row.name(),
        row.kind().range(),
        default_cell(row, m),
        row.unit(),
        what
    )
}

const PARAM_HEADER: &str = "| parameter | accepts | default | unit | what |\n|---|---|---|---|---|\n";

/// docs/methods.md: every family, method and parameter, from the tables. A test compares the
/// file with this (`VERITY_BLESS=1 cargo test -p realtime methods_doc` rewrites it).
pub fn markdown() -> String {
    let mut s = String::from(
        "# Methods and their parameters\n\n\
         <!-- Generated from the parameter tables in realtime/src/technique/ by `markdown()`; \
         do not edit: `VERITY_BLESS=1 cargo test -p realtime methods_doc` rewrites it. -->\n\n\
         `verity raster --method NAME --param K=V` and a study's `[[variant]]` (`method`, `params`) \
         take these names and values. Every method takes `n` (not `area_representative_point`) \
         and `env_n`, then its family's shared parameters, then its own; a method prints as \
         `name(k=v, …)` in the EXR header, the timing line and metrics.json, unset optional \
         parameters left out.\n\n",
    );
    s += "## Every method\n\n";
    s += PARAM_HEADER;
    let quadrature = Method::default();
    for row in COMMON {
        s += &markdown_row(&Row::Method(row), &quadrature);
    }
    s += "\nDefaults of `n` / `env_n` by family: ";
    let defaults: Vec<String> = Family::ALL
        .iter()
        .map(|f| {
            let m = Method::by_name(f.methods()[0].name).expect("a family's method parses");
            format!("{} {} / {}", f.title().to_lowercase(), m.area_n, m.env_n)
        })
        .collect();
    s += &defaults.join("; ");
    s += ".\n";
    for family in Family::ALL {
        let methods = family.methods();
        s += &format!(
            "\n## {}\n\n| method | what | paper |\n|---|---|---|\n",
            family.title()
        );
        for m in &methods {
            s += &format!("| `{}` | {} | {} |\n", m.name, m.summary, m.source);
        }
        let first = Method::by_name(methods[0].name).expect("a family's method parses");
        let shared = family.shared_rows();
        if !shared.is_empty() {
            s += "\nParameters of every method of the family:\n\n";
            s += PARAM_HEADER;
            for row in &shared {
                s += &markdown_row(row, &first);
            }
        }
        for info in &methods {
            let m = Method::by_name(info.name).expect("a listed method parses");
            let own = own_rows(&m, &shared);
            if own.is_empty() {
                continue;
            }
            s += &format!("\n`{}`'s own:\n\n", info.name);
            s += PARAM_HEADER;
            for row in &own {
                s += &markdown_row(row, &m);
            }
        }
    }
    s
}

/// One line per family for `verity raster --help`'s `--method`: the method names and papers.
pub fn method_help() -> String {
    Family::ALL
        .iter()
        .map(|f| {
            let names: Vec<&str> = f.methods().iter().map(|m| m.name).collect();
            format!("{}: {}.", f.title(), names.join(", "))
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `k=default (accepts unit)` of each row (`k (unset: …; accepts unit)` for optional ones).
fn help_rows(rows: &[Row], m: &Method) -> String {
    rows.iter()
        .map(|r| {
            let accepts = match r.unit() {
                "" => r.kind().range(),
                unit => format!("{} {unit}", r.kind().range()),
            };
            match r.get(m) {
                Some(v) => format!("{}={v} ({accepts})", r.name()),
                None => format!("{} (unset: {}; {accepts})", r.name(), r.unset()),
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// `verity raster --help`'s `--param`: every parameter with its default and range, family by
/// family, then each method's own (full text: docs/methods.md).
pub fn param_help() -> String {
    let every: Vec<String> = COMMON
        .iter()
        .map(|r| format!("{} ({})", r.name, r.kind.range()))
        .collect();
    let mut lines = vec![format!(
        "Every method: {} (area_representative_point has no n); their defaults by family:",
        every.join(", ")
    )];
    for family in Family::ALL {
        let methods = family.methods();
        let first = Method::by_name(methods[0].name).expect("a family's method parses");
        let shared = family.shared_rows();
        let mut line = format!("{}: n={}, env_n={}", family.title(), first.area_n, first.env_n);
        if !shared.is_empty() {
            line += &format!("; {}", help_rows(&shared, &first));
        }
        for info in &methods {
            let m = Method::by_name(info.name).expect("a listed method parses");
            let own = own_rows(&m, &shared);
            if !own.is_empty() {
                line += &format!("; {}: {}", info.name, help_rows(&own, &m));
            }
        }
        lines.push(line + ".");
    }
    lines.join("\n")
}

/// The WGSL constants naming every method's code, written here once and put ahead of the
/// shader module's sources (pipelines.rs `shader_source`): the values of the override
/// constants `AREA_METHOD` (`AREA_QUADRATURE` …), `SHADOW_METHOD` (`SHADOW_NONE`,
/// `SHADOW_HARD` …), `DETAIL_METHOD` (`DETAIL_FLAT`, `DETAIL_NORMAL_MAPPING` …) and
/// `ENVMAP_METHOD` (`ENVMAP_NONE`, `ENVMAP_CUBE` …), each a family's prefix and its method's
/// name in capitals, numbered in table order.
pub fn wgsl_codes() -> String {
    fn family<T>(out: &mut String, prefix: &str, none: Option<&str>, specs: &'static [MethodSpec<T>]) {
        let first = match none {
            Some(none) => {
                *out += &format!("const {prefix}{none}: u32 = 0u;\n");
                1
            }
            None => 0,
        };
        for (i, spec) in specs.iter().enumerate() {
            let name = spec.name.to_uppercase();
            let name = name.strip_prefix(prefix).unwrap_or(&name);
            *out += &format!("const {prefix}{name}: u32 = {}u;\n", first + i);
        }
    }
    let mut s = String::from("// Generated by realtime::technique::wgsl_codes() from the method tables.\n");
    family(&mut s, "AREA_", None, area::METHODS);
    family(&mut s, "SHADOW_", Some("NONE"), shadow::METHODS);
    family(&mut s, "DETAIL_", Some("FLAT"), detail::METHODS);
    family(&mut s, "ENVMAP_", Some("NONE"), envmap::METHODS);
    family(&mut s, "TEX_", None, texture::METHODS);
    family(&mut s, "SHADING_", None, shading::METHODS);
    family(&mut s, "LIGHTMAP_", Some("NONE"), lightmap::METHODS);
    family(&mut s, "ENERGY_", None, energy::METHODS);
    s += &shading::wgsl_codes();
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadow::ShadowTechnique;

    fn kv(k: &str, v: &str) -> (String, String) {
        (k.to_string(), v.to_string())
    }

    #[test]
    fn parse_applies_parameters_over_defaults() {
        let m = Method::parse("area_quadrature", &[kv("n", "4"), kv("env_n", "0")]).unwrap();
        assert_eq!(m, Method::quadrature(4).with_env_n(0));
        assert_eq!(m.to_string(), "area_quadrature(n=4, env_n=0)");
        let r = Method::parse("area_representative_point", &[]).unwrap();
        assert_eq!(r.to_string(), "area_representative_point(env_n=8)");
    }

    #[test]
    fn parse_rejects_bad_names_and_values() {
        let e = Method::parse("pcss_fixed", &[]).unwrap_err();
        assert!(e.contains("area_quadrature") && e.contains("pcss"), "{e}");
        let e = Method::parse("area_representative_point", &[kv("n", "4")]).unwrap_err();
        assert!(e.contains("no parameter `n`") && e.contains("env_n"), "{e}");
        for bad in ["0", "65", "-1", "x", "2.5"] {
            assert!(
                Method::parse("area_quadrature", &[kv("n", bad)]).is_err(),
                "n={bad}"
            );
        }
        assert!(Method::parse("area_quadrature", &[kv("env_n", "0")]).is_ok());
        let e = Method::parse("area_quadrature", &[kv("map", "512")]).unwrap_err();
        assert!(e.contains("no parameter `map`"), "{e}");
    }

    /// Every shadow method's defaults as the method table lists them, and names round-trip.
    #[test]
    fn shadow_methods_have_the_documented_defaults() {
        let common =
            "n=8, env_n=0, map=1024, bias=0.002, slope_bias=1, normal_offset=1, cascades=1, split_lambda=0.5, point_maps=frustum";
        for (name, own) in [
            ("shadow_hard", ""),
            ("pcf_hw_2x2", ""),
            ("pcf_box", ", kernel=3, receiver_plane=on"),
            ("pcf_poisson", ", taps=16, radius=2, receiver_plane=on, rotate=off"),
            (
                "pcss",
                ", blocker_samples=16, filter_samples=32, blocker_depth=search, receiver_plane=on, rotate=off",
            ),
        ] {
            let m = Method::parse(name, &[]).unwrap();
            assert_eq!(m.to_string(), format!("{name}({common}{own})"));
            assert_eq!(m.name(), name);
            assert!(m.validate().is_ok());
            // The header's parameter list parses back to the same method.
            assert_eq!(Method::parse(name, &m.params()).unwrap(), m);
            assert_eq!(m.area, AreaMethod::Quadrature);
        }
        let codes: Vec<u32> = Method::names()
            .iter()
            .map(|n| Method::parse(n, &[]).unwrap().shadow_code())
            .collect();
        assert_eq!(
            codes,
            [
                0, 0, 1, 2, 3, 4, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0
            ]
        );
    }

    #[test]
    fn shadow_parameters_are_range_checked() {
        let ok = |name: &str, k: &str, v: &str| Method::parse(name, &[kv(k, v)]).is_ok();
        assert!(
            ok("pcf_box", "kernel", "5") && !ok("pcf_box", "kernel", "4") && !ok("pcf_box", "kernel", "7")
        );
        assert!(
            ok("pcf_poisson", "taps", "64")
                && !ok("pcf_poisson", "taps", "0")
                && !ok("pcf_poisson", "taps", "65")
        );
        assert!(ok("pcf_poisson", "radius", "0.5") && !ok("pcf_poisson", "radius", "-1"));
        assert!(ok("shadow_hard", "map", "64") && ok("shadow_hard", "map", "4096"));
        assert!(!ok("shadow_hard", "map", "32") && !ok("shadow_hard", "map", "8192"));
        assert!(
            ok("shadow_hard", "bias", "0")
                && !ok("shadow_hard", "bias", "NaN")
                && !ok("shadow_hard", "bias", "inf")
        );
        assert!(!ok("shadow_hard", "kernel", "3"), "kernel is pcf_box's");
        assert!(ok("pcss", "blocker_depth", "ignore") && !ok("pcss", "blocker_depth", "fixed"));
        let m = Method::parse("pcss", &[kv("light_size", "0.25"), kv("blocker_depth", "ignore")]).unwrap();
        assert!(
            m.to_string()
                .ends_with("light_size=0.25, blocker_depth=ignore, receiver_plane=on, rotate=off)"),
            "{m}"
        );
        assert!(ok("pcf_box", "receiver_plane", "off") && !ok("pcf_hw_2x2", "receiver_plane", "off"));
        let off = Method::parse("pcss", &[kv("receiver_plane", "false")]).unwrap();
        assert!(
            off.to_string().ends_with("receiver_plane=off, rotate=off)"),
            "{off}"
        );
        let e = Method::parse("pcf_box", &[kv("kernel", "4")]).unwrap_err();
        assert!(e.contains("kernel") && e.contains("one of 3, 5"), "{e}");
        let e = Method::parse("pcss", &[kv("radius", "1")]).unwrap_err();
        assert!(e.contains("blocker_samples") && e.contains("light_size"), "{e}");
        let mut bad = Method::parse("pcf_poisson", &[]).unwrap();
        bad.shadow = Some(Shadow::new(ShadowTechnique::PcfPoisson {
            taps: 99,
            radius: 1.0,
        }));
        assert!(bad.validate().unwrap_err().contains("taps"));
    }

    /// `cascades` and `split_lambda` on every shadow method, `rotate` on the Poisson-tap ones,
    /// each range-checked with the accepted values in the error.
    #[test]
    fn cascade_and_rotation_parameters() {
        let ok = |name: &str, k: &str, v: &str| Method::parse(name, &[kv(k, v)]).is_ok();
        for name in ["shadow_hard", "pcf_hw_2x2", "pcf_box", "pcf_poisson", "pcss"] {
            assert!(ok(name, "cascades", "1") && ok(name, "cascades", "4"), "{name}");
            assert!(!ok(name, "cascades", "0") && !ok(name, "cascades", "5"), "{name}");
            assert!(
                ok(name, "split_lambda", "0") && ok(name, "split_lambda", "1"),
                "{name}"
            );
            assert!(
                !ok(name, "split_lambda", "1.5") && !ok(name, "split_lambda", "NaN"),
                "{name}"
            );
        }
        assert!(!ok("area_quadrature", "cascades", "2"));
        for name in ["pcf_poisson", "pcss"] {
            assert!(ok(name, "rotate", "on") && ok(name, "rotate", "true") && !ok(name, "rotate", "yes"));
        }
        for name in ["shadow_hard", "pcf_hw_2x2", "pcf_box"] {
            assert!(!ok(name, "rotate", "on"), "{name} has no Poisson taps to rotate");
        }
        let e = Method::parse("pcss", &[kv("cascades", "8")]).unwrap_err();
        assert!(e.contains("cascades") && e.contains("1..=4"), "{e}");
        let e = Method::parse("pcf_box", &[kv("rotate", "on")]).unwrap_err();
        assert!(e.contains("no parameter `rotate`"), "{e}");
        let m = Method::parse(
            "pcss",
            &[kv("cascades", "3"), kv("split_lambda", "0.9"), kv("rotate", "on")],
        )
        .unwrap();
        let s = m.shadow.unwrap();
        assert_eq!((s.cascades, s.split_lambda, s.rotate), (3, 0.9, true));
        assert_eq!(Method::parse("pcss", &m.params()).unwrap(), m);
    }

    /// Every detail method parses with its defaults, round-trips through its parameter list,
    /// and range-checks its own parameters only.
    #[test]
    fn detail_methods_have_the_documented_defaults() {
        for (name, own) in [
            ("normal_mapping", ""),
            ("bump_mapping", ", delta=1"),
            ("parallax", ", bias=0"),
            ("parallax_offset_limited", ", bias=0"),
            ("steep_parallax", ", steps=16"),
            ("relief_mapping", ", steps=16, binary_steps=6"),
            (
                "pom",
                ", min_steps=8, max_steps=32, self_shadow=off, shadow_steps=16",
            ),
            ("cone_step", ", steps=32, relaxed=off, binary_steps=6"),
        ] {
            let m = Method::parse(name, &[]).unwrap();
            assert_eq!(
                m.to_string(),
                format!("{name}(n=8, env_n=8, height_scale=1{own})")
            );
            assert_eq!(m.name(), name);
            assert_eq!(Method::parse(name, &m.params()).unwrap(), m);
            assert!(m.validate().is_ok() && m.shadow.is_none() && m.detail_code() > 0);
        }
        let ok = |name: &str, k: &str, v: &str| Method::parse(name, &[kv(k, v)]).is_ok();
        assert!(ok("pom", "self_shadow", "on") && !ok("pom", "self_shadow", "soft"));
        assert!(
            ok("pom", "max_steps", "256") && !ok("pom", "max_steps", "257") && !ok("pom", "min_steps", "0")
        );
        assert!(ok("relief_mapping", "binary_steps", "0") && !ok("relief_mapping", "binary_steps", "17"));
        assert!(ok("cone_step", "relaxed", "on") && !ok("steep_parallax", "relaxed", "on"));
        assert!(ok("parallax", "bias", "-0.5") && !ok("parallax", "bias", "2"));
        assert!(
            !ok("normal_mapping", "steps", "8"),
            "normal mapping does not march"
        );
        assert!(!ok("pcss", "height_scale", "1") && !ok("parallax", "height_scale", "-1"));
        let e = Method::parse("bump_mapping", &[kv("delta", "0")]).unwrap_err();
        assert!(e.contains("delta") && e.contains("[0.01, 16]"), "{e}");
        let m = Method::parse("cone_step", &[kv("relaxed", "true"), kv("height_scale", "0.5")]).unwrap();
        let d = m.detail.unwrap();
        assert_eq!(d.height_scale, 0.5);
        assert_eq!(d.technique.cone_kind(), Some(detail::cone_map::ConeKind::Relaxed));
    }

    /// docs/methods.md is what the tables say (`VERITY_BLESS=1` rewrites it).
    #[test]
    fn methods_doc_is_current() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/methods.md");
        let want = markdown();
        if std::env::var_os("VERITY_BLESS").is_some() {
            std::fs::write(&path, &want).unwrap();
        }
        let have = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            have == want,
            "docs/methods.md differs from the parameter tables in realtime/src/technique/: \
             run `VERITY_BLESS=1 cargo test -p realtime methods_doc` and commit the file"
        );
        // The README describes every method and sends readers to the tables for the values.
        let readme =
            std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md"))
                .unwrap();
        assert!(
            readme.contains("(docs/methods.md)"),
            "README.md does not link docs/methods.md"
        );
        for name in Method::names() {
            assert!(
                readme.contains(&format!("| `{name}`")),
                "README.md has no table row for {name}"
            );
        }
    }

    /// Every row of every method: a distinct name, a doc, a default its kind accepts that
    /// prints and parses back (or, unset, the text saying what unset means).
    #[test]
    fn every_row_has_a_default_that_round_trips() {
        for name in Method::names() {
            let m = Method::parse(name, &[]).unwrap();
            assert_eq!(m.name(), name);
            assert!(m.validate().is_ok(), "{name}");
            assert_eq!(Method::parse(name, &m.params()).unwrap(), m, "{name}");
            let rows = m.rows();
            for (i, row) in rows.iter().enumerate() {
                assert!(
                    rows[..i].iter().all(|r| r.name() != row.name()),
                    "{name}: {} twice",
                    row.name()
                );
                assert!(!row.doc().is_empty(), "{name}: {} has no doc", row.name());
                match row.get(&m) {
                    Some(v) => {
                        assert!(row.kind().accepts(&v), "{name}: {} = {v}", row.name());
                        assert_eq!(
                            row.kind().parse(&v.to_string()),
                            Some(v),
                            "{name}: {}",
                            row.name()
                        );
                    }
                    None => assert!(
                        !row.unset().is_empty(),
                        "{name}: {} unset unexplained",
                        row.name()
                    ),
                }
            }
        }
    }

    /// Typed parameters go through the same range checks as text.
    #[test]
    fn typed_parameters_are_range_checked() {
        let mut m = Method::parse("pcf_poisson", &[]).unwrap();
        m.set_param("taps", Value::Whole(32)).unwrap();
        assert!(m
            .set_param("taps", Value::Whole(65))
            .unwrap_err()
            .contains("1..=64"));
        assert!(m.set_param("radius", Value::Real(f32::NAN)).is_err());
        assert!(
            m.set_param("radius", Value::Whole(1)).is_err(),
            "kinds do not mix"
        );
        assert!(m
            .set_param("kernel", Value::Whole(3))
            .unwrap_err()
            .contains("no parameter"));
        let mut e = Method::parse("envmap_sphere", &[]).unwrap();
        assert!(e
            .set_param("sphere_view", Value::Vector(glam::Vec3::ZERO))
            .is_err());
        e.set_param("detail", Value::Keyword("pom")).unwrap();
        e.set_param("max_steps", Value::Whole(64)).unwrap();
        assert!(
            e.to_string().ends_with(
                "detail=pom, height_scale=1, min_steps=8, max_steps=64, self_shadow=off, shadow_steps=16)"
            ),
            "{e}"
        );
    }

    /// The codes the shaders switch on are the tables' order: each spec's default has the
    /// code `wgsl_codes` names it by.
    #[test]
    fn shader_codes_follow_the_tables() {
        let codes = wgsl_codes();
        let has = |line: String| assert!(codes.contains(&line), "{line} missing from\n{codes}");
        for (i, s) in area::METHODS.iter().enumerate() {
            assert_eq!((s.default)().shader_code() as usize, i);
        }
        for (i, s) in shadow::METHODS.iter().enumerate() {
            assert_eq!((s.default)().technique.shader_code() as usize, i + 1);
        }
        for (i, s) in detail::METHODS.iter().enumerate() {
            assert_eq!((s.default)().technique.shader_code() as usize, i + 1);
        }
        for (i, s) in envmap::METHODS.iter().enumerate() {
            assert_eq!((s.default)().parameterization.shader_code() as usize, i + 1);
        }
        has("const AREA_REPRESENTATIVE_POINT: u32 = 1u;".into());
        has("const SHADOW_NONE: u32 = 0u;".into());
        has("const SHADOW_HARD: u32 = 1u;".into());
        has("const SHADOW_PCF_HW_2X2: u32 = 2u;".into());
        has("const DETAIL_CONE_STEP: u32 = 8u;".into());
        has("const ENVMAP_PARABOLOID: u32 = 3u;".into());
    }
}
