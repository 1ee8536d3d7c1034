//! A method: the frame configuration one render uses, and the interface through which the
//! families plug into it.
//!
//! A [`Method`] holds what every method has (the area-light technique and the quadratures,
//! [`COMMON`]) and, for each family it uses, that family's settings as a
//! [`Settings`] trait object: a shadow-mapped method holds a `Shadow`, an environment-mapped one
//! an `EnvMapping` and perhaps a `Detail` (environment-mapped normal mapping), `aa_specular_toksvig`
//! an `AntiAliasing` and the trilinear `TextureFilter` it reads. This is a bevy camera with one
//! optional settings component per effect: the core asks for a family's settings by type
//! ([`Method::get`]) and never names a family itself.
//!
//! A family is a [`Family`] (its methods, their defaults, its docs and its WGSL method codes),
//! registered by one line in [`super::FAMILIES`]; its settings type implements [`Settings`]
//! (its parameter rows, the WGSL override constants it sets, the frame configurations it
//! refuses). The method's name is its primary part's, the part the method was looked up by,
//! not found by a priority chain.

use std::any::{Any, TypeId};
use std::fmt;

use super::area::{AreaMethod, METHODS as AREA_METHODS};
use super::param::{spec_named, Kind, MethodSpec, Param, Value};

/// Largest `n` / `env_n` accepted (N² samples per light per pixel).
pub const MAX_QUADRATURE_N: u32 = 64;

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

/// Which pipelines an override constant applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Applies {
    /// Every pipeline that draws the camera's view (G-buffer, background, forward, lighting):
    /// constants that move the surface itself (surface detail, texture derivatives).
    Geometry,
    /// The pipelines that shade (forward, lighting, the visibility AOV).
    Shading,
}

/// A WGSL override constant a method sets, by name: pipelines are specialised on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Override {
    /// The WGSL `override` it sets (its default in the WGSL is the family's "none").
    pub name: &'static str,
    /// Its value.
    pub value: u32,
    /// The pipelines it applies to.
    pub applies: Applies,
}

impl Override {
    /// `name = value` in the shading pipelines.
    pub fn shading(name: &'static str, value: u32) -> Override {
        Override {
            name,
            value,
            applies: Applies::Shading,
        }
    }

    /// `name = value` in every pipeline that draws the camera's view.
    pub fn geometry(name: &'static str, value: u32) -> Override {
        Override {
            name,
            value,
            applies: Applies::Geometry,
        }
    }
}

/// What a family's [`Settings::check`] may refuse a method for: the frame it is rendered in.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Deferred shading (a G-buffer and a lighting pass), or forward.
    pub deferred: bool,
    /// The adapter's largest texture side.
    pub max_texture_side: u32,
    /// The MSAA sample counts the adapter renders the targets with.
    pub msaa_counts: &'a [u32],
}

/// One family's settings in a [`Method`].
pub trait Settings: SettingsObject + fmt::Debug + Send + Sync + 'static {
    /// The name of the method these settings make, when they are the method's primary part.
    fn method_name(&self) -> &'static str;

    /// Its parameter rows, in printing order (the family's shared ones, then its method's own).
    fn rows(&self) -> Vec<Row>;

    /// The WGSL override constants it sets (those it leaves at their WGSL default are left
    /// out).
    fn overrides(&self) -> Vec<Override>;

    /// Refuses a frame it cannot be rendered in, with the reason (after the parameters' own
    /// range checks have passed). The method's printed form `method` is for the message.
    fn check(&self, _method: &Method, _frame: &Frame<'_>) -> Result<(), String> {
        Ok(())
    }

    /// Bytes it allocates before the frame (budget checks; 0 unless it allocates much).
    fn bytes(&self) -> u64 {
        0
    }

    /// Its multiplier of the target's samples per pixel axis (supersampling; 1 by default).
    fn supersampling(&self) -> u32 {
        1
    }

    /// Samples per pixel of the multisampled targets (1: none).
    fn msaa_samples(&self) -> u32 {
        1
    }
}

