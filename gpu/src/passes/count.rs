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

use super::complexity::COMPLEXITY_WGSL;
use super::complexity::COUNT_WGSL;
use crate::constants::{COUNT_GROUP, STATE_WORDS};

/// Loop iterations that one invocation of `count_chunk` may spend on its entries: an eighth of
/// llvmpipe's 65,535, so that the fixed work around them (the pattern's permutations, at most
/// a few hundred iterations) keeps an invocation far below that limit, and short enough for a
/// hardware driver's watchdog (a few thousand region tests per invocation).
pub const DISPATCH_ITERATIONS: u32 = 8192;

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
            args_layout,
        }
    }

    /// Records the pass over an image of `size` pixels in one compute pass: the set-up, the
    /// arguments of `chunks` chunk dispatches (in `args`, bound by `args_group`), the chunks
    /// and the finish.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (frame, inputs, args_group): (&wgpu::BindGroup, &wgpu::BindGroup, &wgpu::BindGroup),
        (args, chunks): (&wgpu::Buffer, u32),
        size: (u32, u32),
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let groups = (size.0.div_ceil(COUNT_GROUP), size.1.div_ceil(COUNT_GROUP));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("count"),
            timestamp_writes: timestamps,
        });
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        pass.set_pipeline(&self.setup);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
        pass.set_pipeline(&self.args);
        pass.set_bind_group(2, args_group, &[]);
        pass.dispatch_workgroups(chunks.div_ceil(64).max(1), 1, 1);
        pass.set_pipeline(&self.chunk);
        for c in 0..chunks {
            pass.dispatch_workgroups_indirect(args, 12 * c as u64);
        }
        pass.set_pipeline(&self.finish);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }
}

/// Words of the counting pass's buffer per pixel at `n x n` samples: V, the state between
/// dispatches ([`STATE_WORDS`]) and the counts, one byte per sample.
pub fn words_per_pixel(n: u32) -> u64 {
    1 + STATE_WORDS as u64 + (n as u64 * n as u64).div_ceil(4)
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
    }
}
