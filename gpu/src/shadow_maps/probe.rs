//! The probe passes of the techniques' shaders, for their property tests: a function of the
//! shader run over a synthetic light map.

use crate::timing::PassQueries;
use bytemuck::Zeroable;
use penumbra_geom::Technique;
use wgpu::util::DeviceExt;

use super::ShadowMapRenderer;
use super::inputs::ShadowUniforms;
use super::resources::{RGBA, SAMPLED};
use crate::context::GpuError;
use crate::frame_uniforms::{FrameUniforms, single_frame_group};
use crate::passes::fullscreen::{INPUT_IMAGES, LIGHT_MAP_FORMAT};
use crate::passes::{VISIBILITY_FORMAT, bind_group, buffer, texture, texture_descriptor, view};
use crate::readback::read_r32f;

impl ShadowMapRenderer {
    /// Runs probe pass `entry` (`fs_probe` of `mdsm`, `fs_probe_count` of `fractional-disk`)
    /// over a `size` image with `base` uniforms and `map` (`R32Float` texels, row-major, the
    /// map's size from `base.map`) as the base light map; `mdsm`'s build pass runs first. Returns
    /// the probe image, row-major. For the property tests of the techniques' shaders.
    pub fn probe(
        &self,
        entry: &str,
        base: &ShadowUniforms,
        map: &[f32],
        size: (u32, u32),
    ) -> Result<Vec<f32>, GpuError> {
        let device = &self.ctx.device;
        let map_size = (base.map[0] as u32, base.map[1] as u32);
        let base_map = device.create_texture_with_data(
            &self.ctx.queue,
            &texture_descriptor(
                "probe map",
                map_size,
                LIGHT_MAP_FORMAT,
                wgpu::TextureUsages::TEXTURE_BINDING,
            ),
            Default::default(),
            bytemuck::cast_slice(map),
        );
        let base_view = view(&base_map);
        let dummy = view(&texture(
            device,
            "unused",
            (1, 1),
            LIGHT_MAP_FORMAT,
            SAMPLED,
        ));
        let buf = buffer(
            device,
            "probe uniforms",
            std::slice::from_ref(base),
            wgpu::BufferUsages::UNIFORM,
        );
        // The frame is unused by the probes but part of the layout.
        let frame = single_frame_group(
            device,
            &self.pipelines.frame_layout,
            &FrameUniforms::zeroed(),
        );
        let group = |images: [&wgpu::TextureView; 3]| {
            let mut r = vec![
                buf.as_entire_binding(),
                wgpu::BindingResource::TextureView(&dummy),
                wgpu::BindingResource::TextureView(&dummy),
            ];
            r.extend(images.map(wgpu::BindingResource::TextureView));
            r.resize(3 + INPUT_IMAGES, wgpu::BindingResource::TextureView(&dummy));
            bind_group(device, "probe inputs", &self.pipelines.shadow_layout, &r)
        };
        let mut enc = device.create_command_encoder(&Default::default());
        let built = (self.technique == Technique::Mdsm).then(|| {
            let v = view(&texture(device, "mdsm", map_size, RGBA, SAMPLED));
            self.pipelines.pass("fs_build").record(
                &mut enc,
                &frame,
                &group([&base_view, &dummy, &dummy]),
                &v,
                PassQueries::default(),
            );
            v
        });
        let out = texture(
            device,
            "probe",
            size,
            VISIBILITY_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let images = [&base_view, built.as_ref().unwrap_or(&dummy), &dummy];
        self.pipelines.pass(entry).record(
            &mut enc,
            &frame,
            &group(images),
            &view(&out),
            PassQueries::default(),
        );
        read_r32f(&self.ctx, &mut enc, &out, size.0, size.1)
    }
}