/// Cloning, comparing and downcasting a [`Settings`] behind a box; implemented for every
/// settings type that is `Clone + PartialEq`.
pub trait SettingsObject {
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn Settings>;
    /// Whether `other` is of the same type and equal.
    fn eq_box(&self, other: &dyn Settings) -> bool;
    /// For [`Method::get`].
    fn as_any(&self) -> &dyn Any;
    /// For [`Method::get_mut`].
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<T: Settings + Clone + PartialEq> SettingsObject for T {
    fn clone_box(&self) -> Box<dyn Settings> {
        Box::new(self.clone())
    }

    fn eq_box(&self, other: &dyn Settings) -> bool {
        other.as_any().downcast_ref::<T>() == Some(self)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// A family of methods, registered in [`super::FAMILIES`].
pub trait Family: Sync {
    /// Its heading in the docs.
    fn title(&self) -> &'static str;

    /// Its methods' names, summaries and papers, in table order.
    fn methods(&self) -> Vec<MethodInfo>;

    /// The method called `name` with the defaults it runs with, if it is one of this
    /// family's.
    fn method(&self, name: &str) -> Option<Method>;

    /// The rows its methods share after [`COMMON`] (none by default).
    fn shared_rows(&self) -> Vec<Row> {
        Vec::new()
    }

    /// The WGSL constants naming its methods' codes (`SHADOW_NONE`, `SHADOW_HARD`, …), or "".
    fn wgsl_codes(&self) -> String {
        String::new()
    }

    /// Its block of the frame uniform (WGSL `frame.families.<field>`), or None: the values its
    /// shaders read by name.
    fn uniforms(&self) -> Option<UniformBlock> {
        None
    }

    /// Its WGSL files that join the shading module, beside its Rust (name, source): its
    /// override constants, its uniforms' readers and the functions the shared shading code
    /// calls (none by default: a family whose passes are shader modules of their own).
    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[]
    }
}

/// A family's block of the frame uniform: a `#[repr(C)]` struct of its own, mirrored by a
/// WGSL struct in its files, so that its parameters keep their names down to the shader
/// (`frame.families.detail.height_scale`). The frame uniform's buffer is the core
/// `FrameUniforms` followed by every family's block in registry order, each at a 16-byte
/// boundary (WGSL's uniform layout for members of struct type, written `@align(16)` in the
/// generated `FamilyUniforms`, [`super::wgsl_codes`]).
#[derive(Clone, Copy, Debug)]
pub struct UniformBlock {
    /// Its field of WGSL `FamilyUniforms`.
    pub field: &'static str,
    /// Its WGSL struct's name.
    pub wgsl_type: &'static str,
    /// The Rust struct's size in bytes (checked against the WGSL struct's).
    pub size: usize,
    /// Its bytes for a method (the family's defaults where the method does not use it).
    pub bytes: fn(&Method) -> Vec<u8>,
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

impl MethodInfo {
    /// The infos of a family's method table.
    pub fn of<T>(specs: &'static [MethodSpec<T>]) -> Vec<MethodInfo> {
        specs
            .iter()
            .map(|s| MethodInfo {
                name: s.name,
                summary: s.summary,
                source: s.source,
            })
            .collect()
    }
}

/// `const {prefix}{NAME}: u32 = …u;` for each method of `specs` (the method's name in capitals
/// without the prefix), numbered in table order from 1 after `{prefix}{none}` = 0, or from 0.
pub fn wgsl_method_codes<T>(prefix: &str, none: Option<&str>, specs: &'static [MethodSpec<T>]) -> String {
    let mut out = String::new();
    let first = match none {
        Some(none) => {
            out += &format!("const {prefix}{none}: u32 = 0u;\n");
            1
        }
        None => 0,
    };
    for (i, spec) in specs.iter().enumerate() {
        let name = spec.name.to_uppercase();
        let name = name.strip_prefix(prefix).unwrap_or(&name);
        out += &format!("const {prefix}{name}: u32 = {}u;\n", first + i);
    }
    out
}

/// One parameter row, whichever part of a method it reads and writes.
pub trait AnyParam: Sync {
    /// The row's table entry.
    fn param(&self) -> ParamDoc;
    /// Its value in `m` (None: unset, or not a row of `m`).
    fn get(&self, m: &Method) -> Option<Value>;
    /// Stores `value` (already accepted by its kind) in `m`; None if `m` cannot take it.
    fn set(&self, m: &mut Method, value: Value) -> Option<()>;
}

/// A row's name, kind, unit, doc, paper and unset meaning.
#[derive(Clone, Copy, Debug)]
pub struct ParamDoc {
    /// `--param NAME=…`.
    pub name: &'static str,
    /// What it accepts.
    pub kind: Kind,
    /// Unit of its values.
    pub unit: &'static str,
    /// One line: what it does.
    pub doc: &'static str,
    /// Its paper, or "".
    pub source: &'static str,
    /// What an unset optional parameter means, or "".
    pub unset: &'static str,
}

fn doc_of<T>(p: &Param<T>) -> ParamDoc {
    ParamDoc {
        name: p.name,
        kind: p.kind,
        unit: p.unit,
        doc: p.doc,
        source: p.source,
        unset: p.unset,
    }
}

/// A row of a family's settings `T`: read and written in the method's part of type `T`.
impl<T: Settings> AnyParam for Param<T> {
    fn param(&self) -> ParamDoc {
        doc_of(self)
    }

    fn get(&self, m: &Method) -> Option<Value> {
        m.get::<T>().and_then(|t| (self.get)(t))
    }

    fn set(&self, m: &mut Method, value: Value) -> Option<()> {
        (self.set)(m.get_mut::<T>()?, value)
    }
}

/// A row of the method itself ([`COMMON`], an environment map's `detail`).
impl AnyParam for Param<Method> {
    fn param(&self) -> ParamDoc {
        doc_of(self)
    }

    fn get(&self, m: &Method) -> Option<Value> {
        (self.get)(m)
    }

    fn set(&self, m: &mut Method, value: Value) -> Option<()> {
        (self.set)(m, value)
    }
}

/// One row of a method's table.
#[derive(Clone, Copy)]
pub struct Row(pub &'static dyn AnyParam);

impl Row {
    /// The rows of a family's table.
    pub fn all<T: 'static>(params: impl IntoIterator<Item = &'static Param<T>>) -> Vec<Row>
    where
        Param<T>: AnyParam,
    {
        params.into_iter().map(|p| Row(p)).collect()
    }

    /// `--param NAME=…`.
    pub fn name(&self) -> &'static str {
        self.0.param().name
    }

    /// What it accepts.
    pub fn kind(&self) -> Kind {
        self.0.param().kind
    }

    /// Unit of its values.
    pub fn unit(&self) -> &'static str {
        self.0.param().unit
    }

    /// One line: what it does.
    pub fn doc(&self) -> &'static str {
        self.0.param().doc
    }

