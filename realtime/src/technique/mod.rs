//! The real-time techniques: one module per family, each holding its methods, their
//! parameter tables ([`param`]), their GPU resources and (under `shaders/<family>/`) their
//! WGSL; [`Method`] ([`method`]), the one method a render uses, composed of the families'
//! settings; and [`FAMILIES`], the registry every family joins with one line.
//!
//! | family | module | methods | ground truth (oracle) |
//! |---|---|---|---|
//! | area lights | [`area`], [`method::AreaLights`] | `area_quadrature`, `area_representative_point` | `direct-unshadowed` |
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
pub mod method;
pub mod param;
pub mod shading;
pub mod shadow;
pub mod ssao;
pub mod texture;

pub use method::{
    Applies, Family, Frame, Method, MethodInfo, Override, Row, Settings, UniformBlock, COMMON,
    MAX_QUADRATURE_N,
};

/// Every family, in the order the docs list them: a new family is one line here.
pub static FAMILIES: &[&dyn Family] = &[
    &method::AreaLights,
    &shadow::ShadowMapping,
    &detail::SurfaceDetail,
    &envmap::EnvironmentMapping,
    &distance_impostor::DistanceImpostors,
    &texture::TextureFiltering,
    &shading::ShadingFrequencies,
    &antialias::AntiAliasingFamily,
    &lightmap::LightMaps,
    &ssao::AmbientOcclusionFamily,
    &energy::EnergyCompensationFamily,
];

impl Method {
    /// Every method name `parse` accepts, family by family.
    pub fn names() -> Vec<&'static str> {
        FAMILIES
            .iter()
            .flat_map(|f| f.methods())
            .map(|m| m.name)
            .collect()
    }

    /// The method called `name` with its defaults, as its family builds it.
    pub fn by_name(name: &str) -> Option<Method> {
        FAMILIES.iter().find_map(|f| f.method(name))
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
}

/// The first method of `family` with its defaults.
fn first_method(family: &dyn Family) -> Method {
    Method::by_name(family.methods()[0].name).expect("a family's method parses")
}

/// The rows of `m` that are neither [`COMMON`]'s nor in its family's `shared`.
fn own_rows(m: &Method, shared: &[Row]) -> Vec<Row> {
    m.rows()
        .into_iter()
        .filter(|r| !COMMON.iter().any(|c| r.is(c)))
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
        s += &markdown_row(&Row(row), &quadrature);
    }
    s += "\nDefaults of `n` / `env_n` by family: ";
    let defaults: Vec<String> = FAMILIES
        .iter()
        .map(|f| {
            let m = first_method(*f);
            format!("{} {} / {}", f.title().to_lowercase(), m.area_n, m.env_n)
        })
        .collect();
    s += &defaults.join("; ");
    s += ".\n";
    for family in FAMILIES {
        let methods = family.methods();
        s += &format!(
            "\n## {}\n\n| method | what | paper |\n|---|---|---|\n",
            family.title()
        );
        for m in &methods {
            s += &format!("| `{}` | {} | {} |\n", m.name, m.summary, m.source);
        }
        let first = first_method(*family);
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
    FAMILIES
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
    for family in FAMILIES {
        let methods = family.methods();
        let first = first_method(*family);
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

/// The WGSL generated from the registry, put ahead of the shader module's sources (pipelines.rs
/// `shader_source`): each family's method codes ([`Family::wgsl_codes`]), such as the values of
/// `SHADOW_METHOD` (`SHADOW_NONE`, `SHADOW_HARD` …: a family's prefix and its method's name in
/// capitals, numbered in table order), and `FamilyUniforms`, the families' blocks of the frame
/// uniform ([`UniformBlock`]), one field per family that has one.
pub fn wgsl_codes() -> String {
    let mut s = String::from("// Generated by realtime::technique::wgsl_codes() from the method tables.\n");
    for family in FAMILIES {
        s += &family.wgsl_codes();
    }
    s += "struct FamilyUniforms {\n";
    for block in uniform_blocks() {
        s += &format!("    @align(16) {}: {},\n", block.field, block.wgsl_type);
    }
    s + "}\n"
}

/// The families' blocks of the frame uniform, in registry order.
pub fn uniform_blocks() -> impl Iterator<Item = UniformBlock> {
    FAMILIES.iter().filter_map(|f| f.uniforms())
}

/// The bytes of the frame uniform's `families` for `m`: each block at a 16-byte boundary, the
/// whole padded to 16 bytes (WGSL's uniform layout of `FamilyUniforms`).
pub fn family_uniform_bytes(m: &Method) -> Vec<u8> {
    let mut bytes = Vec::new();
    for block in uniform_blocks() {
        let b = (block.bytes)(m);
        debug_assert_eq!(b.len(), block.size, "{}", block.field);
        bytes.extend_from_slice(&b);
        bytes.resize(bytes.len().next_multiple_of(16), 0);
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;
    use area::AreaMethod;
    use param::Value;
    use shadow::{Shadow, ShadowTechnique};

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
            .map(|n| {
                Method::parse(n, &[])
                    .unwrap()
                    .get::<Shadow>()
                    .map_or(0, |s| s.technique.shader_code())
            })
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
        bad.insert(Shadow::new(ShadowTechnique::PcfPoisson {
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
        let s = *m.get::<Shadow>().unwrap();
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
            assert!(
                m.validate().is_ok() && m.get::<Shadow>().is_none() && m.get::<detail::Detail>().is_some()
            );
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
        let d = *m.get::<detail::Detail>().unwrap();
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
