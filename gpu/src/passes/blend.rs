//! Blend pass of penumbra-wedges blending: drives `shaders/blend.wgsl`.

use crate::timing::PassQueries;
use bytemuck::{Pod, Zeroable};

use crate::constants::{MAX_WORKGROUPS, TILE};

/// Forest et al.'s blending of one silhouette's part into the final buffer's, shared by the
/// blend of each group and the tiled pass (`passes::blend_tiles`).
pub const BLEND_PARTS_WGSL: &str = include_str!("../shaders/blend_parts.wgsl");

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

/// Bytes per pixel of the visibility buffers of `wedges-blend`: one silhouette buffer and the
/// final buffer.
#[cfg(test)]
fn bytes_per_pixel() -> u64 {
    let silhouette: u64 = SILHOUETTE_FORMATS
        .iter()
        .map(|f| f.block_copy_size(None).unwrap_or(0) as u64)
        .sum();
    silhouette + 4 * crate::constants::FINAL_WORDS
}

/// A set of the screen's [`TILE`]-pixel tiles: where one silhouette can shadow, or a group's
/// union of those. A bit per tile, row by row, stored only over the span of 64-tile words
/// between its first and last tile, so that a small shadow on a large image (or many of them)
/// costs little memory and time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TileMask {
    /// Tiles across and down.
    size: [u32; 2],
    /// Index of the first stored word.
    first: usize,
    /// Words `first..first + bits.len()`.
    bits: Vec<u64>,
}

impl TileMask {
    /// No tile of a `width` x `height`-pixel screen.
    pub fn new(width: u32, height: u32) -> Self {
        TileMask {
            size: [width.div_ceil(TILE), height.div_ceil(TILE)],
            first: 0,
            bits: Vec::new(),
        }
    }

    /// Stores the words `lo..hi` (and those already stored).
    fn reach(&mut self, lo: usize, hi: usize) {
        if self.bits.is_empty() {
            self.first = lo;
            self.bits = vec![0; hi - lo];
            return;
        }
        if lo < self.first {
            self.bits
                .splice(0..0, std::iter::repeat_n(0, self.first - lo));
            self.first = lo;
        }
        if hi > self.first + self.bits.len() {
            self.bits.resize(hi - self.first, 0);
        }
    }

    /// Adds the tiles that hold a pixel of the rectangle `[x0, x1) x [y0, y1)` (clipped to the
    /// screen).
    pub fn insert_pixels(&mut self, x0: u32, y0: u32, x1: u32, y1: u32) {
        let (tx0, ty0) = (x0 / TILE, y0 / TILE);
        let tx1 = x1.div_ceil(TILE).min(self.size[0]);
        let ty1 = y1.div_ceil(TILE).min(self.size[1]);
        if x0 >= x1 || y0 >= y1 || tx0 >= tx1 || ty0 >= ty1 {
            return;
        }
        let across = self.size[0];
        let index = |tx: u32, ty: u32| (ty * across + tx) as usize;
        self.reach(index(tx0, ty0) / 64, index(tx1 - 1, ty1 - 1) / 64 + 1);
        for ty in ty0..ty1 {
            for tx in tx0..tx1 {
                let i = index(tx, ty);
                self.bits[i / 64 - self.first] |= 1 << (i % 64);
            }
        }
    }

    /// Every tile.
    pub fn fill(&mut self) {
        self.insert_pixels(0, 0, self.size[0] * TILE, self.size[1] * TILE);
    }

    /// Whether it holds tile number `i` (row by row).
    fn holds(&self, i: usize) -> bool {
        let w = i / 64;
        w >= self.first
            && w < self.first + self.bits.len()
            && self.bits[w - self.first] & (1 << (i % 64)) != 0
    }

    /// Whether it holds the tile of pixel `(x, y)`.
    #[cfg(test)]
    pub(crate) fn holds_pixel(&self, x: u32, y: u32) -> bool {
        let (tx, ty) = (x / TILE, y / TILE);
        tx < self.size[0] && ty < self.size[1] && self.holds((ty * self.size[0] + tx) as usize)
    }

    /// Whether it holds no tile.
    pub fn is_empty(&self) -> bool {
        self.bits.iter().all(|&b| b == 0)
    }

