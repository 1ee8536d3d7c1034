//! Methods (how area lights, sun disks and the environment are shaded) and their parameters,
//! as `verity raster --method NAME --param k=v` names them.
//!
//! | method | area lights and sun disks | parameters |
//! |---|---|---|
//! | `area_quadrature` | N×N midpoint quadrature: converges to the exact unshadowed integral | `n` (16), `env_n` (8) |
//! | `area_representative_point` | one representative point per light (Karis 2013) | `env_n` (8) |
//!
//! Delta lights (point, spot, zero-diameter directional) are exact under every method. The
//! environment lights surfaces by `env_n`×`env_n` cosine-weighted midpoint quadrature under
//! every method (0 turns environment lighting off; the background is always drawn).

use std::fmt;

/// Largest `n` / `env_n` accepted (N² samples per light per pixel).
pub const MAX_QUADRATURE_N: u32 = 64;

/// The area-light technique (WGSL `AREA_METHOD`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AreaMethod {
    /// N×N stratified midpoint quadrature (the reference for unshadowed area light).
    Quadrature,
    /// Karis 2013 representative point with energy normalisation (an approximation).
    RepresentativePoint,
}

impl AreaMethod {
    /// The value of the WGSL override constant `AREA_METHOD`.
    pub fn shader_code(self) -> u32 {
        match self {
            AreaMethod::Quadrature => 0,
            AreaMethod::RepresentativePoint => 1,
        }
    }
}

/// A method with its parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Method {
    /// How area lights and sun disks are shaded.
    pub area: AreaMethod,
    /// N of the N×N area quadrature (ignored by the representative point).
    pub area_n: u32,
    /// N of the N×N environment quadrature; 0 = no environment lighting.
    pub env_n: u32,
}

impl Default for Method {
    /// `area_quadrature` with n = 16, env_n = 8.
    fn default() -> Self {
        Method {
            area: AreaMethod::Quadrature,
            area_n: 16,
            env_n: 8,
        }
    }
}

impl Method {
    /// Every method name `parse` accepts.
    pub const NAMES: [&'static str; 2] = ["area_quadrature", "area_representative_point"];

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

    /// The same method with environment quadrature N.
    pub fn with_env_n(self, env_n: u32) -> Self {
        Method { env_n, ..self }
    }

    /// The method called `name` with `params` (`key`, `value`) applied over its defaults.
    /// Errors name the method or parameter and list what is accepted.
    pub fn parse(name: &str, params: &[(String, String)]) -> Result<Method, String> {
        let mut m = match name {
            "area_quadrature" => Method::default(),
            "area_representative_point" => Method::representative_point(),
            _ => {
                return Err(format!(
                    "unknown method `{name}`; methods: {}",
                    Method::NAMES.join(", ")
                ))
            }
        };
        for (key, value) in params {
            let accepted: &[&str] = match m.area {
                AreaMethod::Quadrature => &["n", "env_n"],
                AreaMethod::RepresentativePoint => &["env_n"],
            };
            let slot = match key.as_str() {
                "n" if m.area == AreaMethod::Quadrature => &mut m.area_n,
                "env_n" => &mut m.env_n,
                _ => {
                    return Err(format!(
                        "method {name} has no parameter `{key}`; parameters: {}",
                        accepted.join(", ")
                    ))
                }
            };
            *slot = parse_n(key, value, key == "env_n")?;
        }
        Ok(m)
    }

    /// The method's name.
    pub fn name(&self) -> &'static str {
        match self.area {
            AreaMethod::Quadrature => "area_quadrature",
            AreaMethod::RepresentativePoint => "area_representative_point",
        }
    }

    /// Its parameters as `k=v` pairs (for headers and the timing line).
    pub fn params(&self) -> Vec<(String, String)> {
        let mut p = Vec::new();
        if self.area == AreaMethod::Quadrature {
            p.push(("n".to_string(), self.area_n.to_string()));
        }
        p.push(("env_n".to_string(), self.env_n.to_string()));
        p
    }
}

impl fmt::Display for Method {
    /// `name(k=v, …)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let params: Vec<String> = self.params().iter().map(|(k, v)| format!("{k}={v}")).collect();
        write!(f, "{}({})", self.name(), params.join(", "))
    }
}

/// A quadrature N in 1..=[`MAX_QUADRATURE_N`] (0 too when `zero_ok`).
fn parse_n(key: &str, value: &str, zero_ok: bool) -> Result<u32, String> {
    let lo = if zero_ok { 0 } else { 1 };
    match value.trim().parse::<u32>() {
        Ok(n) if (lo..=MAX_QUADRATURE_N).contains(&n) => Ok(n),
        _ => Err(format!(
            "parameter {key} = `{value}`: expected a whole number in {lo}..={MAX_QUADRATURE_N}"
        )),
    }
}

/// Forward shading or deferred shading (G-buffer + lighting pass).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum PipelineKind {
    /// Shade in the geometry pass.
    #[default]
    Forward,
    /// Write a G-buffer, then shade in a full-screen lighting pass.
    Deferred,
}

impl PipelineKind {
    /// `forward` or `deferred`.
    pub fn name(self) -> &'static str {
        match self {
            PipelineKind::Forward => "forward",
            PipelineKind::Deferred => "deferred",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let e = Method::parse("pcss", &[]).unwrap_err();
        assert!(e.contains("area_quadrature"), "{e}");
        let e = Method::parse("area_representative_point", &[kv("n", "4")]).unwrap_err();
        assert!(e.contains("no parameter `n`") && e.contains("env_n"), "{e}");
        for bad in ["0", "65", "-1", "x", "2.5"] {
            assert!(
                Method::parse("area_quadrature", &[kv("n", bad)]).is_err(),
                "n={bad}"
            );
        }
        assert!(Method::parse("area_quadrature", &[kv("env_n", "0")]).is_ok());
    }
}
