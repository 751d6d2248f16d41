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
    /// A technique that a [`crate::GpuScene`] does not record: the shadow-map techniques and the
    /// CPU references.
    #[error(
        "{technique}: a GpuScene records the volume techniques (hard, wedges, wedges-blend) and depth-complexity"
    )]
    NotRecordable {
        /// The technique asked for.
        technique: penumbra_geom::Technique,
    },
    /// [`crate::GpuScene::set_positions`] given another number of vertices than the mesh has.
    #[error("mesh {mesh} has {expected} vertices, {given} positions were given")]
    PositionCount {
        /// The mesh.
        mesh: usize,
        /// Its vertices.
        expected: usize,
        /// The positions given.
        given: usize,
    },
    /// [`crate::GpuScene::set_positions`] given a position that is not finite.
    #[error("mesh {mesh}: vertex {vertex} is not finite")]
    NonFinitePosition {
        /// The mesh.
        mesh: usize,
        /// The vertex.
        vertex: usize,
    },
    /// [`crate::GpuScene::render_lights`] given another number of targets than of lights.
    #[error("{lights} lights and {targets} targets: one target per light")]
    LightTargets {
        /// The lights.
        lights: usize,
        /// The targets.
        targets: usize,
    },
    /// A G-buffer or target whose size is not the camera's.
    #[error(
        "the camera's image is {} x {} pixels, the {what} {} x {}",
        camera.0,
        camera.1,
        size.0,
        size.1
    )]
    SizeMismatch {
        /// The camera's image size in pixels.
        camera: (u32, u32),
        /// What has another size: `"G-buffer"` or `"target"`.
        what: &'static str,
        /// Its size.
        size: (u32, u32),
    },
    /// A target that is not an `R32Float` render attachment.
    #[error(
        "the target is {format:?} with usage {usage:?}: it must be R32Float with RENDER_ATTACHMENT"
    )]
    TargetFormat {
        /// The target's format.
        format: wgpu::TextureFormat,
        /// Its usages.
        usage: wgpu::TextureUsages,
    },
    /// A number of light samples that depth-complexity sampling on the GPU does not take.
    #[error(
        "{samples} light samples: depth-complexity sampling on the GPU takes a perfect square up to {most} (the CPU takes up to 65536)"
    )]
    LightSamples {
        /// The samples asked for.
        samples: u32,
        /// The most it takes ([`crate::MAX_SAMPLES`]).
        most: u32,
    },
    /// A depth-complexity frame that ran, but that the device may have cut short: pixels that
    /// need more loop iterations than a software device runs (see
    /// [`crate::SOFTWARE_LOOP_BUDGET`]).
    #[error(
        "{adapter}: {pixels} pixels need more loop iterations than this software device runs ({budget} at most per invocation): their V would be wrong"
    )]
    CutShort {
        /// The device, as [`GpuContext::describe`] names it.
        adapter: String,
        /// Pixels that may have been cut short.
        pixels: u32,
        /// Loop iterations an invocation may take.
        budget: u32,
    },
    /// A depth-complexity frame whose storage buffers (V, or the edge list) would exceed one
    /// binding of the device.
    #[error(
        "depth-complexity at {} x {} pixels needs a storage buffer of {bytes} bytes (V, or an edge list of {entries} entries), more than the device binds ({limit})",
        size.0,
        size.1
    )]
    TooLarge {
        /// The image size in pixels.
        size: (u32, u32),
        /// Bytes of the largest buffer.
        bytes: u64,
        /// Entries of the edge list.
        entries: u32,
        /// The most bytes one storage binding may hold on the device.
        limit: u64,
    },
    /// A readback failed.
    #[error("reading back from the GPU failed while {stage}: {reason}")]
    Readback {
        /// What it was doing: waiting for the device, or mapping the buffer.
        stage: &'static str,
        /// wgpu's reason.
        reason: String,
    },
}

/// A device and its queue, with what the adapter offered.
///
/// On Linux with Mesa, the device-select layer (an implicit Vulkan layer) prints
/// "error: XDG_RUNTIME_DIR is invalid or not set" when no display is reachable. It is harmless
/// (the layer only reorders adapters, which [`GpuContext::new`] ranks itself), so
/// [`GpuContext::new`] sets `NODEVICE_SELECT=1` before it creates its wgpu instance, unless the
/// variable is already set.
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
    /// Whether pipeline-statistics queries are available (the passes' counters).
    pub statistics: bool,
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
/// caps at infinity are otherwise clipped on devices that clip them), timestamp queries (the
/// pass times) and pipeline-statistics queries (the passes' counters).
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::DEPTH_CLIP_CONTROL
    .union(wgpu::Features::TIMESTAMP_QUERY)
    .union(wgpu::Features::PIPELINE_STATISTICS_QUERY);

/// Limits beyond wgpu's defaults that the passes need: the silhouette buffer's six colour
/// targets take 56 bytes per sample, and wgpu's default allows 32; the counting pass of
/// depth-complexity binds nine storage buffers (the scene's edges, faces, crossings and
/// triangles, the tiles' ranges and lists, the demand, V with the pixels' state, and its
/// dispatches' arguments), and wgpu's default allows eight (desktop Vulkan, Metal and D3D12
/// devices allow far more).
pub fn required_limits() -> wgpu::Limits {
    wgpu::Limits {
        max_color_attachment_bytes_per_sample: 64,
        max_storage_buffers_per_shader_stage: 9,
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

/// Turns Mesa's device-select layer off (`NODEVICE_SELECT=1`) unless the environment says
/// otherwise: the layer only reorders adapters, and prints an "error:" line on stderr when no
/// display is reachable. [`GpuContext::new`] calls it; an application that makes its own wgpu
/// instance may call it first.
pub fn quiet_device_select() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if std::env::var_os("NODEVICE_SELECT").is_none() {
            // SAFETY: the environment is written once, before this library creates its
            // first wgpu instance (whose Vulkan loader reads it), and by nothing else of
            // this library; a program that reads or writes the environment on other
            // threads while it opens its first device should set the variable itself.
            #[allow(unsafe_code)] // `set_var` is unsafe since edition 2024; see the line above.
            unsafe {
                std::env::set_var("NODEVICE_SELECT", "1")
            };
        }
    });
}

impl GpuContext {
    /// Opens the best adapter (see the module documentation).
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        quiet_device_select();
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
        let wanted = OPTIONAL_FEATURES | required_features();
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
        if device.limits().max_storage_buffers_per_shader_stage
            < needed.max_storage_buffers_per_shader_stage
        {
            return Err(GpuError::MissingFeature {
                adapter: info.name.clone(),
                feature: "max_storage_buffers_per_shader_stage >= 9",
            });
        }
        Ok(GpuContext {
            device: device.clone(),
            queue: queue.clone(),
            info,
            unclipped_depth: features.contains(wgpu::Features::DEPTH_CLIP_CONTROL),
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            statistics: features.contains(wgpu::Features::PIPELINE_STATISTICS_QUERY),
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