    /// Whether the two share a tile.
    pub fn meets(&self, other: &TileMask) -> bool {
        let lo = self.first.max(other.first);
        let hi = (self.first + self.bits.len()).min(other.first + other.bits.len());
        (lo..hi).any(|w| self.bits[w - self.first] & other.bits[w - other.first] != 0)
    }

    /// Adds `other`'s tiles.
    pub fn union_with(&mut self, other: &TileMask) {
        if other.bits.is_empty() {
            return;
        }
        self.reach(other.first, other.first + other.bits.len());
        let at = other.first - self.first;
        for (a, b) in self.bits[at..].iter_mut().zip(&other.bits) {
            *a |= b;
        }
    }

    /// Its tiles, row by row, as `x | y << 16` (tile coordinates), as `blend.wgsl` reads them.
    pub fn packed_tiles(&self) -> Vec<u32> {
        let n = (self.size[0] * self.size[1]) as usize;
        let end = ((self.first + self.bits.len()) * 64).min(n);
        (self.first * 64..end)
            .filter(|&i| self.holds(i))
            .map(|i| (i as u32 % self.size[0]) | (i as u32 / self.size[0]) << 16)
            .collect()
    }
}

/// Occluders in groups whose tile masks are pairwise disjoint (first fit, in order): their
/// silhouette buffers cannot meet, so each group's stencil, wedge and blend passes serve all of
/// its occluders at once (Forest et al.'s per-silhouette loop, one pass per group instead of one per
/// silhouette). Empty masks are left out. Also each group's union of tiles, which its blend
/// covers.
pub fn disjoint_groups(masks: &[TileMask]) -> Vec<(Vec<usize>, TileMask)> {
    let mut groups: Vec<(Vec<usize>, TileMask)> = Vec::new();
    for (i, m) in masks.iter().enumerate() {
        if m.is_empty() {
            continue;
        }
        match groups.iter_mut().find(|(_, union)| !union.meets(m)) {
            Some((g, union)) => {
                g.push(i);
                union.union_with(m);
            }
            None => groups.push((vec![i], m.clone())),
        }
    }
    groups
}

/// Which tiles of the list a blend dispatch covers (`TileRange` in `blend.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct TileRange {
    /// Index of the first tile in the list.
    pub first: u32,
    /// Number of tiles.
    pub count: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
}

const _: () = assert!(std::mem::size_of::<TileRange>() == 16);

/// The blend pipeline.
pub struct BlendPass {
    pipeline: wgpu::ComputePipeline,
    /// Layout of group 1: the silhouette buffer's six textures, its stencil counts and the final
    /// buffer.
    pub inputs_layout: wgpu::BindGroupLayout,
    /// Layout of group 2: a [`TileRange`] (with a dynamic offset) and the tile list
    /// ([`TileMask::packed_tiles`], concatenated).
    pub tiles_layout: wgpu::BindGroupLayout,
}

