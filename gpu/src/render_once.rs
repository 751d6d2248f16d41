//! [`GpuRenderer::render`]: a scene rendered once and read back, as a [`GpuScene`] recorded for
//! one frame.

use penumbra_geom::image::VisibilityImage;
use penumbra_geom::{Scene, Technique};
use penumbra_volumes::Volumes;

use crate::context::GpuError;
use crate::frame::{FrameCamera, eye_relative, scene_radius};
use crate::gpu_scene::{FrameInputs, GpuScene, check_technique};
use crate::passes::depth::{GBuffer, visibility_target};
use crate::passes::view;
use crate::renderer::GpuRenderer;
use crate::timing::{PassTimes, Timer, read_frame};

impl GpuRenderer {
    /// Renders V of `scene` by `technique` with the volumes and wedges of `volumes` (built for
    /// `scene`).
    pub fn render(
        &self,
        scene: &Scene,
        volumes: &Volumes,
        technique: Technique,
    ) -> Result<VisibilityImage, GpuError> {
        Ok(self.render_timed(scene, volumes, technique)?.0)
    }

    /// [`GpuRenderer::render`], with the GPU time of each pass when the device has timestamp
    /// queries. An error if `technique` is not a volume technique (`hard`, `wedges`,
    /// `wedges-blend`).
    pub fn render_timed(
        &self,
        scene: &Scene,
        volumes: &Volumes,
        technique: Technique,
    ) -> Result<(VisibilityImage, Option<PassTimes>), GpuError> {
        check_technique(technique)?;
        let device = &self.ctx.device;
        let size = (scene.camera.width, scene.camera.height);
        let world = scene.triangles();
        let radius = scene_radius(&eye_relative(scene.camera.eye, &world));
        let camera = FrameCamera::for_scene(&scene.camera, radius);
        let mut gpu_scene = GpuScene::for_scene(self, scene, volumes);
        let gbuffer = GBuffer::new(device, size);
        let visibility = visibility_target(device, size);
        // Timestamp queries (for `wedges-blend` at most three passes per blending unit: its group's).
        let timer = Timer::new(
            &self.ctx,
            if technique == Technique::WedgesBlend {
                2 + 3 * volumes.unit_count()
            } else {
                4
            },
        );
        let mut enc = device.create_command_encoder(&Default::default());
        gpu_scene.record_depth_timed(&mut enc, &camera, &gbuffer, &timer)?;
        let inputs = FrameInputs { camera, technique };
        gpu_scene.record_timed(&mut enc, &inputs, &gbuffer, &view(&visibility), &timer)?;
        read_frame(&self.ctx, enc, &timer, &visibility)
    }
}
