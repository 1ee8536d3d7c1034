//! The adapter and device: chosen the way wgpu's own tools choose them, so one environment
//! variable moves every Verity run to another GPU.
//!
//! - `WGPU_BACKEND` (e.g. `vulkan`, `metal`, `dx12`) restricts the backends
//!   (`wgpu::InstanceDescriptor::from_env_or_default`).
//! - `WGPU_ADAPTER_NAME` picks the first adapter whose name contains it (case-insensitive), as
//!   `wgpu::util::initialize_adapter_from_env` does, but with an error listing the adapters
//!   instead of a panic when none matches.
//! - `WGPU_POWER_PREF` (`low`/`high`) otherwise steers `request_adapter` (default: high).
//!
//! Only what the renderer uses is requested: 48 bytes of colour attachments per sample (three
//! Rgba32Float targets), fragment-stage storage writes (the cost counters), the adapter's own
//! texture and buffer size limits, `TIMESTAMP_QUERY` when the adapter has it (without it,
//! timings fall back to wall time around submit-and-wait), and
//! `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES` when it has that (WebGPU alone does not
//! multisample Rgba32Float; without it `aa_msaa` is refused naming no sample count).

use std::sync::{Arc, Mutex};

use crate::error::{RasterError, INSTALL_HINT};

/// How long one wait for the queue may take in all before it is an error: ten minutes, far
/// above what a frame takes even on lavapipe, yet bounded, so a lost device cannot hang a run.
/// [`WAIT_LIMIT_VARIABLE`] sets another.
pub(crate) const GPU_WAIT_LIMIT: std::time::Duration = std::time::Duration::from_secs(600);

/// The environment variable that sets the wait limit in seconds (a positive number): shorter
/// to give up on a stuck device sooner, longer for frames that take more than ten minutes,
/// and how the tests make a frame outlast the wait.
pub const WAIT_LIMIT_VARIABLE: &str = "VERITY_GPU_WAIT_LIMIT_S";

/// How long wgpu-core's `PollType::Wait` blocks before it reports a timeout
/// (`CLEANUP_WAIT_MS`, wgpu-core 26).
const WGPU_BLOCKING_WAIT: std::time::Duration = std::time::Duration::from_secs(60);

/// The wait limit: [`WAIT_LIMIT_VARIABLE`]'s value, or [`GPU_WAIT_LIMIT`] when it is unset.
fn wait_limit() -> Result<std::time::Duration, RasterError> {
    let Some(value) = std::env::var_os(WAIT_LIMIT_VARIABLE) else {
        return Ok(GPU_WAIT_LIMIT);
    };
    let text = value.to_string_lossy();
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|s| s.is_finite() && *s > 0.0 && *s <= 1e9)
        .map(std::time::Duration::from_secs_f64)
        .ok_or_else(|| {
            RasterError::Settings(format!(
                "{WAIT_LIMIT_VARIABLE}={text:?}: expected a positive number of seconds"
            ))
        })
}

/// Colour-attachment bytes per sample the passes write (three Rgba32Float targets).
pub const COLOR_BYTES_PER_SAMPLE: u32 = 48;

