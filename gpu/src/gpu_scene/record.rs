//! Recording a frame of a [`GpuScene`]: the depth pre-pass, then the passes of the technique
//! into the application's visibility target.

use crate::counters::{Pass, Traffic};
use penumbra_geom::{Light, Technique, Warp};

use super::frame_shadows::FrameShadows;
use super::{FrameInputs, GpuScene, WedgePass};
use crate::context::GpuError;
use crate::frame_uniforms::FrameCamera;
use crate::passes::depth::{GBuffer, MeshDraws};
use crate::passes::resolve::ResolveInput;
use crate::passes::wedge::{WedgeDraws, WedgeOutput};
use crate::passes::wedge_tiles::WedgeTilesInputs;
use crate::passes::{FrameBindings, VISIBILITY_FORMAT, bind_group};
use crate::timing::Timer;

/// Checks that `camera` (the camera's size) is the size of `what`.
fn same_size(camera: (u32, u32), what: &'static str, other: (u32, u32)) -> Result<(), GpuError> {
    if camera == other {
        Ok(())
    } else {
        Err(GpuError::SizeMismatch {
            camera,
            what,
            size: other,
        })
    }
}

impl GpuScene {
    /// Records the depth pre-pass of the frame seen by `camera` into `gbuffer`: depth, stencil
    /// cleared, eye-relative positions and normals ([`GBuffer`] documents them). An application
    /// that renders these itself skips it.
    pub fn record_depth(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        gbuffer: &GBuffer,
    ) -> Result<(), GpuError> {
        self.record_depth_timed(encoder, camera, gbuffer, &Timer::disabled())
    }