    /// Its paper, or "".
    pub fn source(&self) -> &'static str {
        self.0.param().source
    }

    /// What an unset optional parameter means, or "".
    pub fn unset(&self) -> &'static str {
        self.0.param().unset
    }

    /// Its value in `m` (None: unset, or not a row of `m`).
    pub fn get(&self, m: &Method) -> Option<Value> {
        self.0.get(m)
    }

    /// Stores `value` (already accepted by its kind) in `m`; None if `m` cannot take it.
    fn set(&self, m: &mut Method, value: Value) -> Option<()> {
        self.0.set(m, value)
    }

    /// Whether it is the row `p`.
    pub fn is<T>(&self, p: &'static Param<T>) -> bool {
        std::ptr::addr_eq(self.0 as *const dyn AnyParam, p as *const Param<T>)
    }
}

/// A method with its parameters: the frame configuration of one render.
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
    /// The settings of each family the method uses besides the area lights, at most one per
    /// type, in the order the method was built (its rows print in that order).
    parts: Vec<Box<dyn Settings>>,
    /// The type of the part that names the method; None: the area-light technique does.
    primary: Option<TypeId>,
}

impl Clone for Method {
    fn clone(&self) -> Self {
        Method {
            area: self.area,
            area_n: self.area_n,
            env_n: self.env_n,
            mesh_n: self.mesh_n,
            parts: self.parts.iter().map(|p| p.clone_box()).collect(),
            primary: self.primary,
        }
    }
}

