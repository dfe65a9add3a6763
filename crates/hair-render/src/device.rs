//! Headless device acquisition: any adapter (a real GPU first), falling back to Mesa's CPU drivers.
//!
//! The backend is chosen by [`DeviceOptions::backend`], which [`DeviceOptions::from_env`] reads from
//! the `HAIRLOD_BACKEND` environment variable (`vulkan`, `gl` or `auto`). In `auto` mode hardware
//! adapters come first (discrete, integrated, virtual, other), then CPU adapters such as lavapipe
//! (Vulkan) and llvmpipe (GL through EGL); within a kind, Vulkan is preferred to GL. The first
//! adapter that meets the renderer's needs (storage buffers in vertex shaders, compute shaders,
//! multisampling) and opens a device wins.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use crate::error::{INSTALL_HINT, RenderError, Result};
use crate::target::{COLOR_FORMAT, DEPTH_FORMAT};

/// Name of the environment variable that picks the backend.
pub const BACKEND_ENV_VAR: &str = "HAIRLOD_BACKEND";

/// Storage buffers the evaluation pass binds in its one stage, the most of any pipeline: nodes
/// and chains (group 0); strands, chain-curve samples, residual profiles, strands drawn and
/// strand shifts (group 1); its output (group 2). WebGPU's default limit, which the CPU
/// drivers exceed.
pub(crate) const REQUIRED_STORAGE_BUFFERS_PER_STAGE: u32 = 8;

/// Which wgpu backend to search for adapters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BackendChoice {
    /// Vulkan and GL: hardware adapters first, then CPU ones; Vulkan before GL.
    #[default]
    Auto,
    /// Vulkan only (a GPU driver or Mesa's lavapipe).
    Vulkan,
    /// OpenGL (ES) through EGL only (a GPU driver or Mesa's llvmpipe).
    Gl,
}

impl BackendChoice {
    /// The wgpu backend set this choice searches.
    pub fn backends(self) -> wgpu::Backends {
        match self {
            BackendChoice::Auto => wgpu::Backends::VULKAN | wgpu::Backends::GL,
            BackendChoice::Vulkan => wgpu::Backends::VULKAN,
            BackendChoice::Gl => wgpu::Backends::GL,
        }
    }

    /// Reads `HAIRLOD_BACKEND`: `Ok(None)` when it is unset or empty, an error when it names
    /// no known backend.
    pub fn from_env() -> Result<Option<BackendChoice>> {
        match std::env::var(BACKEND_ENV_VAR) {
            Ok(value) if value.trim().is_empty() => Ok(None),
            Ok(value) => parse_backend(&value, BACKEND_ENV_VAR).map(Some),
            Err(std::env::VarError::NotPresent) => Ok(None),
            Err(std::env::VarError::NotUnicode(value)) => Err(RenderError::UnknownBackend {
                value: value.to_string_lossy().into_owned(),
                source_name: BACKEND_ENV_VAR.to_owned(),
            }),
        }
    }
}

fn parse_backend(value: &str, source_name: &str) -> Result<BackendChoice> {
    match value.trim().to_ascii_lowercase().as_str() {
        "auto" => Ok(BackendChoice::Auto),
        "vulkan" | "vk" => Ok(BackendChoice::Vulkan),
        "gl" | "gles" | "opengl" => Ok(BackendChoice::Gl),
        _ => Err(RenderError::UnknownBackend {
            value: value.to_owned(),
            source_name: source_name.to_owned(),
        }),
    }
}

impl FromStr for BackendChoice {
    type Err = RenderError;

    /// Parses `vulkan`, `gl` or `auto` (case-insensitive; `vk`, `gles`, `opengl` also accepted).
    fn from_str(value: &str) -> Result<Self> {
        parse_backend(value, "backend name")
    }
}

impl fmt::Display for BackendChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BackendChoice::Auto => "auto",
            BackendChoice::Vulkan => "vulkan",
            BackendChoice::Gl => "gl",
        })
    }
}

/// How to pick the adapter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceOptions {
    /// Backends to search.
    pub backend: BackendChoice,
    /// Whether CPU adapters (lavapipe, llvmpipe) may be used when no hardware adapter works.
    pub allow_software: bool,
    /// MSAA sample count the adapter must support for the colour and depth targets (1, 2, 4, 8, 16).
    pub sample_count: u32,
}

impl Default for DeviceOptions {
    /// `auto` backend, software allowed, 4× MSAA.
    fn default() -> Self {
        DeviceOptions {
            backend: BackendChoice::Auto,
            allow_software: true,
            sample_count: 4,
        }
    }
}

