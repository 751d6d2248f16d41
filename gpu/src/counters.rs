//! What each pass did, in counts that do not depend on the device's speed: the invocations of
//! its shaders and the primitives it rasterised (wgpu's pipeline-statistics queries, where the
//! device offers `PIPELINE_STATISTICS_QUERY`: Vulkan and DX12, lavapipe included), and the bytes
//! of the buffers and textures it binds for reading and for writing (known from their sizes, on
//! every device). Summed per kind of pass into [`PassCounters`].

use std::cell::RefCell;

use crate::context::{GpuContext, GpuError};
use crate::readback::read_u64;

/// The kind of a pass, under which its time and its counts are summed: the field of
/// [`PassTimes`](crate::PassTimes) it adds to, and its [`PassCounts::pass`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// [`crate::PassTimes::depth`].
    Depth,
    /// [`crate::PassTimes::build`].
    Build,
    /// [`crate::PassTimes::stencil`].
    Stencil,
    /// [`crate::PassTimes::wedge`].
    Wedge,
    /// [`crate::PassTimes::blend`].
    Blend,
    /// [`crate::PassTimes::resolve`].
    Resolve,
    /// [`crate::PassTimes::light_map`].
    LightMap,
    /// [`crate::PassTimes::preprocess`].
    Preprocess,
    /// [`crate::PassTimes::filter`].
    Filter,
    /// [`crate::PassTimes::edge_lists`].
    EdgeLists,
    /// [`crate::PassTimes::count`].
    Count,
}

impl Pass {
    /// The name of its field of [`PassTimes`](crate::PassTimes).
    pub(crate) fn name(self) -> &'static str {
        match self {
            Pass::Depth => "depth",
            Pass::Build => "build",
            Pass::Stencil => "stencil",
            Pass::Wedge => "wedge",
            Pass::Blend => "blend",
            Pass::Resolve => "resolve",
            Pass::LightMap => "light_map",
            Pass::Preprocess => "preprocess",
            Pass::Filter => "filter",
            Pass::EdgeLists => "edge_lists",
            Pass::Count => "count",
        }
    }
}

/// The statistics each query records, in the order wgpu resolves them.
const STATISTICS: wgpu::PipelineStatisticsTypes = wgpu::PipelineStatisticsTypes::all();

/// Values one statistics query resolves to (one per flag of [`STATISTICS`]).
const VALUES: usize = 5;

/// The pipeline statistics of the passes of one kind, summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Statistics {
    /// Vertex shader invocations.
    pub vertices: u64,
    /// Primitives that reached the clipper (one per triangle drawn).
    pub clipper_in: u64,
    /// Primitives the clipper passed on to the rasteriser.
    pub primitives: u64,
    /// Fragment shader invocations (2x2 quads counted whole on most devices).
    pub fragments: u64,
    /// Compute shader invocations (workgroups dispatched times the workgroup size).
    pub compute: u64,
}

impl Statistics {
    fn add(&mut self, v: &[u64]) {
        self.vertices += v[0];
        self.clipper_in += v[1];
        self.primitives += v[2];
        self.fragments += v[3];
        self.compute += v[4];
    }
}

/// What the passes of one kind did in one frame.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PassCounts {
    /// The kind of pass, as [`crate::PassTimes`] names its fields ("depth", "build", "stencil", "wedge",
    /// "blend", "resolve", "light_map", "preprocess", "filter", "edge_lists", "count").
    pub pass: &'static str,
    /// Passes of this kind recorded.
    pub passes: u32,
    /// Their pipeline statistics; `None` where the device has no statistics queries.
    pub statistics: Option<Statistics>,
    /// Bytes of the buffers and textures they bind for reading: whole textures and storage or
    /// uniform buffers, and the vertex data they draw. An upper bound of what they read.
    pub bytes_read: u64,
    /// Bytes of the attachments and storage resources they write, whole.
    pub bytes_written: u64,
}

/// The counts of one frame's passes, per kind of pass in the order they first ran.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PassCounters {
    /// Pixels of the image, to read the counts per pixel.
    pub pixels: u64,
    /// One entry per kind of pass.
    pub passes: Vec<PassCounts>,
    /// The bytes the frame wrote to the GPU from the CPU, for the volume techniques (`None`
    /// for the others): the scene's vertices (and topology) as a one-shot frame uploads them,
    /// the shadow volumes and wedges the CPU built, the frame's uniforms and lists.
    pub uploads: Option<crate::Uploads>,
}

impl PassCounters {
    /// Passes recorded in the frame.
    pub fn pass_count(&self) -> u32 {
        self.passes.iter().map(|p| p.passes).sum()
    }

    /// Shader invocations of every kind (vertex, fragment and compute) per pixel; `None`
    /// without statistics queries.
    pub fn invocations_per_pixel(&self) -> Option<f64> {
        let mut total = 0u64;
        for p in &self.passes {
            let s = p.statistics.as_ref()?;
            total += s.vertices + s.fragments + s.compute;
        }
        Some(total as f64 / self.pixels.max(1) as f64)
    }
}

/// Something whose size in bytes a pass moves: a buffer, a texture, a view of one, or a number
/// of bytes.
pub(crate) trait Footprint {
    /// Its size in bytes.
    fn bytes(&self) -> u64;
}

impl Footprint for u64 {
    fn bytes(&self) -> u64 {
        *self
    }
}

impl Footprint for wgpu::Buffer {
    fn bytes(&self) -> u64 {
        self.size()
    }
}