impl PartialEq for Method {
    /// The same common parameters, primary part and parts (in any order: there is at most one
    /// of each type).
    fn eq(&self, other: &Self) -> bool {
        (self.area, self.area_n, self.env_n, self.mesh_n, self.primary)
            == (other.area, other.area_n, other.env_n, other.mesh_n, other.primary)
            && self.parts.len() == other.parts.len()
            && self
                .parts
                .iter()
                .all(|p| other.parts.iter().any(|q| p.eq_box(q.as_ref())))
    }
}

impl fmt::Debug for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Method")
            .field("area", &self.area)
            .field("area_n", &self.area_n)
            .field("env_n", &self.env_n)
            .field("mesh_n", &self.mesh_n)
            .field("parts", &self.parts)
            .finish()
    }
}

impl Default for Method {
    /// `area_quadrature` with n = 16, env_n = 8.
    fn default() -> Self {
        Method {
            area: AreaMethod::Quadrature,
            area_n: 16,
            env_n: 8,
            mesh_n: 0,
            parts: Vec::new(),
            primary: None,
        }
    }
}

impl Method {
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

    /// The method `part` names, over N×N area quadrature with n = 8 and `env_n`, unshadowed:
    /// what every family but the area lights builds its methods on.
    pub fn of(part: impl Settings, env_n: u32) -> Self {
        Method {
            area_n: 8,
            env_n,
            ..Method::default()
        }
        .with_primary(part)
    }

    /// The method called `name` in a family's table `specs`, its settings at their defaults,
    /// as [`Method::of`] builds it; None if the table has no such method.
    pub fn from_table<T: Settings>(specs: &'static [MethodSpec<T>], name: &str, env_n: u32) -> Option<Self> {
        spec_named(specs, name).map(|s| Method::of((s.default)(), env_n))
    }

    /// The same method with `part` added (or put in place of its part of that type), named by
    /// it.
    pub fn with_primary<T: Settings>(mut self, part: T) -> Self {
        self.primary = Some(TypeId::of::<T>());
        self.with(part)
    }

    /// The same method with `part` added, or put in place of its part of that type.
    pub fn with<T: Settings>(mut self, part: T) -> Self {
        self.insert(part);
        self
    }

    /// Adds `part`, or puts it in place of the part of its type.
    pub fn insert<T: Settings>(&mut self, part: T) {
        match self.get_mut::<T>() {
            Some(p) => *p = part,
            None => self.parts.push(Box::new(part)),
        }
    }

    /// Removes the part of type `T` (the method is then named by its area-light technique if
    /// that part named it).
    pub fn remove<T: Settings>(&mut self) {
        self.parts.retain(|p| p.as_any().type_id() != TypeId::of::<T>());
        if self.primary == Some(TypeId::of::<T>()) {
            self.primary = None;
        }
    }

    /// The same method without its part of type `T`.
    pub fn without<T: Settings>(mut self) -> Self {
        self.remove::<T>();
        self
    }

    /// The same method with environment quadrature N.
    pub fn with_env_n(self, env_n: u32) -> Self {
        Method { env_n, ..self }
    }

    /// Its family settings of type `T`, if it uses that family.
    pub fn get<T: Settings>(&self) -> Option<&T> {
        self.parts.iter().find_map(|p| p.as_any().downcast_ref::<T>())
    }

    /// Its family settings of type `T`, mutable.
    pub fn get_mut<T: Settings>(&mut self) -> Option<&mut T> {
        self.parts
            .iter_mut()
            .find_map(|p| p.as_any_mut().downcast_mut::<T>())
    }

    /// Its family settings, in the order the method was built.
    pub fn parts(&self) -> impl Iterator<Item = &dyn Settings> {
        self.parts.iter().map(|p| p.as_ref())
    }