    pub(crate) fn record_depth_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        gbuffer: &GBuffer,
        timer: &Timer,
    ) -> Result<(), GpuError> {
        same_size(camera.size, "G-buffer", gbuffer.size())?;
        let seen = self.frame_camera(camera);
        self.write_frame(camera, &seen);
        self.expand_corners(encoder);
        self.pipelines.depth.record(
            encoder,
            &self.frame,
            MeshDraws {
                vertices: &self.vertices,
                ranges: &self.vertex_ranges,
            },
            gbuffer,
            timer.pass(Pass::Depth, gbuffer.drawn().reads(&self.vertices)),
        );
        Ok(())
    }

    /// Records the passes of `inputs.technique` for the frame seen by `inputs.camera`, reading
    /// `gbuffer` (filled by [`GpuScene::record_depth`] or by the application) and writing V into
    /// `target`: a view of a whole `R32Float` texture of the camera's size with usage
    /// `RENDER_ATTACHMENT`. Rebuilds the silhouettes, volumes and wedges first when the light or
    /// a transform changed since they were last built.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
        gbuffer: &GBuffer,
        target: &wgpu::TextureView,
    ) -> Result<(), GpuError> {
        self.record_timed(encoder, inputs, gbuffer, target, &Timer::disabled())
    }

    pub(crate) fn record_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
        gbuffer: &GBuffer,
        target: &wgpu::TextureView,
        timer: &Timer,
    ) -> Result<(), GpuError> {
        let technique = inputs.technique;
        Self::check_technique(technique)?;
        let camera = &inputs.camera;
        same_size(camera.size, "G-buffer", gbuffer.size())?;
        let t = target.texture();
        same_size(camera.size, "target", (t.width(), t.height()))?;
        if t.format() != VISIBILITY_FORMAT
            || !t.usage().contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
        {
            return Err(GpuError::TargetFormat {
                format: t.format(),
                usage: t.usage(),
            });
        }
        let seen = self.frame_camera(camera);
        self.write_frame(camera, &seen);
        let camera = &seen;
        if technique == Technique::DepthComplexity {
            return self.record_complexity(encoder, camera, gbuffer, Some(target), timer);
        }
        self.expand_corners(encoder);
        let on_gpu = technique != Technique::WedgesBlend && self.builds_on_gpu();
        if on_gpu {
            self.record_build(encoder, timer);
        } else {
            self.shadows();
        }
        self.scratch
            .prepare(&self.ctx.device, technique, camera.size);
        if technique == Technique::WedgesBlend {
            let tiled = self.wedge_pass == WedgePass::Tiled
                && self.record_blend_tiled(encoder, camera, gbuffer, target, timer);
            if !tiled {
                self.record_blend(encoder, camera, gbuffer, target, timer);
            }
        } else {
            self.record_additive(encoder, technique, on_gpu, gbuffer, target, timer);
        }
        Ok(())
    }

    /// Records the rewriting of the meshes' corners where the application moved vertices
    /// ([`GpuScene::set_positions`]).
    fn expand_corners(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if !self.corners_stale {
            return;
        }
        self.corners_stale = false;
        let Some(Ok(built)) = &self.built else {
            return;
        };
        self.pipelines
            .build
            .record_expand(encoder, &built.frame_group, &built.groups);
    }

    /// Records the shadows' build on the GPU where the light or a mesh moved since the last.
    fn record_build(&mut self, encoder: &mut wgpu::CommandEncoder, timer: &Timer) {
        if self.built_fresh {
            return;
        }
        let Some(Ok(built)) = &self.built else {
            return;
        };
        self.pipelines.build.record(
            encoder,
            &built.frame_group,
            &built.groups,
            &built.bounds,
            timer.pass(
                Pass::Build,
                Traffic::new()
                    .reads(&self.models)
                    .reads(&built.build_bytes.0)
                    .writes(&built.build_bytes.1),
            ),
        );
        self.built_fresh = true;
    }

    /// Renders the frame of `inputs` under each of `lights` into the target of the same index,
    /// one V target per light, each what [`GpuScene::record`] writes for that light alone: for
    /// each light in turn, [`GpuScene::set_light`], the depth pre-pass into `gbuffer` (where the
    /// light before it left the G-buffer in another light's warp, or none was recorded) and the
    /// technique's passes, in an encoder of its own submitted to the scene's queue (the frame's
    /// uniforms go through the queue, so each light takes a submission of its own). What was
    /// built for each light is kept while the meshes stay where they are: lights that come back
    /// frame after frame are not built again. The scene is left lit by the last light.
    pub fn render_lights(
        &mut self,
        lights: &[Light],
        inputs: &FrameInputs,
        gbuffer: &GBuffer,
        targets: &[&wgpu::TextureView],
    ) -> Result<(), GpuError> {
        if lights.len() != targets.len() {
            return Err(GpuError::LightTargets {
                lights: lights.len(),
                targets: targets.len(),
            });
        }
        // The warp the G-buffer's points are in, once a depth pre-pass was recorded here.
        let mut drawn: Option<Option<Warp>> = None;
        for (&light, target) in lights.iter().zip(targets) {
            self.set_light(light);
            let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
            // The camera may renew the warp: settle it before comparing.
            self.frame_camera(&inputs.camera);
            if drawn != Some(self.warp()) {
                self.record_depth(&mut encoder, &inputs.camera, gbuffer)?;
                drawn = Some(self.warp());
            }
            self.record(&mut encoder, inputs, gbuffer, target)?;
            self.ctx.queue.submit([encoder.finish()]);
        }
        Ok(())
    }

    /// Checks that `technique` is one [`GpuScene::record`] renders.
    pub(crate) fn check_technique(technique: Technique) -> Result<(), GpuError> {
        if technique.is_volume() || technique == Technique::DepthComplexity {
            Ok(())
        } else {
            Err(GpuError::NotRecordable { technique })
        }
    }

    /// Records `hard` (every volume's stencil count, then the hard shadow) or additive
    /// `wedges` (the same, with every wedge's occlusion over it), with the shadows built and the
    /// scratch targets prepared.
    fn record_additive(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        technique: Technique,
        on_gpu: bool,
        gbuffer: &GBuffer,
        target: &wgpu::TextureView,
        timer: &Timer,
    ) {
        let p = &self.pipelines;
        let device = &self.ctx.device;
        let position = p.resolve.receivers(device, gbuffer);
        let bindings = FrameBindings {
            frame: &self.frame,
            depth: &gbuffer.depth_view,
            position: &position,
        };
        // The volumes and wedges, built on the GPU or uploaded.
        let source = match &self.built {
            Some(Ok(b)) if on_gpu => FrameShadows::Built(b),
            _ => FrameShadows::Uploaded(self.shadows.as_ref().expect("built by record")),
        };
        let (volumes, volume_bytes) = source.volumes();
        let wedges = source.wedges();
        let tiled = match self.wedge_pass {
            WedgePass::Tiled => source.tiled(device.limits().max_storage_buffer_binding_size),
            WedgePass::Rasterised => None,
        };
        p.stencil.record(
            encoder,
            bindings,
            volumes,
            timer.pass(
                Pass::Stencil,
                Traffic::new().reads(&volume_bytes).updates(&gbuffer.depth),
            ),
        );
        let group;
        let input = if technique == Technique::Hard {
            ResolveInput::Hard
        } else {
            let occlusion = self.scratch.occlusion.as_ref().expect("prepared by record");
            match tiled {
                // Culled per screen tile, one invocation a pixel.
                Some((parts, args)) => p.wedge_tiles.record(
                    encoder,
                    device,
                    &self.frame,
                    WedgeTilesInputs {
                        position: &gbuffer.position_view,
                        wedges: parts,
                        args,
                        occlusion,
                    },
                    gbuffer.size(),
                    timer.pass(
                        Pass::Wedge,
                        Traffic::new()
                            .reads(wedges.buffer)
                            .reads(&gbuffer.position)
                            .writes(occlusion),
                    ),
                ),
                // Asked for, or more wedges than two bindings hold: each one's solid rasterised.
                None => p.wedge.record(
                    encoder,
                    bindings,
                    WedgeDraws {
                        cube: &self.cube,
                        wedges: wedges.buffer,
                        ranges: std::slice::from_ref(&wedges.range),
                        indirect: wedges.indirect,
                    },
                    WedgeOutput::Additive(occlusion),
                    timer.pass(
                        Pass::Wedge,
                        Traffic::new()
                            .reads(&self.cube)
                            .reads(wedges.buffer)
                            .reads(&gbuffer.depth)
                            .reads(&gbuffer.position)
                            .updates(occlusion),
                    ),
                ),
            }
            group = bind_group(
                device,
                "occlusion",
                &p.resolve.texture_layout,
                &[wgpu::BindingResource::TextureView(occlusion)],
            );
            ResolveInput::Additive(&group)
        };
        let read = gbuffer.receivers_read();
        let read = match technique {
            Technique::Hard => read,
            _ => read.reads(self.scratch.occlusion.as_ref().expect("prepared by record")),
        };
        p.resolve.record(
            encoder,
            bindings,
            input,
            target,
            timer.pass(Pass::Resolve, read.writes(target)),
        );
    }
}
