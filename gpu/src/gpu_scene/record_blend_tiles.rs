//! Recording `wedges-blend` of a [`GpuScene`] in one compute pass over screen tiles
//! (`passes::blend_tiles`), then the resolve.

use crate::counters::{Pass, Traffic};

use super::GpuScene;
use super::frame_shadows::FrameShadows;
use crate::frame_uniforms::FrameCamera;
use crate::passes::blend_tiles::BlendTilesInputs;
use crate::passes::buffer;
use crate::passes::depth::GBuffer;
use crate::timing::Timer;

impl GpuScene {
    /// Records `wedges-blend` over screen tiles, with the shadows built on the CPU and the
    /// final buffer prepared; false, with nothing recorded, where two bindings cannot hold the
    /// wedges (the caller records a stencil, a wedge and a blend pass per group instead).
    pub(super) fn record_blend_tiled(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        gbuffer: &GBuffer,
        target: &wgpu::TextureView,
        timer: &Timer,
    ) -> bool {
        let device = &self.ctx.device;
        let shadows = self.shadows.as_ref().expect("built by record");
        let Some((parts, _)) =
            FrameShadows::Uploaded(shadows).tiled(device.limits().max_storage_buffer_binding_size)
        else {
            return false;
        };
        // Each unit's count at the eye, which every pixel's count starts from (`buffer` gives
        // a scene without units the one element a binding needs).
        let counts = shadows
            .units
            .eye_counts(camera.eye, self.light.rect().center);
        let eye_counts = buffer(device, "eye counts", &counts, wgpu::BufferUsages::STORAGE);
        let p = &self.pipelines;
        let (_, final_buffer) = self
            .scratch
            .silhouettes
            .as_ref()
            .expect("prepared by record");
        let frame = crate::frame_uniforms::frame_group(
            device,
            &p.blend_tiles.frame_layout,
            &self.uniforms,
            &self.models,
        );
        p.blend_tiles.record(
            encoder,
            device,
            &frame,
            BlendTilesInputs {
                position: &gbuffer.position_view,
                wedges: parts,
                items: &shadows.items,
                eye_counts: &eye_counts,
                quads: &shadows.quads,
                final_buffer,
                normal: &gbuffer.normal_view,
                triangle_units: &shadows.triangle_units,
            },
            gbuffer.size(),
            timer.pass(
                Pass::Blend,
                Traffic::new()
                    .reads(&shadows.instance_buffer)
                    .reads(&shadows.items)
                    .reads(&shadows.quads)
                    .reads(&eye_counts)
                    .reads(&gbuffer.position)
                    .reads(&gbuffer.normal)
                    .reads(&shadows.triangle_units)
                    .writes(final_buffer),
            ),
        );
        self.record_blended_resolve(encoder, gbuffer, final_buffer, target, timer);
        self.uploads.frame += std::mem::size_of_val(counts.as_slice()) as u64;
        true
    }
}