    /// The WGSL override constants of pipelines that draw `applies` (the area-light
    /// technique's `AREA_METHOD` and every part's), sorted by name.
    pub fn overrides(&self, applies: Applies) -> Vec<Override> {
        let mut o: Vec<Override> =
            std::iter::once(Override::geometry("AREA_METHOD", self.area.shader_code()))
                .chain(self.parts.iter().flat_map(|p| p.overrides()))
                .filter(|o| o.applies <= applies)
                .collect();
        o.sort();
        o
    }

    /// Its parameter rows, in printing order: [`COMMON`], then each part's.
    pub fn rows(&self) -> Vec<Row> {
        let common = &COMMON;
        let mut rows = Vec::new();
        if self.area == AreaMethod::Quadrature {
            rows.push(Row(&common[0]));
        }
        rows.push(Row(&common[1]));
        rows.push(Row(&common[2]));
        for p in &self.parts {
            rows.extend(p.rows());
        }
        rows
    }

    /// Its row called `key`, if it has that parameter.
    pub fn row(&self, key: &str) -> Option<Row> {
        self.rows().into_iter().find(|r| r.name() == key)
    }

    /// The error for a parameter `key` it does not have, listing those it has.
    pub(super) fn no_parameter(&self, key: &str) -> String {
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

    /// Checks the parameters' ranges, then asks each part whether it can be rendered in
    /// `frame`.
    pub fn check(&self, frame: &Frame<'_>) -> Result<(), String> {
        if !(1..=MAX_QUADRATURE_N).contains(&self.area_n) || self.env_n > MAX_QUADRATURE_N {
            return Err(format!(
                "method {self}: n must be in 1..={MAX_QUADRATURE_N} and env_n in 0..={MAX_QUADRATURE_N}"
            ));
        }
        self.validate()?;
        self.parts.iter().try_for_each(|p| p.check(self, frame))
    }

    /// The method's name: its primary part's, or its area-light technique's.
    pub fn name(&self) -> &'static str {
        let primary = self
            .primary
            .and_then(|id| self.parts.iter().find(|p| p.as_any().type_id() == id));
        match primary {
            Some(p) => p.method_name(),
            None => AREA_METHODS[self.area.shader_code() as usize].name,
        }
    }

    /// Its parameters as `k=v` pairs (for headers and the timing line); unset optional
    /// parameters are left out.
    pub fn params(&self) -> Vec<(String, String)> {
        self.rows()
            .iter()
            .filter_map(|r| r.get(self).map(|v| (r.name().to_string(), v.to_string())))
            .collect()
    }

    /// The product of its parts' supersampling factors.
    pub fn supersampling(&self) -> u32 {
        self.parts.iter().map(|p| p.supersampling()).product()
    }

    /// Samples per pixel of its multisampled targets (1: none).
    pub fn msaa_samples(&self) -> u32 {
        self.parts.iter().map(|p| p.msaa_samples()).max().unwrap_or(1)
    }

    /// Bytes its parts allocate before the frame.
    pub fn bytes(&self) -> u64 {
        self.parts.iter().map(|p| p.bytes()).fold(0, u64::saturating_add)
    }
}

impl fmt::Display for Method {
    /// `name(k=v, …)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let params: Vec<String> = self.params().iter().map(|(k, v)| format!("{k}={v}")).collect();
        write!(f, "{}({})", self.name(), params.join(", "))
    }
}

/// The area-light family ([`super::area`]): the base every method is built on, so it lives with
/// the method (its `n`, `env_n` and `mesh_n` are [`COMMON`]).
pub struct AreaLights;