impl DeviceOptions {
    /// The defaults, with the backend taken from `HAIRLOD_BACKEND` when it is set.
    /// A command-line flag should override the result's `backend`.
    pub fn from_env() -> Result<DeviceOptions> {
        let mut options = DeviceOptions::default();
        if let Some(backend) = BackendChoice::from_env()? {
            options.backend = backend;
        }
        Ok(options)
    }
}

/// What adapter the renderer got.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AdapterReport {
    /// Adapter name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// Backend the device runs on.
    pub backend: wgpu::Backend,
    /// Kind of device (discrete GPU, CPU, ...).
    pub device_type: wgpu::DeviceType,
    /// Driver name, e.g. `llvmpipe`.
    pub driver: String,
    /// Driver details, e.g. the Mesa version.
    pub driver_info: String,
}

impl AdapterReport {
    /// Builds the report from wgpu's adapter information.
    pub fn from_info(info: &wgpu::AdapterInfo) -> AdapterReport {
        AdapterReport {
            name: info.name.clone(),
            backend: info.backend,
            device_type: info.device_type,
            driver: info.driver.clone(),
            driver_info: info.driver_info.clone(),
        }
    }

    /// Whether this is a CPU (software) rasteriser such as lavapipe or llvmpipe.
    pub fn is_software(&self) -> bool {
        self.device_type == wgpu::DeviceType::Cpu
    }
}

impl fmt::Display for AdapterReport {
    /// `NAME (BACKEND, KIND, driver DRIVER DRIVER_INFO)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.device_type {
            wgpu::DeviceType::Other => "other",
            wgpu::DeviceType::IntegratedGpu => "integrated GPU",
            wgpu::DeviceType::DiscreteGpu => "discrete GPU",
            wgpu::DeviceType::VirtualGpu => "virtual GPU",
            wgpu::DeviceType::Cpu => "CPU",
        };
        write!(f, "{} ({}, {kind}", self.name, self.backend)?;
        let driver = format!("{} {}", self.driver, self.driver_info);
        let driver = driver.trim();
        if !driver.is_empty() {
            write!(f, ", driver {driver}")?;
        }
        f.write_str(")")
    }
}

/// An opened device with its queue and a report of what was found.
#[derive(Debug, Clone)]
pub struct GpuContext {
    /// The chosen adapter.
    pub adapter: wgpu::Adapter,
    /// The device opened on it.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What was found.
    pub report: AdapterReport,
}

/// Sort key: hardware before software, Vulkan before GL.
fn adapter_rank(info: &wgpu::AdapterInfo) -> (u8, u8) {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    };
    let backend = match info.backend {
        wgpu::Backend::Vulkan => 0,
        wgpu::Backend::Metal | wgpu::Backend::Dx12 => 1,
        _ => 2,
    };
    (kind, backend)
}

/// Why an adapter cannot run the renderer, or `None` when it can.
fn unsuitability(adapter: &wgpu::Adapter, options: &DeviceOptions) -> Option<String> {
    let info = adapter.get_info();
    if !options.allow_software && info.device_type == wgpu::DeviceType::Cpu {
        return Some("software adapter, and software is not allowed".to_owned());
    }
    let downlevel = adapter.get_downlevel_capabilities();
    if !downlevel
        .flags
        .contains(wgpu::DownlevelFlags::VERTEX_STORAGE)
    {
        return Some("no storage buffers in vertex shaders".to_owned());
    }
    if !downlevel
        .flags
        .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
    {
        return Some("no compute shaders".to_owned());
    }
    let limits = adapter.limits();
    if limits.max_storage_buffers_per_shader_stage < REQUIRED_STORAGE_BUFFERS_PER_STAGE {
        return Some(format!(
            "only {} storage buffers per shader stage (need {REQUIRED_STORAGE_BUFFERS_PER_STAGE})",
            limits.max_storage_buffers_per_shader_stage
        ));
    }
    for format in [COLOR_FORMAT, DEPTH_FORMAT] {
        let features = adapter.get_texture_format_features(format);
        if !features.flags.sample_count_supported(options.sample_count) {
            return Some(format!(
                "{}x MSAA not supported for {format:?} (supported: {:?})",
                options.sample_count,
                features.flags.supported_sample_counts()
            ));
        }
    }
    None
}

/// Finds an adapter for `options` and opens a device on it.
///
/// Errors: [`RenderError::NoAdapter`] when no adapter exists on the chosen backends,
/// [`RenderError::NoUsableAdapter`] when none meets the renderer's needs; both say what to install.
pub fn acquire_device(options: &DeviceOptions) -> Result<GpuContext> {
    let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
    descriptor.backends = options.backend.backends();
    let instance = wgpu::Instance::new(descriptor);
    open_device(&instance, options, None)
}

