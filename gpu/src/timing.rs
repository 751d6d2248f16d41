//! GPU timestamp queries around each pass, summed per kind of pass into [`PassTimes`]: one
//! [`Timer`] per frame, shared by every technique's renderer.

use std::cell::RefCell;

use crate::context::{GpuContext, GpuError};
use crate::counters::{Counters, Pass, PassCounters, Traffic};
use crate::readback::{read_r32f, read_u64};
use penumbra_geom::VisibilityImage;

/// GPU time of each pass of one frame, from timestamp queries, in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PassTimes {
    /// Depth pre-pass.
    pub depth: f64,
    /// The shadows' build on the GPU (silhouettes, volumes and wedges; `hard` and `wedges`).
    pub build: f64,
    /// z-fail stencil pass.
    pub stencil: f64,
    /// Penumbra-wedge passes (0 for `hard`).
    pub wedge: f64,
    /// Blend passes (`wedges-blend` only).
    pub blend: f64,
    /// Resolve into V (the `gaussian` technique's read-out).
    pub resolve: f64,
    /// Light maps of the shadow-map techniques.
    pub light_map: f64,
    /// Their preprocessing passes (MDSM build, fractional-disk edges and propagation, Gaussian
    /// distance map and dilation).
    pub preprocess: f64,
    /// Their filter passes (the V pass of `pcf`, `pcss`, `mdsm`, `fractional-disk`; the
    /// blur passes of `gaussian`).
    pub filter: f64,
    /// The edge-list pass of `depth-complexity`.
    pub edge_lists: f64,
    /// Its counting pass.
    pub count: f64,
}

impl PassTimes {
    /// Sum of the passes.
    pub fn total(&self) -> f64 {
        self.depth
            + self.build
            + self.stencil
            + self.wedge
            + self.blend
            + self.resolve
            + self.light_map
            + self.preprocess
            + self.filter
            + self.edge_lists
            + self.count
    }

    /// The times of two frames' passes added, pass by pass (a frame of several lights is one
    /// frame per light).
    pub fn plus(&self, other: &PassTimes) -> PassTimes {
        PassTimes {
            depth: self.depth + other.depth,
            build: self.build + other.build,
            stencil: self.stencil + other.stencil,
            wedge: self.wedge + other.wedge,
            blend: self.blend + other.blend,
            resolve: self.resolve + other.resolve,
            light_map: self.light_map + other.light_map,
            preprocess: self.preprocess + other.preprocess,
            filter: self.filter + other.filter,
            edge_lists: self.edge_lists + other.edge_lists,
            count: self.count + other.count,
        }
    }

    fn slot(&mut self, kind: Pass) -> &mut f64 {
        match kind {
            Pass::Depth => &mut self.depth,
            Pass::Build => &mut self.build,
            Pass::Stencil => &mut self.stencil,
            Pass::Wedge => &mut self.wedge,
            Pass::Blend => &mut self.blend,
            Pass::Resolve => &mut self.resolve,
            Pass::LightMap => &mut self.light_map,
            Pass::Preprocess => &mut self.preprocess,
            Pass::Filter => &mut self.filter,
            Pass::EdgeLists => &mut self.edge_lists,
            Pass::Count => &mut self.count,
        }
    }
}

/// The queries around one pass: its two timestamps and its pipeline-statistics query, each
/// where the frame records them. A pass's `record` puts [`PassQueries::render_writes`] (or
/// [`PassQueries::compute_writes`]) in its descriptor and wraps its commands in `begin_*` and
/// `end_*`.
#[derive(Clone, Copy, Default)]
pub(crate) struct PassQueries<'a> {
    timestamps: Option<(&'a wgpu::QuerySet, u32)>,
    statistics: Option<(&'a wgpu::QuerySet, u32)>,
}

impl<'a> PassQueries<'a> {
    /// The timestamp writes of a render pass.
    pub(crate) fn render_writes(&self) -> Option<wgpu::RenderPassTimestampWrites<'a>> {
        self.timestamps
            .map(|(q, i)| wgpu::RenderPassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: Some(2 * i),
                end_of_pass_write_index: Some(2 * i + 1),
            })
    }

    /// The timestamp writes of a compute pass.
    pub(crate) fn compute_writes(&self) -> Option<wgpu::ComputePassTimestampWrites<'a>> {
        self.timestamps
            .map(|(q, i)| wgpu::ComputePassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: Some(2 * i),
                end_of_pass_write_index: Some(2 * i + 1),
            })
    }

    /// Starts the statistics of render pass `pass`.
    pub(crate) fn begin_render(&self, pass: &mut wgpu::RenderPass<'_>) {
        if let Some((q, i)) = self.statistics {
            pass.begin_pipeline_statistics_query(q, i);
        }
    }

    /// Ends them.
    pub(crate) fn end_render(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.statistics.is_some() {
            pass.end_pipeline_statistics_query();
        }
    }

    /// Starts the statistics of compute pass `pass`.
    pub(crate) fn begin_compute(&self, pass: &mut wgpu::ComputePass<'_>) {
        if let Some((q, i)) = self.statistics {
            pass.begin_pipeline_statistics_query(q, i);
        }
    }

    /// Ends them.
    pub(crate) fn end_compute(&self, pass: &mut wgpu::ComputePass<'_>) {
        if self.statistics.is_some() {
            pass.end_pipeline_statistics_query();
        }
    }
}