impl Family for AreaLights {
    fn title(&self) -> &'static str {
        "Area lights"
    }

    fn methods(&self) -> Vec<MethodInfo> {
        MethodInfo::of(AREA_METHODS)
    }

    fn method(&self, name: &str) -> Option<Method> {
        Some(match (spec_named(AREA_METHODS, name)?.default)() {
            AreaMethod::Quadrature => Method::default(),
            AreaMethod::RepresentativePoint => Method::representative_point(),
        })
    }

    fn wgsl_codes(&self) -> String {
        wgsl_method_codes("AREA_", None, AREA_METHODS)
    }

    fn shading_sources(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("area/quadrature.wgsl", include_str!("area/quadrature.wgsl")),
            (
                "area/representative_point.wgsl",
                include_str!("area/representative_point.wgsl"),
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::technique::detail::Detail;
    use crate::technique::envmap::EnvMapping;
    use crate::technique::shadow::Shadow;

    fn parse(name: &str, params: &[(&str, &str)]) -> Method {
        let params: Vec<(String, String)> = params
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        Method::parse(name, &params).unwrap()
    }

    /// The geometry pipelines get the constants that move the surface, the shading ones every
    /// constant; each part's by name, sorted, the area technique's always.
    #[test]
    fn overrides_are_named_and_scoped() {
        let m = parse("envmap_cube", &[("detail", "pom")]);
        let names =
            |a: Applies| -> Vec<(&str, u32)> { m.overrides(a).iter().map(|o| (o.name, o.value)).collect() };
        assert_eq!(
            names(Applies::Geometry),
            [("AREA_METHOD", 0), ("DETAIL_METHOD", 7)]
        );
        assert_eq!(
            names(Applies::Shading),
            [("AREA_METHOD", 0), ("DETAIL_METHOD", 7), ("ENVMAP_METHOD", 1)]
        );
        let plain = Method::representative_point();
        assert_eq!(plain.overrides(Applies::Shading).len(), 1);
        assert_eq!(plain.overrides(Applies::Shading)[0].value, 1);
    }

    /// A method names itself by the part it was looked up by, whatever parts join it; an
    /// environment map's `detail` adds and removes its `Detail` part, after the map's rows.
    #[test]
    fn parts_are_found_by_type_and_the_primary_names_the_method() {
        let mut m = parse("envmap_sphere", &[("detail", "relief_mapping")]);
        assert_eq!(m.name(), "envmap_sphere");
        assert!(m.get::<EnvMapping>().is_some() && m.get::<Shadow>().is_none());
        let names: Vec<&str> = m.rows().iter().map(Row::name).collect();
        let detail_at = names.iter().position(|n| *n == "detail").unwrap();
        let steps_at = names.iter().position(|n| *n == "binary_steps").unwrap();
        assert!(detail_at < steps_at, "{names:?}");
        m.set_param("detail", Value::Keyword("none")).unwrap();
        assert!(m.get::<Detail>().is_none());
        assert_eq!(m, parse("envmap_sphere", &[]));
        let toksvig = parse("aa_specular_toksvig", &[]);
        assert_eq!(toksvig.name(), "aa_specular_toksvig");
        assert_eq!(toksvig.parts().count(), 2);
        assert_eq!(
            toksvig
                .clone()
                .without::<crate::technique::antialias::AntiAliasing>()
                .name(),
            "area_quadrature"
        );
    }

    /// A family refuses the frames it cannot be rendered in, naming the method and the reason.
    #[test]
    fn families_refuse_frames_they_cannot_render() {
        let forward = Frame {
            deferred: false,
            max_texture_side: 8192,
            msaa_counts: &[4],
        };
        let deferred = Frame {
            deferred: true,
            ..forward
        };
        assert!(parse("ssao_gtao", &[])
            .check(&forward)
            .unwrap_err()
            .contains("G-buffer"));
        assert!(parse("ssao_gtao", &[]).check(&deferred).is_ok());
        assert!(parse("shading_gouraud", &[])
            .check(&deferred)
            .unwrap_err()
            .contains("vertex"));
        assert!(parse("shading_phong", &[]).check(&deferred).is_ok());
        let small = Frame {
            max_texture_side: 512,
            ..forward
        };
        let e = parse("shadow_hard", &[]).check(&small).unwrap_err();
        assert!(
            e.starts_with("method shadow_hard(") && e.contains("map = 1024"),
            "{e}"
        );
        let e = parse("aa_msaa", &[("samples", "8")]).check(&forward).unwrap_err();
        assert!(e.contains("8 samples") && e.contains("it can do 4"), "{e}");
    }
}
