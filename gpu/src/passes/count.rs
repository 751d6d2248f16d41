//! The counting pass of depth-complexity sampling (`shaders/count.wgsl`), in dispatches that
//! bound each invocation's work whatever the scene.
//!
//! One invocation per pixel adds the change of every edge of its tile's list (or of every edge,
//! where the tile's range did not fit the list) and of every crossing to its samples' counts.
//! That work grows with the scene; Mesa's llvmpipe ends an invocation's loops after 65,535
//! iterations in all, silently, and hardware drivers stop shaders that run too long. So the
//! pass runs as:
//!
//! 1. `count_setup`: each pixel's receiver, the centre's count and the length of its work,
//!    into a per-pixel state kept in the pass's storage buffer; the most dispatches a pixel
//!    needs into `demand[2]`;
//! 2. `count_args`: the indirect arguments of the chunk dispatches, the whole image for as
//!    many as a pixel needs, none for the others;
//! 3. [`chunks`] dispatches of `count_chunk`, each taking the next [`edges_per_dispatch`]
//!    entries of every pixel's work, its counts kept in the storage buffer between them; then,
//!    for a pixel whose receiver is not the rasterised one (a pixel centre within the
//!    rasteriser's snapping of an edge), [`DISPATCH_ITERATIONS`] triangles at a time of its
//!    count towards the light's centre (the stencil counted the other point);
//! 4. `count_finish`: V from the counts, and the pixels whose work was not finished (none,
//!    as many dispatches as the longest possible work are recorded) or that ran past the loop
//!    budget, counted in `demand[3]` and `demand[1]`.
//!
//! The state and counts (a byte per sample) of every pixel would not fit one storage binding
//! for large images at many samples, so the four steps run per band of [`band_rows`] rows,
//! `count_band` moving to the next; most images are one band.

use super::complexity::COMPLEXITY_WGSL;
use crate::constants::{COUNT_GROUP, DISPATCH_ITERATIONS, STATE_WORDS};
use crate::timing::PassQueries;

/// The counting pass's WGSL: its regions of light samples (`count_regions.wgsl`), its sample
/// pattern (`count_pattern.wgsl`), its receiver and the side tests made from its corners
/// (`count_receiver.wgsl`), then the pass (`count.wgsl`), one shader in four files.
pub const COUNT_WGSL: &str = concat!(
    include_str!("../shaders/count_regions.wgsl"),
    include_str!("../shaders/count_pattern.wgsl"),
    include_str!("../shaders/count_receiver.wgsl"),
    include_str!("../shaders/count.wgsl")
);

/// Loop iterations one entry of a pixel's work may take in `count_chunk` at `n x n` samples,
/// on edges of at most `faces` faces, as the shader counts them: the entry's own iteration,
/// the side of the centre (3), each face (1 + 3), the light's pyramid (5), the slab (2), the
/// plane of P and the edge (3), the clipping of the light by three lines (3 + 4 + 5 + 6 and
/// the box, at most 7), and the cells of its region (n rows, n² cells).
pub fn entry_iterations(n: u32, faces: u32) -> u32 {
    1 + 3 + 4 * faces + 5 + 2 + 3 + 25 + n + n * n
}

/// Entries of a pixel's work one dispatch takes at `n x n` samples on edges of at most `faces`
/// faces: as many as [`DISPATCH_ITERATIONS`] holds, at least one.
pub fn edges_per_dispatch(n: u32, faces: u32) -> u32 {
    (DISPATCH_ITERATIONS / entry_iterations(n, faces)).max(1)
}

/// Dispatches of `count_chunk` that finish the longest possible work: every edge and every
/// crossing, `chunk` entries at a time, then every one of `triangles` towards the centre,
/// [`DISPATCH_ITERATIONS`] at a time.
pub fn chunks(edges: u32, crossings: u32, chunk: u32, triangles: u32) -> u32 {
    (edges + crossings).div_ceil(chunk.max(1)) + triangles.div_ceil(DISPATCH_ITERATIONS)
}

