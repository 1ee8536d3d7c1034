//! WGPU_ADAPTER_NAME that matches no adapter is an error that lists the adapters (or, with
//! none at all, says what to install) — never a panic. Its own test binary: it sets an
//! environment variable of the whole process.

#[test]
fn unknown_adapter_name_is_a_clear_error() {
    std::env::set_var("WGPU_ADAPTER_NAME", "no-such-adapter-7f3a");
    let err = match realtime::Renderer::new() {
        Ok(r) => panic!("WGPU_ADAPTER_NAME matched adapter {}", r.gpu().adapter_name()),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("WGPU_ADAPTER_NAME=no-such-adapter-7f3a matches none")
            || err.contains("mesa-vulkan-drivers"),
        "unexpected error: {err}"
    );
}
