//! Blend pass of penumbra-wedges blending: drives `shaders/blend.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Formats of the silhouette buffer's targets: signed area per part (added), the inner
/// half-wedges' cover of each part's border (added), one rectangle per part in 8 bits per
/// coordinate (kept by `Min` blending). 16 + 8 + 4 x 4 = 40 bytes per pixel.
pub const SILHOUETTE_FORMATS: [wgpu::TextureFormat; 6] = [
    wgpu::TextureFormat::Rgba32Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8Unorm,
];

/// The first `SILHOUETTE_ADDED` targets of [`SILHOUETTE_FORMATS`] are added (areas, cover);
/// the others hold encoded rectangles, kept by `Min`.
pub const SILHOUETTE_ADDED: usize = 2;

/// Words (`u32`) per pixel of the final buffer, a storage buffer: areas as 16-bit unorm (2),
/// rectangles as 8-bit unorm (4). `FINAL_WORDS` in `frame.wgsl`.
pub const FINAL_WORDS: u64 = 6;

/// Bytes per pixel of the visibility buffers of `wedges-blend`: one silhouette buffer and the
/// final buffer.
pub fn bytes_per_pixel() -> u64 {
    let silhouette: u64 = SILHOUETTE_FORMATS
        .iter()
        .map(|f| f.block_copy_size(None).unwrap_or(0) as u64)
        .sum();
    silhouette + 4 * FINAL_WORDS
}

/// The screen rectangle a blend dispatch covers, in pixels (`Region` in `blend.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct Region {
    /// Top-left pixel.
    pub origin: [u32; 2],
    /// Width and height.
    pub size: [u32; 2],
}

const _: () = assert!(std::mem::size_of::<Region>() == 16);

impl Region {
    /// Whether the two regions share a pixel.
    pub fn overlaps(&self, other: &Region) -> bool {
        (0..2).all(|i| {
            self.origin[i] < other.origin[i] + other.size[i]
                && other.origin[i] < self.origin[i] + self.size[i]
        })
    }
}

/// Occluders in groups whose screen regions are pairwise disjoint (first fit, in order): their
/// silhouette buffers cannot meet, so each group's stencil, wedge and blend passes serve all of
/// its occluders at once (seed 004's per-silhouette loop, one pass per group instead of one per
/// silhouette). Empty regions are left out.
pub fn disjoint_groups(regions: &[Region]) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, r) in regions.iter().enumerate() {
        if r.size[0] == 0 || r.size[1] == 0 {
            continue;
        }
        match groups
            .iter_mut()
            .find(|g| g.iter().all(|&j| !regions[j].overlaps(r)))
        {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
}

/// Workgroup side of `blend.wgsl`.
const WORKGROUP: u32 = 8;

/// The blend pipeline.
pub struct BlendPass {
    pipeline: wgpu::ComputePipeline,
    /// Layout of group 1: the silhouette buffer's six textures, its stencil counts and the final
    /// buffer.
    pub inputs_layout: wgpu::BindGroupLayout,
    /// Layout of group 2: the [`Region`], with a dynamic offset.
    pub region_layout: wgpu::BindGroupLayout,
}

impl BlendPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let module = super::shader(device, "blend", include_str!("../shaders/blend.wgsl"));
        let mut entries = vec![super::float_texture(); SILHOUETTE_FORMATS.len()];
        entries.push(wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        });
        entries.push(wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        });
        let compute = wgpu::ShaderStages::COMPUTE;
        let inputs_layout = super::layout(device, "blend inputs", compute, &entries);
        let region_layout = super::layout(
            device,
            "blend region",
            compute,
            &[wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<Region>() as u64),
            }],
        );
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("blend"),
            bind_group_layouts: &[
                Some(frame_layout),
                Some(&inputs_layout),
                Some(&region_layout),
            ],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("blend"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("blend"),
            compilation_options: Default::default(),
            cache: None,
        });
        BlendPass {
            pipeline,
            inputs_layout,
            region_layout,
        }
    }

    /// Blends the silhouette buffer into the final one over each of `regions`, pairs of the
    /// dynamic offset of a [`Region`] in `region_group` and the region (`inputs`: the
    /// silhouette buffer, its stencil counts, the final buffer). The regions must not overlap.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        inputs: &wgpu::BindGroup,
        region_group: &wgpu::BindGroup,
        regions: &[(u32, Region)],
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("blend"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        for (offset, region) in regions {
            pass.set_bind_group(2, region_group, &[*offset]);
            pass.dispatch_workgroups(
                region.size[0].div_ceil(WORKGROUP),
                region.size[1].div_ceil(WORKGROUP),
                1,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(x: u32, y: u32, w: u32, h: u32) -> Region {
        Region {
            origin: [x, y],
            size: [w, h],
        }
    }

    #[test]
    fn groups_hold_pairwise_disjoint_regions_and_every_non_empty_one() {
        let regions = [
            r(0, 0, 10, 10),
            r(5, 5, 10, 10),
            r(10, 0, 10, 10),
            r(0, 0, 0, 0),
            r(12, 12, 5, 5),
            r(0, 0, 100, 100),
        ];
        assert!(regions[0].overlaps(&regions[1]));
        assert!(
            !regions[0].overlaps(&regions[2]),
            "touching is not overlapping"
        );
        let groups = disjoint_groups(&regions);
        let mut seen: Vec<usize> = groups.iter().flatten().copied().collect();
        seen.sort();
        assert_eq!(seen, [0, 1, 2, 4, 5]);
        for g in &groups {
            for (i, &a) in g.iter().enumerate() {
                for &b in &g[i + 1..] {
                    assert!(!regions[a].overlaps(&regions[b]), "{a} and {b}");
                }
            }
        }
        assert_eq!(groups, [vec![0, 2, 4], vec![1], vec![5]]);
    }
}
