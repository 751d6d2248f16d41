//! Device creation: any adapter, hardware first, lavapipe (a CPU Vulkan) otherwise.
//!
//! Honours `WGPU_BACKEND` (e.g. `vulkan`) and `WGPU_ADAPTER_NAME` (a case-insensitive part of
//! the adapter's name), and asks the adapter for the features and limits the passes need.

/// Why no GPU device could be made.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter at all (no Vulkan, Metal, DX12 or GL driver).
    #[error(
        "no GPU adapter found (backends {backends:?}); install a driver, e.g. Mesa's lavapipe: apt-get install mesa-vulkan-drivers libvulkan1"
    )]
    NoAdapter {
        /// Backends searched.
        backends: wgpu::Backends,
    },
    /// `WGPU_ADAPTER_NAME` matches no adapter.
    #[error("WGPU_ADAPTER_NAME={wanted:?} matches none of the adapters {found:?}")]
    NoMatchingAdapter {
        /// The requested name.
        wanted: String,
        /// The adapters' names.
        found: Vec<String>,
    },
    /// The adapter lacks a feature the passes cannot do without.
    #[error("adapter {adapter} lacks {feature}")]
    MissingFeature {
        /// The adapter's name.
        adapter: String,
        /// The missing feature.
        feature: &'static str,
    },
    /// The adapter refused the device.
    #[error("the adapter refused a device: {0}")]
    RequestDevice(#[from] wgpu::RequestDeviceError),
    /// A frame's inputs that do not fit together or that the passes cannot take.
    #[error("{0}")]
    Frame(String),
    /// A frame that ran, but whose image the device may have cut short (see
    /// `complexity::SOFTWARE_LOOP_BUDGET`).
    #[error("{0}")]
    CutShort(String),
    /// A frame whose buffers would exceed the device's limits.
    #[error("{0}")]
    TooLarge(String),
    /// A readback failed.
    #[error("reading back from the GPU failed: {0}")]
    Readback(String),
}

/// A device and its queue, with what the adapter offered.
///
/// On Linux with Mesa, the device-select layer (an implicit Vulkan layer) prints
/// "XDG_RUNTIME_DIR is invalid or not set" when no display is reachable. It is harmless, and
/// `NODEVICE_SELECT=1` in the environment turns it off; the `penumbra` command sets it.
///
/// Cloning it is cheap: the device and the queue are shared handles.
#[derive(Clone)]
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's description (name, driver, backend).
    pub info: wgpu::AdapterInfo,
    /// Whether depth clipping can be turned off (z-fail caps at infinity rely on it).
    pub unclipped_depth: bool,
    /// Whether timestamp queries are available.
    pub timestamps: bool,
}

/// Features a device must have for the passes.
pub const REQUIRED_FEATURES: [(wgpu::Features, &str); 2] = [
    (
        wgpu::Features::DEPTH32FLOAT_STENCIL8,
        "DEPTH32FLOAT_STENCIL8",
    ),
    (wgpu::Features::FLOAT32_BLENDABLE, "FLOAT32_BLENDABLE"),
];

/// [`REQUIRED_FEATURES`] as one set, for `wgpu::DeviceDescriptor::required_features`.
pub fn required_features() -> wgpu::Features {
    REQUIRED_FEATURES
        .iter()
        .fold(wgpu::Features::empty(), |all, (f, _)| all | *f)
}

/// Features the passes use when the device has them: unclipped depth (the shadow volumes' far
/// caps at infinity are otherwise clipped on devices that clip them) and timestamp queries (the
/// pass times).
pub const OPTIONAL_FEATURES: wgpu::Features =
    wgpu::Features::DEPTH_CLIP_CONTROL.union(wgpu::Features::TIMESTAMP_QUERY);

/// Limits beyond wgpu's defaults that the passes need: the silhouette buffer's six colour
/// targets take 56 bytes per sample, and wgpu's default allows 32.
pub fn required_limits() -> wgpu::Limits {
    wgpu::Limits {
        max_color_attachment_bytes_per_sample: 64,
        ..Default::default()
    }
}

/// Preference order of adapter kinds: real GPUs first.
fn rank(t: wgpu::DeviceType) -> u8 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

impl GpuContext {
    /// Opens the best adapter (see the module documentation).
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        let desc = wgpu::InstanceDescriptor::new_without_display_handle().with_env();
        let backends = desc.backends;
        let instance = wgpu::Instance::new(desc);
        let mut adapters = instance.enumerate_adapters(backends).await;
        if adapters.is_empty() {
            return Err(GpuError::NoAdapter { backends });
        }
        if let Ok(wanted) = std::env::var("WGPU_ADAPTER_NAME") {
            let w = wanted.to_lowercase();
            let found: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
            adapters.retain(|a| a.get_info().name.to_lowercase().contains(&w));
            if adapters.is_empty() {
                return Err(GpuError::NoMatchingAdapter { wanted, found });
            }
        }
        adapters.sort_by_key(|a| rank(a.get_info().device_type));
        let adapter = adapters.remove(0);
        let info = adapter.get_info();
        let offered = adapter.features();
        let wanted = wgpu::Features::DEPTH_CLIP_CONTROL
            | wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::DEPTH32FLOAT_STENCIL8
            | wgpu::Features::FLOAT32_BLENDABLE;
        let features = offered & wanted;
        for (f, name) in REQUIRED_FEATURES {
            if !features.contains(f) {
                return Err(GpuError::MissingFeature {
                    adapter: info.name.clone(),
                    feature: name,
                });
            }
        }
        let limits = adapter.limits();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("penumbra"),
                required_features: features,
                // Everything the adapter allows: the colour attachment bytes per sample in
                // particular default to 32 but lavapipe offers 128.
                required_limits: limits,
                ..Default::default()
            })
            .await?;
        Self::from_device(&device, &queue)
    }

    /// The context of an application's own `device` and `queue`, which must have been created
    /// with [`REQUIRED_FEATURES`] and [`required_limits`]; [`OPTIONAL_FEATURES`] are used when
    /// present.
    pub fn from_device(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Self, GpuError> {
        let info = device.adapter_info();
        let features = device.features();
        for (f, name) in REQUIRED_FEATURES {
            if !features.contains(f) {
                return Err(GpuError::MissingFeature {
                    adapter: info.name.clone(),
                    feature: name,
                });
            }
        }
        let needed = required_limits();
        if device.limits().max_color_attachment_bytes_per_sample
            < needed.max_color_attachment_bytes_per_sample
        {
            return Err(GpuError::MissingFeature {
                adapter: info.name.clone(),
                feature: "max_color_attachment_bytes_per_sample >= 64",
            });
        }
        Ok(GpuContext {
            device: device.clone(),
            queue: queue.clone(),
            info,
            unclipped_depth: features.contains(wgpu::Features::DEPTH_CLIP_CONTROL),
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
        })
    }

    /// One line naming the adapter, for logs.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {}, {:?})",
            self.info.name, self.info.device_type, self.info.driver, self.info.backend
        )
    }
}
