//! GPU timestamp queries around each pass, summed per kind of pass into [`PassTimes`]: one
//! [`Timer`] per frame, shared by every technique's renderer.

use std::cell::RefCell;

use crate::context::{GpuContext, GpuError};
use crate::readback::{read_r32f, read_u64};
use penumbra_geom::VisibilityImage;

/// GPU time of each pass of one frame, from timestamp queries, in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PassTimes {
    /// Depth pre-pass.
    pub depth: f64,
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

    fn slot(&mut self, kind: Pass) -> &mut f64 {
        match kind {
            Pass::Depth => &mut self.depth,
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

/// The kind of a pass: the field of [`PassTimes`] it adds to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// [`PassTimes::depth`].
    Depth,
    /// [`PassTimes::stencil`].
    Stencil,
    /// [`PassTimes::wedge`].
    Wedge,
    /// [`PassTimes::blend`].
    Blend,
    /// [`PassTimes::resolve`].
    Resolve,
    /// [`PassTimes::light_map`].
    LightMap,
    /// [`PassTimes::preprocess`].
    Preprocess,
    /// [`PassTimes::filter`].
    Filter,
    /// [`PassTimes::edge_lists`].
    EdgeLists,
    /// [`PassTimes::count`].
    Count,
}

/// Timestamps of one frame: two per pass, at most `passes` passes; nothing where the device has
/// no timestamp queries.
pub struct Timer {
    queries: Option<wgpu::QuerySet>,
    kinds: RefCell<Vec<Pass>>,
}

impl Timer {
    /// Room for `passes` passes on `ctx`'s device. A frame of more passes than one query set
    /// can time (`wgpu::QUERY_SET_MAX_QUERIES / 2`: a scene of thousands of silhouettes under
    /// `wedges-blend`) records no pass times, rather than some of them.
    pub fn new(ctx: &GpuContext, passes: usize) -> Self {
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
        }
    }

    /// A timer that records nothing.
    pub fn disabled() -> Self {
        Timer {
            queries: None,
            kinds: RefCell::new(Vec::new()),
        }
    }

    /// The timestamp writes of the next render pass, of kind `kind`.
    pub fn render(&self, kind: Pass) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let i = self.next(kind);
        self.queries
            .as_ref()
            .map(|q| wgpu::RenderPassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: Some(2 * i),
                end_of_pass_write_index: Some(2 * i + 1),
            })
    }

    /// The timestamp writes of the next compute pass, of kind `kind`.
    pub fn compute(&self, kind: Pass) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let i = self.next(kind);
        self.queries
            .as_ref()
            .map(|q| wgpu::ComputePassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: Some(2 * i),
                end_of_pass_write_index: Some(2 * i + 1),
            })
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

/// Submits a frame's commands `enc` and reads back its V from `visibility` (`R32Float`), with
/// the pass times of `timer` where the device has timestamp queries.
pub(crate) fn read_frame(
    ctx: &GpuContext,
    mut enc: wgpu::CommandEncoder,
    timer: &Timer,
    visibility: &wgpu::Texture,
) -> Result<(VisibilityImage, Option<PassTimes>), GpuError> {
    let (width, height) = (visibility.width(), visibility.height());
    let stamps = timer.resolve(&ctx.device, &mut enc);
    let data = read_r32f(ctx, &mut enc, visibility, width, height)?;
    let times = stamps.map(|s| s.read(ctx)).transpose()?;
    Ok((
        VisibilityImage {
            width,
            height,
            data,
        },
        times,
    ))
}