/// The counting pass's four pipelines and the layout of its indirect arguments (group 2 of
/// `count_args`).
pub struct CountPass {
    setup: wgpu::ComputePipeline,
    args: wgpu::ComputePipeline,
    chunk: wgpu::ComputePipeline,
    finish: wgpu::ComputePipeline,
    band: wgpu::ComputePipeline,
    /// Group 2 of `count_args`: the indirect arguments, written.
    pub args_layout: wgpu::BindGroupLayout,
}

impl CountPass {
    /// The pipelines over the frame (group 0) and depth-complexity sampling's inputs (group 1,
    /// `complexity::inputs_layout`).
    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        inputs: &wgpu::BindGroupLayout,
    ) -> Self {
        let module = super::shader(device, "count", &format!("{COMPLEXITY_WGSL}\n{COUNT_WGSL}"));
        let args_layout = super::layout(
            device,
            "count arguments",
            wgpu::ShaderStages::COMPUTE,
            &[wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            }],
        );
        let pipeline = |entry: &str, groups: &[Option<&wgpu::BindGroupLayout>]| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry),
                bind_group_layouts: groups,
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let two = [Some(frame_layout), Some(inputs)];
        CountPass {
            setup: pipeline("count_setup", &two),
            args: pipeline(
                "count_args",
                &[Some(frame_layout), Some(inputs), Some(&args_layout)],
            ),
            chunk: pipeline("count_chunk", &two),
            finish: pipeline("count_finish", &two),
            band: pipeline("count_band", &two),
            args_layout,
        }
    }

    /// Records the pass over an image of `size` pixels in one compute pass, band by band of
    /// `band_rows` rows: the set-up, the arguments of `chunks` chunk dispatches (in `args`,
    /// bound by `args_group`), the chunks, the finish, and the move to the next band.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (frame, inputs, args_group): (&wgpu::BindGroup, &wgpu::BindGroup, &wgpu::BindGroup),
        (args, chunks): (&wgpu::Buffer, u32),
        (size, band_rows): ((u32, u32), u32),
        queries: PassQueries<'_>,
    ) {
        let band_rows = band_rows.max(1);
        let groups = (
            size.0.div_ceil(COUNT_GROUP),
            band_rows.div_ceil(COUNT_GROUP),
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("count"),
            timestamp_writes: queries.compute_writes(),
        });
        queries.begin_compute(&mut pass);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        pass.set_bind_group(2, args_group, &[]);
        for _ in 0..size.1.div_ceil(band_rows) {
            pass.set_pipeline(&self.setup);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
            pass.set_pipeline(&self.args);
            pass.dispatch_workgroups(chunks.div_ceil(64).max(1), 1, 1);
            pass.set_pipeline(&self.chunk);
            for c in 0..chunks {
                pass.dispatch_workgroups_indirect(args, 12 * c as u64);
            }
            pass.set_pipeline(&self.finish);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
            pass.set_pipeline(&self.band);
            pass.dispatch_workgroups(1, 1, 1);
        }
        queries.end_compute(&mut pass);
    }
}

/// Bytes of the counting pass's buffer for an image of `size` pixels at `n x n` samples
/// keeping `band_rows` rows at once: V of every pixel (4), and for each pixel of a band its
/// state between dispatches ([`STATE_WORDS`] words) and its counts, one byte per sample.
pub fn count_bytes(size: (u32, u32), n: u32, band_rows: u32) -> u64 {
    let pixels = size.0 as u64 * size.1 as u64;
    4 * pixels + band_rows as u64 * size.0 as u64 * band_bytes(n)
}

/// Bytes per pixel of a band at `n x n` samples: its state and its counts.
fn band_bytes(n: u32) -> u64 {
    4 * (STATE_WORDS as u64 + (n as u64 * n as u64).div_ceil(4))
}