/// Timestamps of one frame: two per pass, at most `passes` passes; nothing where the device has
/// no timestamp queries. With counters, also each pass's statistics and traffic
/// ([`crate::counters`]).
pub struct Timer {
    queries: Option<wgpu::QuerySet>,
    kinds: RefCell<Vec<Pass>>,
    counters: Option<Counters>,
}

impl Timer {
    /// Room for `passes` passes on `ctx`'s device, counting them when `counters`. A frame of
    /// more passes than one query set can time (`wgpu::QUERY_SET_MAX_QUERIES / 2`: a scene of
    /// thousands of silhouettes under `wedges-blend`) records no pass times, rather than some
    /// of them.
    pub fn new(ctx: &GpuContext, passes: usize, counters: bool) -> Self {
        let fits = 2 * passes <= wgpu::QUERY_SET_MAX_QUERIES as usize;
        let queries = (ctx.timestamps && fits).then(|| {
            ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass times"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * passes as u32,
            })
        });
        Timer {
            queries,
            kinds: RefCell::new(Vec::with_capacity(passes)),
            counters: counters.then(|| Counters::new(ctx, passes)),
        }
    }

    /// A timer that records nothing.
    pub fn disabled() -> Self {
        Timer {
            queries: None,
            kinds: RefCell::new(Vec::new()),
            counters: None,
        }
    }

    /// The queries of the next pass, of kind `kind`, binding `traffic` (counted only when the
    /// frame counts).
    pub(crate) fn pass(&self, kind: Pass, traffic: Traffic) -> PassQueries<'_> {
        let i = self.next(kind);
        PassQueries {
            timestamps: self.queries.as_ref().map(|q| (q, i)),
            statistics: self.counters.as_ref().and_then(|c| c.next(kind, traffic)),
        }
    }

    fn next(&self, kind: Pass) -> u32 {
        let mut k = self.kinds.borrow_mut();
        k.push(kind);
        k.len() as u32 - 1
    }

    /// Records the copy of the timestamps into a readable buffer (before `enc` is submitted);
    /// `None` without timestamp queries or passes.
    pub fn resolve(&self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder) -> Option<Stamps> {
        let used = self.kinds.borrow().len() as u32;
        let q = self.queries.as_ref().filter(|_| used > 0)?;
        let bytes = 16 * used as u64;
        let resolved = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pass times"),
            size: bytes,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pass times readback"),
            size: bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        enc.resolve_query_set(q, 0..2 * used, &resolved, 0);
        enc.copy_buffer_to_buffer(&resolved, 0, &read, 0, bytes);
        Some(Stamps {
            read,
            kinds: self.kinds.borrow().clone(),
        })
    }
}

/// Timestamps copied by [`Timer::resolve`], to read once their commands were submitted.
pub struct Stamps {
    read: wgpu::Buffer,
    kinds: Vec<Pass>,
}

impl Stamps {
    /// Waits for the timestamps and sums them per kind of pass.
    pub fn read(&self, ctx: &GpuContext) -> Result<PassTimes, GpuError> {
        let t = read_u64(ctx, &self.read)?;
        let period = ctx.queue.get_timestamp_period() as f64 * 1e-6;
        let mut times = PassTimes::default();
        for (i, &k) in self.kinds.iter().enumerate() {
            *times.slot(k) += t[2 * i + 1].saturating_sub(t[2 * i]) as f64 * period;
        }
        Ok(times)
    }
}

/// A frame read back: V, the pass times where the device has timestamp queries, and the
/// passes' counts where they were asked for.
pub struct Rendered {
    /// V.
    pub image: VisibilityImage,
    /// The GPU time of each kind of pass.
    pub times: Option<PassTimes>,
    /// What each kind of pass did ([`PassCounters`]).
    pub counters: Option<PassCounters>,
}

/// Submits a frame's commands `enc` and reads back its V from `visibility` (`R32Float`), with
/// the pass times of `timer` where the device has timestamp queries and its counters where it
/// counts.
pub(crate) fn read_frame(
    ctx: &GpuContext,
    mut enc: wgpu::CommandEncoder,
    timer: &Timer,
    visibility: &wgpu::Texture,
) -> Result<Rendered, GpuError> {
    let (width, height) = (visibility.width(), visibility.height());
    let stamps = timer.resolve(&ctx.device, &mut enc);
    let counts = timer
        .counters
        .as_ref()
        .map(|c| c.resolve(&ctx.device, &mut enc));
    let data = read_r32f(ctx, &mut enc, visibility, width, height)?;
    let times = stamps.map(|s| s.read(ctx)).transpose()?;
    let pixels = u64::from(width) * u64::from(height);
    let counters = counts.map(|c| c.read(ctx, pixels)).transpose()?;
    Ok(Rendered {
        image: VisibilityImage {
            width,
            height,
            data,
        },
        times,
        counters,
    })
}
