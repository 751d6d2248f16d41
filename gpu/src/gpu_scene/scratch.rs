//! The volume techniques' own targets of a [`super::GpuScene`]'s frames.

use penumbra_geom::Technique;

use crate::constants::FINAL_WORDS;
use crate::passes::blend::SILHOUETTE_FORMATS;
use crate::passes::wedge::OCCLUSION_FORMAT;
use crate::passes::{texture, view};

/// The techniques' own targets at one image size, made the first time a frame needs them and
/// kept while the size stays.
#[derive(Default)]
pub(super) struct Scratch {
    size: (u32, u32),
    /// `wedges`: the per-part occlusion.
    pub(super) occlusion: Option<wgpu::TextureView>,
    /// `wedges-blend`: the silhouette buffer's targets and the final buffer.
    pub(super) silhouettes: Option<(Vec<wgpu::TextureView>, wgpu::Buffer)>,
}

impl Scratch {
    /// Makes what `technique` needs at `size`.
    pub(super) fn prepare(
        &mut self,
        device: &wgpu::Device,
        technique: Technique,
        size: (u32, u32),
    ) {
        if self.size != size {
            *self = Scratch {
                size,
                ..Default::default()
            };
        }
        let sampled = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        match technique {
            Technique::Wedges if self.occlusion.is_none() => {
                self.occlusion = Some(view(&texture(
                    device,
                    "occlusion",
                    size,
                    OCCLUSION_FORMAT,
                    sampled | wgpu::TextureUsages::STORAGE_BINDING,
                )));
            }
            Technique::WedgesBlend if self.silhouettes.is_none() => {
                let targets = SILHOUETTE_FORMATS
                    .iter()
                    .map(|&f| view(&texture(device, "silhouette", size, f, sampled)))
                    .collect();
                let final_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("final buffer"),
                    size: 4 * FINAL_WORDS * (size.0 as u64) * (size.1 as u64),
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                self.silhouettes = Some((targets, final_buffer));
            }
            _ => {}
        }
    }
}