/// Bytes of the counting pass's buffer that a depth-complexity frame of `size` pixels at
/// `samples` light samples per pixel allocates on a device whose storage bindings hold at most
/// `limit` bytes ([`storage_binding_limit`]): V of every pixel, and each pixel's state and
/// counts for as many rows at once as fit (`band_rows`), the whole image unless it does not
/// fit one binding. `samples` is rounded up to a square. `None` where not even `COUNT_GROUP`
/// rows fit: the frame is refused (`GpuError::TooLarge`).
///
/// ```
/// use penumbra_gpu::count_buffer_bytes;
///
/// // 320 x 240 at 256 samples: 4 bytes of V and 288 of state and counts per pixel.
/// assert_eq!(count_buffer_bytes((320, 240), 256, 128 << 20), Some(320 * 240 * (4 + 288)));
/// // 1920 x 1080 at 256 samples: bands of rows, bounded by the binding.
/// assert!(count_buffer_bytes((1920, 1080), 256, 128 << 20).unwrap() <= 128 << 20);
/// assert_eq!(count_buffer_bytes((10_000, 10_000), 1024, 128 << 20), None);
/// ```
pub fn count_buffer_bytes(size: (u32, u32), samples: u32, limit: u64) -> Option<u64> {
    let n = (samples as f64).sqrt().ceil() as u32;
    band_rows(size, n, limit, 0).map(|rows| count_bytes(size, n, rows))
}

/// The most bytes one storage binding of a device with `limits` holds: the counting pass's
/// buffer and the edge list must each fit one.
pub fn storage_binding_limit(limits: &wgpu::Limits) -> u64 {
    limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size)
}

/// The most rows of an image of `size` pixels at `n x n` samples whose state and counts fit
/// in `limit` bytes with V, a multiple of `COUNT_GROUP` (or the whole image), at most `most`
/// (0: no other bound); `None` when not even `COUNT_GROUP` rows fit.
pub fn band_rows(size: (u32, u32), n: u32, limit: u64, most: u32) -> Option<u32> {
    let v = 4 * size.0 as u64 * size.1 as u64;
    let row = size.0 as u64 * band_bytes(n);
    let fit = (limit.checked_sub(v)? / row.max(1)).min(size.1 as u64) as u32;
    let wanted = if most == 0 { fit } else { fit.min(most) };
    let rows = if wanted >= size.1 {
        size.1
    } else {
        wanted / COUNT_GROUP * COUNT_GROUP
    };
    (rows > 0).then_some(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constants::MAX_AXIS;

    #[test]
    fn a_dispatch_takes_at_most_its_iterations_at_every_sample_count() {
        for n in 1..=MAX_AXIS {
            for faces in [1, 2, 3, 8] {
                let k = edges_per_dispatch(n, faces);
                assert!(k >= 1);
                assert!(
                    k * entry_iterations(n, faces) <= DISPATCH_ITERATIONS,
                    "{n} {faces}"
                );
            }
        }
        assert_eq!([8, 16, 32].map(|n| edges_per_dispatch(n, 2)), [68, 25, 7]);
        assert_eq!(chunks(19_629, 0, 25, 38_658), 791);
        assert_eq!(chunks(0, 0, 25, 0), 0);
        let mib = 128 << 20;
        // 320x240 at 256 samples: one band; 1920x1080: bands of whole groups of rows.
        assert_eq!(band_rows((320, 240), 16, mib, 0), Some(240));
        let rows = band_rows((1920, 1080), 16, mib, 0).unwrap();
        assert!(rows < 1080 && rows % COUNT_GROUP == 0);
        assert!(count_bytes((1920, 1080), 16, rows) <= mib);
        assert!(count_bytes((1920, 1080), 16, rows + COUNT_GROUP) > mib);
        assert_eq!(band_rows((48, 36), 8, mib, 8), Some(8));
        assert_eq!(band_rows((48, 36), 8, mib, 3), None);
        assert_eq!(band_rows((10_000, 10_000), 32, mib, 0), None);
    }
}