impl BlendPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let source = format!(
            "{BLEND_PARTS_WGSL}\n{}",
            include_str!("../shaders/blend.wgsl")
        );
        let module = super::shader(device, "blend", &source);
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
        let tiles_layout = super::layout(
            device,
            "blend tiles",
            compute,
            &[
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<TileRange>() as u64),
                },
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
            ],
        );
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("blend"),
            bind_group_layouts: &[
                Some(frame_layout),
                Some(&inputs_layout),
                Some(&tiles_layout),
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
            tiles_layout,
        }
    }

    /// Blends the silhouette buffer into the final one over `count` tiles of the list in
    /// `tiles`, from the [`TileRange`] at `offset` in it (`inputs`: the silhouette buffer, its
    /// stencil counts, the final buffer). The tiles must be distinct.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        inputs: &wgpu::BindGroup,
        (tiles, offset, count): (&wgpu::BindGroup, u32, u32),
        queries: PassQueries<'_>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("blend"),
            timestamp_writes: queries.compute_writes(),
        });
        queries.begin_compute(&mut pass);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        pass.set_bind_group(2, tiles, &[offset]);
        if count > 0 {
            pass.dispatch_workgroups(count.min(MAX_WORKGROUPS), count.div_ceil(MAX_WORKGROUPS), 1);
        }
        queries.end_compute(&mut pass);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask(rects: &[[u32; 4]]) -> TileMask {
        let mut m = TileMask::new(100, 60);
        for r in rects {
            m.insert_pixels(r[0], r[1], r[2], r[3]);
        }
        m
    }

    #[test]
    fn tile_masks_hold_the_tiles_their_pixels_touch() {
        let m = mask(&[[7, 0, 9, 1]]);
        // Pixels 7 and 8 of row 0: tiles (0, 0) and (1, 0).
        assert_eq!(m.packed_tiles(), [0, 1]);
        let m = mask(&[[96, 56, 200, 200]]);
        // Clipped to the screen: 13 x 8 tiles, the last (12, 7).
        assert_eq!(m.packed_tiles(), [12 | 7 << 16]);
        assert!(m.holds_pixel(99, 59) && m.holds_pixel(96, 56) && !m.holds_pixel(95, 59));
        assert!(!m.holds_pixel(104, 59), "off the screen");
        assert!(mask(&[[5, 5, 5, 9]]).is_empty(), "no pixel");
        let mut all = TileMask::new(100, 60);
        all.fill();
        assert_eq!(all.packed_tiles().len(), 13 * 8);
        assert!(all.meets(&m) && !m.meets(&mask(&[[0, 0, 8, 8]])));
        // Stored over their span only: the union of two far apart masks holds both and what
        // lies between them stays empty.
        let (a, b) = (mask(&[[0, 0, 8, 8]]), mask(&[[96, 56, 100, 60]]));
        assert!(a.bits.len() == 1 && b.bits.len() == 1 && a.first == 0 && b.first == 1);
        let mut u = b.clone();
        u.union_with(&a);
        assert_eq!(u.packed_tiles(), [0, 12 | 7 << 16]);
        assert!(u.meets(&a) && u.meets(&b) && !u.meets(&mask(&[[50, 30, 60, 40]])));
        u.union_with(&TileMask::new(100, 60));
        assert_eq!(u.packed_tiles().len(), 2, "an empty mask adds nothing");
    }

    #[test]
    fn groups_hold_pairwise_disjoint_masks_and_every_non_empty_one() {
        let masks = [
            mask(&[[0, 0, 10, 10]]),
            mask(&[[9, 9, 20, 20]]),
            // Tile (3, 0): disjoint from both.
            mask(&[[24, 0, 30, 8]]),
            mask(&[]),
            // Two separate rectangles, tiles (0, 3) and (5, 0).
            mask(&[[0, 24, 8, 32], [40, 0, 48, 8]]),
            mask(&[[0, 0, 100, 60]]),
        ];
        assert!(masks[0].meets(&masks[1]));
        let groups = disjoint_groups(&masks);
        let mut seen: Vec<usize> = groups.iter().flat_map(|g| g.0.clone()).collect();
        seen.sort();
        assert_eq!(seen, [0, 1, 2, 4, 5]);
        for (g, union) in &groups {
            for (i, &a) in g.iter().enumerate() {
                assert!(union.meets(&masks[a]));
                for &b in &g[i + 1..] {
                    assert!(!masks[a].meets(&masks[b]), "{a} and {b}");
                }
            }
            let tiles: usize = g.iter().map(|&o| masks[o].packed_tiles().len()).sum();
            assert_eq!(
                union.packed_tiles().len(),
                tiles,
                "the union of disjoint masks"
            );
        }
        let members: Vec<Vec<usize>> = groups.into_iter().map(|g| g.0).collect();
        assert_eq!(members, [vec![0, 2, 4], vec![1], vec![5]]);
    }

    /// The memory bound of Forest et al. 2006: four `RGBA32F`, 64 bytes per pixel, for the
    /// silhouette and final buffers of `wedges-blend` together.
    #[test]
    fn blend_visibility_buffers_take_at_most_64_bytes_per_pixel() {
        let bytes = bytes_per_pixel();
        assert!(bytes <= 64, "{bytes} bytes per pixel");
        assert_eq!(bytes, 40 + 24);
    }
}