/// [`acquire_device`] on the caller's `instance` (one that knows the window's display), keeping
/// only adapters that can present to `surface`: the device of an interactive viewer, which
/// renders with [`crate::Renderer::with_context`] and shows the frames in a window.
///
/// Errors as [`acquire_device`]; an adapter that cannot present to the window is rejected with
/// that reason.
pub fn acquire_device_for_surface(
    instance: &wgpu::Instance,
    surface: &wgpu::Surface<'_>,
    options: &DeviceOptions,
) -> Result<GpuContext> {
    open_device(instance, options, Some(surface))
}

/// Opens a device on the best adapter of `instance` for `options` (and `surface`, when given).
fn open_device(
    instance: &wgpu::Instance,
    options: &DeviceOptions,
    surface: Option<&wgpu::Surface<'_>>,
) -> Result<GpuContext> {
    if !matches!(options.sample_count, 1 | 2 | 4 | 8 | 16) {
        return Err(RenderError::InvalidInput(format!(
            "sample count {} is not one of 1, 2, 4, 8, 16",
            options.sample_count
        )));
    }
    let backends = options.backend.backends();
    let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
    if adapters.is_empty() {
        return Err(RenderError::NoAdapter {
            backends: backend_names(backends),
            hint: INSTALL_HINT,
        });
    }
    adapters.sort_by_key(|adapter| adapter_rank(&adapter.get_info()));

    let mut rejections = Vec::new();
    for adapter in adapters {
        let info = adapter.get_info();
        if let Some(reason) = unsuitability(&adapter, options) {
            rejections.push(format!("{} ({}): {reason}", info.name, info.backend));
            continue;
        }
        if surface.is_some_and(|surface| !adapter.is_surface_supported(surface)) {
            rejections.push(format!(
                "{} ({}): cannot present to the window",
                info.name, info.backend
            ));
            continue;
        }
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("hair-render device"),
            required_features: wgpu::Features::empty(),
            required_limits: adapter.limits(),
            experimental_features: wgpu::ExperimentalFeatures::default(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        };
        match pollster::block_on(adapter.request_device(&descriptor)) {
            Ok((device, queue)) => {
                // Errors are captured by error scopes around each operation; anything that escapes
                // them is reported here instead of wgpu's default panic.
                device.on_uncaptured_error(Arc::new(|error: wgpu::Error| {
                    eprintln!("hair-render: uncaptured GPU error: {error}");
                }));
                return Ok(GpuContext {
                    report: AdapterReport::from_info(&info),
                    adapter,
                    device,
                    queue,
                });
            }
            Err(error) => {
                rejections.push(format!("{} ({}): {error}", info.name, info.backend));
            }
        }
    }
    Err(RenderError::NoUsableAdapter {
        details: rejections.join("; "),
        hint: INSTALL_HINT,
    })
}

fn backend_names(backends: wgpu::Backends) -> String {
    let mut names = Vec::new();
    if backends.contains(wgpu::Backends::VULKAN) {
        names.push("vulkan");
    }
    if backends.contains(wgpu::Backends::GL) {
        names.push("gl");
    }
    names.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backend_names_parse() {
        assert_eq!(
            "Vulkan".parse::<BackendChoice>().unwrap(),
            BackendChoice::Vulkan
        );
        assert_eq!(" gl ".parse::<BackendChoice>().unwrap(), BackendChoice::Gl);
        assert_eq!(
            "auto".parse::<BackendChoice>().unwrap(),
            BackendChoice::Auto
        );
        let error = "metal".parse::<BackendChoice>().unwrap_err().to_string();
        assert!(
            error.contains("\"metal\"") && error.contains("vulkan"),
            "{error}"
        );
    }

    #[test]
    fn missing_adapter_error_says_what_to_install() {
        let message = RenderError::NoAdapter {
            backends: backend_names(BackendChoice::Auto.backends()),
            hint: INSTALL_HINT,
        }
        .to_string();
        assert!(message.contains("vulkan, gl"), "{message}");
        assert!(message.contains("mesa-vulkan-drivers"), "{message}");
        assert!(message.contains("libgl1-mesa-dri"), "{message}");
        assert!(message.contains("libegl1-mesa"), "{message}");
    }

    #[test]
    fn report_display_names_adapter_backend_and_driver() {
        let report = AdapterReport {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".to_owned(),
            backend: wgpu::Backend::Vulkan,
            device_type: wgpu::DeviceType::Cpu,
            driver: "llvmpipe".to_owned(),
            driver_info: "Mesa 22.3.6".to_owned(),
        };
        let text = report.to_string();
        assert!(
            text.starts_with("llvmpipe (LLVM 15.0.6, 256 bits) ("),
            "{text}"
        );
        assert!(
            text.contains("CPU") && text.contains("driver llvmpipe Mesa 22.3.6"),
            "{text}"
        );
        assert!(report.is_software());
    }
}
