//! Why a raster render failed.

/// What to install when no adapter is found (the Vulkan CPU driver, Mesa's lavapipe).
pub const INSTALL_HINT: &str = "no GPU adapter found: install a Vulkan driver — on Debian/Ubuntu \
     `apt-get install mesa-vulkan-drivers libvulkan1` (Mesa's lavapipe CPU driver; \
     scripts/setup.sh does it) — or select one with WGPU_BACKEND / WGPU_ADAPTER_NAME";

/// A failed raster render.
#[derive(Debug, thiserror::Error)]
pub enum RasterError {
    /// No adapter (or none matching WGPU_ADAPTER_NAME), or the device could not be created.
    #[error("{0}")]
    NoAdapter(String),
    /// The adapter lacks a limit or feature the renderer needs.
    #[error("adapter {adapter}: {message}")]
    Unsupported {
        /// Adapter name.
        adapter: String,
        /// What is missing.
        message: String,
    },
    /// The scene cannot be rendered as given (names the file and field).
    #[error("{0}")]
    Scene(String),
    /// Invalid render settings (names the setting).
    #[error("{0}")]
    Settings(String),
    /// wgpu reported a validation or out-of-memory error.
    #[error("GPU error ({context}): {message}")]
    Gpu {
        /// What was being done.
        context: String,
        /// wgpu's message.
        message: String,
    },
}
