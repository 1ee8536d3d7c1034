//! Verity's headless wgpu renderer.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

/// Adapter names visible to wgpu.
pub fn adapters() -> Vec<String> {
    let instance = wgpu::Instance::new(&wgpu::InstanceDescriptor::from_env_or_default());
    instance
        .enumerate_adapters(wgpu::Backends::all())
        .into_iter()
        .map(|a| format!("{:?}", a.get_info()))
        .collect()
}
