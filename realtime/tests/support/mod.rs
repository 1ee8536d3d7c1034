//! Helpers shared by the realtime integration tests (each test file is its own crate and uses
//! some of them, hence `dead_code` allowed).
#![allow(dead_code)]

use std::sync::OnceLock;

use realtime::{Method, Renderer};

/// One renderer per test binary (pipelines are compiled once); no adapter is a failure.
pub fn renderer() -> &'static Renderer {
    static R: OnceLock<Renderer> = OnceLock::new();
    R.get_or_init(|| Renderer::new().unwrap_or_else(|e| panic!("these tests need a GPU adapter: {e}")))
}

/// The method `name` with `params` over its defaults; a bad name or value panics with the
/// parser's message.
pub fn method(name: &str, params: &[(&str, &str)]) -> Method {
    let params: Vec<(String, String)> = params
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Method::parse(name, &params).unwrap_or_else(|e| panic!("{e}"))
}