impl Footprint for wgpu::Texture {
    fn bytes(&self) -> u64 {
        let f = self.format();
        // Combined depth-stencil formats have no copy size of their own: their aspects'.
        let aspect = |a| f.block_copy_size(Some(a)).unwrap_or(0);
        let texel = f.block_copy_size(None).unwrap_or_else(|| {
            aspect(wgpu::TextureAspect::DepthOnly) + aspect(wgpu::TextureAspect::StencilOnly)
        });
        // Depth24Plus has no copy size either: at least three bytes, four on every device.
        let texel = if texel == 0 { 4 } else { texel };
        u64::from(self.width())
            * u64::from(self.height())
            * u64::from(self.depth_or_array_layers())
            * u64::from(texel)
            * u64::from(self.sample_count())
    }
}

impl Footprint for wgpu::TextureView {
    fn bytes(&self) -> u64 {
        self.texture().bytes()
    }
}

/// The bytes a pass binds for reading and for writing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Traffic {
    read: u64,
    written: u64,
}

impl Traffic {
    /// Nothing yet.
    pub(crate) fn new() -> Self {
        Self::default()
    }

    /// And `r`, read.
    pub(crate) fn reads(mut self, r: &impl Footprint) -> Self {
        self.read += r.bytes();
        self
    }

    /// And `w`, written.
    pub(crate) fn writes(mut self, w: &impl Footprint) -> Self {
        self.written += w.bytes();
        self
    }

    /// And `rw`, read and written (a depth-stencil attachment that is tested and updated, a
    /// storage buffer accumulated into).
    pub(crate) fn updates(self, rw: &impl Footprint) -> Self {
        self.reads(rw).writes(rw)
    }

    /// The part `some / all` of it (a pass that touches some tiles of its images).
    pub(crate) fn scaled(self, some: u64, all: u64) -> Self {
        Traffic {
            read: part(self.read, some, all),
            written: part(self.written, some, all),
        }
    }
}

/// The part `drawn / all` of `bytes` (vertex data of which a pass draws some ranges).
pub(crate) fn part(bytes: u64, drawn: u64, all: u64) -> u64 {
    if all == 0 {
        0
    } else {
        (u128::from(bytes) * u128::from(drawn) / u128::from(all)) as u64
    }
}

/// The counters of one frame: a statistics query per pass where the device has them, and the
/// traffic of every pass.
pub(crate) struct Counters {
    queries: Option<wgpu::QuerySet>,
    traffic: RefCell<Vec<(Pass, Traffic)>>,
}

impl Counters {
    /// Room for `passes` passes on `ctx`'s device. A frame of more passes than one query set
    /// holds records their traffic only.
    pub(crate) fn new(ctx: &GpuContext, passes: usize) -> Self {
        let fits = passes <= wgpu::QUERY_SET_MAX_QUERIES as usize;
        let queries = (ctx.statistics && fits).then(|| {
            ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass statistics"),
                ty: wgpu::QueryType::PipelineStatistics(STATISTICS),
                count: passes as u32,
            })
        });
        Counters {
            queries,
            traffic: RefCell::new(Vec::with_capacity(passes)),
        }
    }

    /// Records the next pass, of kind `kind` moving `traffic`: the query to wrap it in.
    pub(crate) fn next(&self, kind: Pass, traffic: Traffic) -> Option<(&wgpu::QuerySet, u32)> {
        let mut t = self.traffic.borrow_mut();
        t.push((kind, traffic));
        let i = t.len() as u32 - 1;
        self.queries
            .as_ref()
            .filter(|q| i < q.count())
            .map(|q| (q, i))
    }

    /// Records the copy of the statistics into a readable buffer (before `enc` is submitted).
    pub(crate) fn resolve(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
    ) -> CountsReadback {
        let traffic = self.traffic.borrow().clone();
        let used = traffic.len() as u32;
        // Every pass had its query, or none is read.
        let all_queried = |q: &&wgpu::QuerySet| used > 0 && used <= q.count();
        let read = self.queries.as_ref().filter(all_queried).map(|q| {
            let bytes = (8 * VALUES) as u64 * u64::from(used);
            let resolved = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pass statistics"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pass statistics readback"),
                size: bytes,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            enc.resolve_query_set(q, 0..used, &resolved, 0);
            enc.copy_buffer_to_buffer(&resolved, 0, &read, 0, bytes);
            read
        });
        CountsReadback { read, traffic }
    }
}

/// The statistics copied by [`Counters::resolve`] and the passes' traffic.
pub(crate) struct CountsReadback {
    read: Option<wgpu::Buffer>,
    traffic: Vec<(Pass, Traffic)>,
}

impl CountsReadback {
    /// Waits for the statistics and sums everything per kind of pass, for an image of `pixels`.
    pub(crate) fn read(&self, ctx: &GpuContext, pixels: u64) -> Result<PassCounters, GpuError> {
        let values = self.read.as_ref().map(|b| read_u64(ctx, b)).transpose()?;
        let mut passes: Vec<PassCounts> = Vec::new();
        for (i, &(kind, traffic)) in self.traffic.iter().enumerate() {
            let at = match passes.iter().position(|p| p.pass == kind.name()) {
                Some(at) => at,
                None => {
                    passes.push(PassCounts {
                        pass: kind.name(),
                        passes: 0,
                        statistics: values.as_ref().map(|_| Statistics::default()),
                        bytes_read: 0,
                        bytes_written: 0,
                    });
                    passes.len() - 1
                }
            };
            let p = &mut passes[at];
            p.passes += 1;
            p.bytes_read += traffic.read;
            p.bytes_written += traffic.written;
            if let (Some(s), Some(v)) = (p.statistics.as_mut(), values.as_ref()) {
                s.add(&v[VALUES * i..VALUES * (i + 1)]);
            }
        }
        Ok(PassCounters {
            pixels,
            passes,
            uploads: None,
        })
    }
}
