//! The pipelines of one shadow-map technique: the depth pre-pass, the light map and the
//! technique's full-screen passes, built once per device.

use penumbra_geom::Technique;

use crate::passes::depth::DepthPass;
use crate::passes::frame_layout;
use crate::passes::fullscreen::{FullscreenPass, LightMapPass, shadow_layout, shadow_shader};

/// A technique's WGSL file and its passes, each a fragment entry point and its target format.
pub(super) struct TechniquePasses {
    pub(super) source: &'static str,
    pub(super) passes: &'static [(&'static str, wgpu::TextureFormat)],
}

/// The pipelines of one technique.
pub(super) struct ShadowPipelines {
    pub(super) frame_layout: wgpu::BindGroupLayout,
    pub(super) shadow_layout: wgpu::BindGroupLayout,
    pub(super) depth: DepthPass,
    pub(super) light: LightMapPass,
    technique: Technique,
    passes: Vec<(&'static str, FullscreenPass)>,
}

impl ShadowPipelines {
    /// Builds the pipelines of `technique`, whose passes are `passes`, on `device`.
    pub(super) fn new(
        device: &wgpu::Device,
        technique: Technique,
        passes: TechniquePasses,
    ) -> Self {
        let frame_layout = frame_layout(device);
        let shadow_layout = shadow_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow map"),
            bind_group_layouts: &[Some(&frame_layout), Some(&shadow_layout)],
            immediate_size: 0,
        });
        let module = shadow_shader(device, "shadow technique", passes.source);
        let passes = passes
            .passes
            .iter()
            .map(|&(e, f)| (e, FullscreenPass::new(device, &layout, &module, e, f)))
            .collect();
        ShadowPipelines {
            depth: DepthPass::new(device, &frame_layout),
            light: LightMapPass::new(device, &layout),
            frame_layout,
            shadow_layout,
            technique,
            passes,
        }
    }

    /// The pass of fragment entry point `entry`.
    ///
    /// # Panics
    ///
    /// If `entry` is not a pass of the technique.
    pub(super) fn pass(&self, entry: &str) -> &FullscreenPass {
        &self
            .passes
            .iter()
            .find(|(e, _)| *e == entry)
            .unwrap_or_else(|| panic!("{entry} is a pass of {:?}", self.technique))
            .1
    }
}
