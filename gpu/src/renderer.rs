//! The volume techniques rendered once, with the pipelines of `pipelines.rs`: `hard` (depth
//! pre-pass, z-fail stencil pass, resolve), additive `wedges` (the same, plus the wedge pass of every silhouette edge before
//! the resolve) and Forest et al.'s `wedges-blend` (the depth pre-pass, then the
//! "per-silhouette 3 passes algorithm" for each occluder: stencil pass of its volume, wedge pass
//! of its edges into a silhouette buffer, blend of that buffer into the final one; then the
//! resolve). Occluders whose screen tiles are disjoint share those three passes
//! (`passes::blend::disjoint_groups`): their silhouette buffers cannot meet.
//!
//! A [`GpuRenderer`] is built once per device; [`GpuScene`] records a scene's frames with it,
//! and [`GpuRenderer::render`] renders a [`Scene`] once and reads V back: a [`GpuScene`]
//! recorded for one frame.

use penumbra_geom::VisibilityImage;
use penumbra_geom::{LitScene, Technique};
use penumbra_volumes::Volumes;

use crate::context::GpuError;
use crate::counters::PassCounters;
use crate::frame_uniforms::FrameCamera;
use crate::gpu_scene::{FrameInputs, GpuScene};
use crate::passes::depth::{GBuffer, visibility_target};
use crate::passes::view;
use crate::pipelines::GpuRenderer;
use crate::timing::{PassTimes, Rendered, Timer, read_frame};

/// A depth-complexity image rendered once ([`GpuRenderer::render_depth_complexity`]).
pub struct ComplexityImage {
    /// V.
    pub image: VisibilityImage,
    /// The GPU time of each pass, where the device has timestamp queries.
    pub times: Option<PassTimes>,
    /// What each pass did, where [`GpuRenderer::set_counters`] asked for it.
    pub counters: Option<PassCounters>,
    /// Potential silhouette edges of the scene's light.
    pub potential_edges: usize,
    /// All edges of the scene's meshes.
    pub all_edges: usize,
    /// Entries of the edge list the frame needed (`(tile, edge)` pairs), and the list's size.
    pub list_entries: u32,
    /// Entries the list held.
    pub list_capacity: u32,
    /// Frames rendered again because the list overflowed: each was exact, and slower (its
    /// tiles that did not fit read every edge); rendered again with the list grown to fit.
    pub redone: u32,
}

impl GpuRenderer {
    /// Renders V of `scene` by `technique` with the volumes and wedges of `volumes` (built for
    /// `scene`).
    pub fn render(
        &self,
        scene: &LitScene,
        volumes: &Volumes,
        technique: Technique,
    ) -> Result<VisibilityImage, GpuError> {
        Ok(self.render_timed(scene, volumes, technique)?.image)
    }

    /// [`GpuRenderer::render`], with the GPU time of each pass when the device has timestamp
    /// queries and their counts when [`GpuRenderer::set_counters`] turned them on. An error if
    /// `technique` is not a volume technique (`hard`, `wedges`, `wedges-blend`).
    pub fn render_timed(
        &self,
        scene: &LitScene,
        volumes: &Volumes,
        technique: Technique,
    ) -> Result<Rendered, GpuError> {
        GpuScene::check_technique(technique)?;
        let device = &self.context().device;
        let (camera, gbuffer, visibility) = self.targets(scene);
        let mut gpu_scene = GpuScene::for_scene(self, scene, volumes, technique);
        if let Some(pass) = self.wedge_pass() {
            gpu_scene.set_wedge_pass(pass);
        }
        // Timestamp queries (for `wedges-blend` at most three passes per blending unit: its group's).
        let timer = Timer::new(
            self.context(),
            if technique == Technique::WedgesBlend {
                2 + 3 * volumes.unit_count()
            } else {
                5
            },
            self.counters(),
        );
        let mut enc = device.create_command_encoder(&Default::default());
        gpu_scene.record_depth_timed(&mut enc, &camera, &gbuffer, &timer)?;
        let inputs = FrameInputs { camera, technique };
        gpu_scene.record_timed(&mut enc, &inputs, &gbuffer, &view(&visibility), &timer)?;
        let mut frame = read_frame(self.context(), enc, &timer, &visibility)?;
        if let Some(c) = frame.counters.as_mut() {
            c.uploads = Some(gpu_scene.take_uploads());
        }
        Ok(frame)
    }

    /// Renders V of `scene` by depth-complexity sampling with `samples` light samples per pixel
    /// (a perfect square up to 1024), with the GPU time of each pass and the potential
    /// silhouette edges and all edges of the scene. The edge lists are recorded once alone first
    /// to size the list ([`GpuScene::record_edge_lists`]); a frame whose list still overflowed
    /// would be rendered again with the list grown.
    pub fn render_depth_complexity(
        &self,
        scene: &LitScene,
        samples: u32,
    ) -> Result<ComplexityImage, GpuError> {
        let device = &self.context().device;
        let (camera, gbuffer, visibility) = self.targets(scene);
        // No outward signs: they serve the wedges' terminator and the shadow maps only.
        let mut gpu_scene = GpuScene::of_scene(self, scene, |_| 0.0);
        gpu_scene.set_light_samples(samples)?;
        let inputs = FrameInputs {
            camera,
            technique: Technique::DepthComplexity,
        };
        // The edge lists alone first, to size the list: no frame then overflows.
        let mut enc = device.create_command_encoder(&Default::default());
        gpu_scene.record_edge_lists(&mut enc, &inputs, &gbuffer)?;
        self.context().queue.submit([enc.finish()]);
        gpu_scene.complexity_report()?;
        let mut redone = 0;
        loop {
            // Depth, stencil, receiver candidates, edge lists, count, resolve.
            let timer = Timer::new(self.context(), 6, self.counters());
            let mut enc = device.create_command_encoder(&Default::default());
            gpu_scene.record_depth_timed(&mut enc, &camera, &gbuffer, &timer)?;
            gpu_scene.record_timed(&mut enc, &inputs, &gbuffer, &view(&visibility), &timer)?;
            let Rendered {
                image,
                times,
                counters,
            } = read_frame(self.context(), enc, &timer, &visibility)?;
            let report = gpu_scene
                .complexity_report()?
                .expect("a frame was recorded");
            // Pixels past the loop budget or whose work was not finished, each found by the
            // counting pass: none at the default budget, whose dispatches are bounded.
            if report.cut_short > 0 || report.unfinished > 0 {
                return Err(GpuError::CutShort {
                    adapter: self.context().describe(),
                    pixels: report.cut_short + report.unfinished,
                    budget: gpu_scene.loop_budget(),
                });
            }
            if !report.overflowed {
                let (potential_edges, all_edges) = gpu_scene.potential_edges();
                return Ok(ComplexityImage {
                    image,
                    times,
                    counters,
                    potential_edges,
                    all_edges,
                    list_entries: report.demand,
                    list_capacity: gpu_scene.edge_list_capacity(),
                    redone,
                });
            }
            redone += 1;
        }
    }

    /// The camera of a one-shot frame of `scene` (near plane from the scene's extent around the
    /// eye), its G-buffer and its V target.
    fn targets(&self, scene: &LitScene) -> (FrameCamera, GBuffer, wgpu::Texture) {
        let device = &self.context().device;
        let size = (scene.camera.width, scene.camera.height);
        let camera = FrameCamera::of_scene(scene);
        (
            camera,
            GBuffer::new(device, size),
            visibility_target(device, size),
        )
    }
}