/// Format of every colour target and G-buffer layer.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Depth buffer format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Keeps Mesa's `VK_LAYER_MESA_device_select` implicit Vulkan layer from printing
/// "error: XDG_RUNTIME_DIR is invalid or not set in the environment." (twice) on headless
/// machines: to order GPUs by the one driving the display it connects to Wayland, whose
/// client library prints that line when no session exists — which reads as Verity's own
/// error. A headless renderer has no display to prefer, so where `XDG_RUNTIME_DIR` is not
/// a folder and the user has not chosen (`MESA_VK_DEVICE_SELECT`, `NODEVICE_SELECT`), the layer
/// is switched off with its documented `NODEVICE_SELECT=1` (Mesa, `src/vulkan/device-select-layer`);
/// wgpu's own `WGPU_ADAPTER_NAME` still selects the adapter. Changes the environment: call it
/// at the start of `main`, before any thread exists.
pub fn quiet_headless_vulkan() {
    let chosen = ["MESA_VK_DEVICE_SELECT", "NODEVICE_SELECT"]
        .iter()
        .any(|k| std::env::var_os(k).is_some());
    let session = std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir());
    if !chosen && !session {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// A device on one adapter.
pub struct Gpu {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    timestamps: bool,
    /// Whether samplers may filter anisotropically (WebGPU's `maxAnisotropy` above 1 is then
    /// honoured; otherwise it is clamped to 1).
    anisotropic: bool,
    /// Sample counts above 1 the adapter renders to Rgba32Float and Depth32Float targets.
    msaa_counts: Vec<u32>,
    limits: wgpu::Limits,
    /// wgpu's uncaptured errors since the last [`Gpu::check_errors`].
    errors: Arc<Mutex<Vec<String>>>,
    /// How long a wait for the queue may take ([`wait_limit`]).
    wait_limit: std::time::Duration,
    /// Set when a wait gave up with work still in flight: the device is then never destroyed
    /// (see `Drop`).
    abandoned: std::sync::atomic::AtomicBool,
}

/// Set when any device of the process was abandoned ([`Gpu::wait_for`]).
static ANY_ABANDONED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether a device of this process was abandoned with work in flight: it is never destroyed,
/// and the driver's threads may still be running it. A program should then end without running
/// the C libraries' exit handlers (`_exit`): on lavapipe, `exit` runs LLVM's and Mesa's static
/// destructors under those threads, which crashed the process after its error was printed
/// (SIGSEGV, or "LLVM ERROR" and SIGABRT; 5 of 30 runs of a 0.000001 s wait limit, two at a
/// time).
pub fn device_abandoned() -> bool {
    ANY_ABANDONED.load(std::sync::atomic::Ordering::Relaxed)
}

impl Drop for Gpu {
    /// wgpu-core's queue, when destroyed, waits about 6 s in all for the last submission and
    /// panics if it has not finished ("We timed out while waiting on the last successful
    /// submission to complete!"): a frame on a slow adapter outlasts that, and the panic in a
    /// destructor ended runs in a segmentation fault. So the queue is first waited for as any
    /// wait is; if that gives up, or an earlier wait did, the device and queue are leaked (the
    /// process keeps them until it exits) rather than destroyed under running work.
    fn drop(&mut self) {
        let idle = !self.abandoned.load(std::sync::atomic::Ordering::Relaxed)
            && self.wait_for("releasing the device").is_ok();
        if !idle {
            std::mem::forget(self.queue.clone());
            std::mem::forget(self.device.clone());
        }
    }
}

impl Gpu {
    /// Picks the adapter (see the module documentation) and creates the device. Without any
    /// adapter the error says what to install.
    pub fn new() -> Result<Gpu, RasterError> {
        let wait_limit = wait_limit()?;
        let instance = wgpu::Instance::new(&wgpu::InstanceDescriptor::from_env_or_default());
        let adapter = pick_adapter(&instance)?;
        let info = adapter.get_info();
        let supported = adapter.limits();
        let unsupported = |message: String| RasterError::Unsupported {
            adapter: info.name.clone(),
            message,
        };
        if supported.max_color_attachment_bytes_per_sample < COLOR_BYTES_PER_SAMPLE {
            return Err(unsupported(format!(
                "needs {COLOR_BYTES_PER_SAMPLE} bytes of colour attachments per sample, has {}",
                supported.max_color_attachment_bytes_per_sample
            )));
        }
        let downlevel = adapter.get_downlevel_capabilities();
        if !downlevel
            .flags
            .contains(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE)
        {
            return Err(unsupported(
                "needs storage-buffer writes in fragment shaders".into(),
            ));
        }
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let format_features = adapter
            .features()
            .contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES);
        let msaa_counts = if format_features {
            let colour = adapter.get_texture_format_features(COLOR_FORMAT);
            let depth = adapter.get_texture_format_features(DEPTH_FORMAT);
            colour
                .flags
                .supported_sample_counts()
                .into_iter()
                .filter(|&n| n > 1 && depth.flags.sample_count_supported(n))
                .collect()
        } else {
            Vec::new()
        };
        let anisotropic = downlevel
            .flags
            .contains(wgpu::DownlevelFlags::ANISOTROPIC_FILTERING);
        let limits = wgpu::Limits {
            max_color_attachment_bytes_per_sample: COLOR_BYTES_PER_SAMPLE,
            max_texture_dimension_2d: supported.max_texture_dimension_2d,
            max_storage_buffer_binding_size: supported.max_storage_buffer_binding_size,
            max_buffer_size: supported.max_buffer_size,
            ..wgpu::Limits::default()
        };
        let desc = wgpu::DeviceDescriptor {
            label: Some("verity realtime device"),
            required_features: {
                let mut f = wgpu::Features::empty();
                f.set(wgpu::Features::TIMESTAMP_QUERY, timestamps);
                f.set(
                    wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES,
                    format_features,
                );
                f
            },
            required_limits: limits.clone(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&desc))
            .map_err(|e| unsupported(format!("device creation failed: {e}")))?;
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = errors.clone();
        device.on_uncaptured_error(Box::new(move |e| {
            sink.lock().unwrap_or_else(|p| p.into_inner()).push(e.to_string());
        }));
        Ok(Gpu {
            device,
            queue,
            info,
            timestamps,
            anisotropic,
            msaa_counts,
            limits,
            errors,
            wait_limit,
            abandoned: std::sync::atomic::AtomicBool::new(false),
        })
    }

    /// wgpu errors reported since the last check, as one error naming `context`.
    pub(crate) fn check_errors(&self, context: &str) -> Result<(), RasterError> {
        let mut errors = self.errors.lock().unwrap_or_else(|p| p.into_inner());
        if errors.is_empty() {
            return Ok(());
        }
        let message = errors.join("\n");
        errors.clear();
        Err(RasterError::Gpu {
            context: context.to_string(),
            message,
        })
    }

    /// Waits until the queue is idle; `context` names the wait in the error.
    ///
    /// wgpu-core gives up a `PollType::Wait` after a fixed 60 s (`CLEANUP_WAIT_MS`). A
    /// software rasteriser (lavapipe) on a loaded two-core machine can take longer than that
    /// for one submission without anything being wrong, so a timed-out wait is retried until
    /// the wait limit ([`GPU_WAIT_LIMIT`], or [`WAIT_LIMIT_VARIABLE`]) has passed; within the
    /// last 60 s of the limit the queue is polled every few milliseconds instead, so that the
    /// limit holds to the millisecond. Only then is it an error, and the device is abandoned
    /// (never destroyed: `Drop`).
    pub(crate) fn wait_for(&self, context: &str) -> Result<(), RasterError> {
        let start = std::time::Instant::now();
        let give_up = |e: String| {
            self.abandoned.store(true, std::sync::atomic::Ordering::Relaxed);
            ANY_ABANDONED.store(true, std::sync::atomic::Ordering::Relaxed);
            RasterError::Gpu {
                context: context.to_string(),
                message: format!(
                    "{e} after {:.1} s, the limit ({WAIT_LIMIT_VARIABLE} sets another); the device is abandoned",
                    start.elapsed().as_secs_f64()
                ),
            }
        };
        loop {
            let left = self.wait_limit.saturating_sub(start.elapsed());
            if left > WGPU_BLOCKING_WAIT {
                match self.device.poll(wgpu::PollType::Wait) {
                    Ok(_) => return Ok(()),
                    Err(wgpu::PollError::Timeout) => continue,
                }
            }
            match self.device.poll(wgpu::PollType::Poll) {
                Ok(status) if status.is_queue_empty() => return Ok(()),
                Ok(_) if left > std::time::Duration::ZERO => {
                    std::thread::sleep(left.min(std::time::Duration::from_millis(2)));
                }
                Ok(_) => return Err(give_up("the queue did not finish".into())),
                Err(e) => return Err(give_up(e.to_string())),
            }
        }
    }

    /// Waits until the queue is idle.
    pub(crate) fn wait(&self) -> Result<(), RasterError> {
        self.wait_for("waiting for the GPU")
    }

    /// The adapter's name as the driver reports it.
    pub fn adapter_name(&self) -> &str {
        &self.info.name
    }

    /// The backend in lower case (`vulkan`, `metal`, `dx12`, …).
    pub fn backend(&self) -> String {
        format!("{:?}", self.info.backend).to_lowercase()
    }

    /// Driver name and version.
    pub fn driver(&self) -> String {
        format!("{} {}", self.info.driver, self.info.driver_info)
            .trim()
            .to_string()
    }

    /// Whether per-pass GPU timestamps are available.
    pub fn has_timestamps(&self) -> bool {
        self.timestamps
    }

    /// Whether the adapter filters anisotropically (`tex_anisotropic` needs it).
    pub fn anisotropic_filtering(&self) -> bool {
        self.anisotropic
    }

    /// MSAA sample counts (above 1) the adapter renders the targets with.
    pub fn msaa_counts(&self) -> &[u32] {
        &self.msaa_counts
    }

    /// The device's limits.
    pub fn limits(&self) -> &wgpu::Limits {
        &self.limits
    }
}

/// WGPU_ADAPTER_NAME's adapter, or wgpu's default choice.
fn pick_adapter(instance: &wgpu::Instance) -> Result<wgpu::Adapter, RasterError> {
    if let Ok(name) = std::env::var("WGPU_ADAPTER_NAME") {
        let want = name.to_lowercase();
        let adapters = instance.enumerate_adapters(wgpu::Backends::all());
        let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        return adapters
            .into_iter()
            .find(|a| a.get_info().name.to_lowercase().contains(&want))
            .ok_or_else(|| {
                if names.is_empty() {
                    RasterError::NoAdapter(INSTALL_HINT.to_string())
                } else {
                    RasterError::NoAdapter(format!(
                        "WGPU_ADAPTER_NAME={name} matches none of the adapters: {}",
                        names.join("; ")
                    ))
                }
            });
    }
    let options = wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::from_env().unwrap_or(wgpu::PowerPreference::HighPerformance),
        force_fallback_adapter: false,
        compatible_surface: None,
    };
    pollster::block_on(instance.request_adapter(&options))
        .map_err(|e| RasterError::NoAdapter(format!("{INSTALL_HINT} (wgpu: {e})")))
}
