//! A scene on the GPU, uploaded once and rendered every frame into an application's targets:
//! its meshes' vertices stay on the device; per frame only the camera, the meshes' model
//! matrices, the vertices of meshes the application deformed and (for `wedges-blend`) the
//! blend's tile lists are written. The silhouettes, shadow volumes and wedges depend on the
//! light and on where the meshes are: in frames where either changed, `hard` and `wedges` build
//! them on the GPU from the vertices there ([`ShadowBuilder::Gpu`], where the scene allows it),
//! the other techniques on the CPU, uploading them.

mod built;
mod complexity;
mod complexity_buffers;
mod complexity_receivers;
mod complexity_state;
mod distant;
mod frame_shadows;
mod meshes;
mod record;
mod record_blend;
mod record_blend_tiles;
mod scratch;
mod shadows;
mod uploads;

use std::ops::Range;
use std::sync::Arc;

use glam::{DMat4, DVec3};
use penumbra_geom::{HalfEdgeMesh, Light, LitScene, RectLight, Technique, TriangleMesh};
use penumbra_volumes::Volumes;
use penumbra_volumes::outward_sign;

use crate::context::{GpuContext, GpuError};
use crate::frame_uniforms::{FrameCamera, FrameUniforms, ModelMatrix, frame_group, model_matrix};
use crate::passes::buffer;
use crate::passes::wedge::unit_cube;
use crate::pipelines::{GpuRenderer, Pipelines};
use built::{Built, TooLarge};
use complexity_state::ComplexityState;
pub use complexity_state::{ComplexityReport, SOFTWARE_LOOP_BUDGET};
use distant::SceneLight;
use meshes::{StoredMesh, centre, world};
use scratch::Scratch;
use shadows::Shadows;
pub use uploads::Uploads;

/// How many lights' shadows a [`GpuScene`] keeps besides the current light's.
const KEPT_LIGHTS: usize = 8;

/// Where a [`GpuScene`] builds the silhouettes, shadow volumes and wedges of `hard` and
/// `wedges`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadowBuilder {
    /// On the GPU, in a compute pass, from the meshes' vertices as they are there: nothing is
    /// uploaded when the light or a mesh moves. Scenes it does not take are built on the CPU:
    /// a mesh reaching behind the light's plane (a lamp hanging in a room, a mesh through its
    /// light; a lamp flush with a ceiling is taken), more than 65,535 meshes or faces on one
    /// edge, or buffers beyond the device's binding size
    /// (`docs/gpu.md`, "Shadows built on the GPU").
    #[default]
    Gpu,
    /// On the CPU (`penumbra_volumes`, the oracle), uploaded each time.
    Cpu,
}

/// How `wedges` and `wedges-blend` evaluate their wedges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WedgePass {
    /// One compute pass over screen tiles: each tile culls the wedges against its receivers'
    /// light-space box, each pixel integrates those that reach it (`docs/gpu.md`, "Tiled
    /// wedges"); for `wedges-blend` the same pass also counts each blending unit's shadow
    /// volume and blends the units ("Tiled blending"). A few shader invocations a pixel,
    /// whatever the wedges' area on screen, and three passes a frame.
    Tiled,
    /// Each wedge's solid rasterised, one fragment a pixel it covers; for `wedges-blend` a
    /// stencil, a wedge and a blend pass per group of units. The same image, bit for bit for
    /// `wedges` and within rounding for `wedges-blend`.
    Rasterised,
}

impl WedgePass {
    /// The faster on a device of type `device`, as measured: rasterised on a CPU device
    /// (lavapipe), whose rasteriser covers fragments in blocks and whose workgroups cost tens of
    /// microseconds each, tiled on a GPU.
    pub fn for_device(device: wgpu::DeviceType) -> Self {
        if device == wgpu::DeviceType::Cpu {
            WedgePass::Rasterised
        } else {
            WedgePass::Tiled
        }
    }
}

/// What a frame renders: the camera and the technique.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameInputs {
    /// The camera.
    pub camera: FrameCamera,
    /// A volume technique (`hard`, `wedges` or `wedges-blend`) or `depth-complexity` (with
    /// [`GpuScene::light_samples`] samples per pixel).
    pub technique: Technique,
}

/// A scene on the GPU: its meshes uploaded once, each with a transform, and the light, both of
/// which may change from frame to frame. [`GpuScene::record_depth`] and [`GpuScene::record`]
/// record a frame into the application's command encoder; the frame's buffer writes go through
/// the queue and take effect when that encoder is submitted, so submit each frame's commands
/// before recording the next.
///
/// Meshes are stored in `f32` relative to the centre of their bounding box and placed relative
/// to the eye by a matrix composed in `f64` each frame, so precision follows the mesh's size and
/// its distance to the eye, not where the world's origin lies.
pub struct GpuScene {
    ctx: GpuContext,
    pipelines: Arc<Pipelines>,
    meshes: Vec<StoredMesh>,
    /// Every mesh's triangles' corners, as stored, and each mesh's range of them.
    vertices: wgpu::Buffer,
    vertex_ranges: Vec<Range<u32>>,
    /// The light: a rectangle, or a distant light with its warp and the rectangle the passes
    /// render.
    light: SceneLight,
    /// Built for the current light and transforms; `None` until a frame needs them.
    shadows: Option<Shadows>,
    /// Built for other lights under the current transforms, most recent last: a light that
    /// comes back finds its shadows here ([`GpuScene::render_lights`]).
    kept: Vec<(RectLight, Shadows)>,
    uniforms: wgpu::Buffer,
    models: wgpu::Buffer,
    /// The frame's group 0: `uniforms` and `models`.
    frame: wgpu::BindGroup,
    /// What `uniforms` and `models` hold.
    written: Option<(FrameUniforms, Vec<ModelMatrix>)>,
    /// The unit cube each wedge instance is drawn from.
    cube: wgpu::Buffer,
    scratch: Scratch,
    uploads: Uploads,
    /// Depth-complexity sampling's own state.
    complexity: ComplexityState,
    /// Where `hard` and `wedges` build their shadows.
    builder: ShadowBuilder,
    /// How `wedges` evaluates its wedges.
    wedge_pass: WedgePass,
    /// The meshes' topology and the build's buffers on the GPU, made when first needed (an
    /// error where the scene is too large for them).
    built: Option<Result<Built, TooLarge>>,
    /// Whether the build's outputs are those of the current light, transforms and vertices.
    built_fresh: bool,
    /// Whether the meshes' corners must be rewritten from moved vertices before a depth pass.
    corners_stale: bool,
}

impl GpuScene {
    /// Uploads `meshes`, each given in its own space with its transform into the world, lit by
    /// `light`.
    ///
    /// ```no_run
    /// use penumbra::glam::dcamera::rh::{proj::directx, view};
    /// use penumbra::glam::{DMat4, DVec2, DVec3};
    /// use penumbra::geom::{RectLight, Technique, TriangleMesh};
    /// use std::path::Path;
    /// use penumbra::gpu::{FrameCamera, FrameInputs, GBuffer, GpuContext, GpuRenderer, GpuScene};
    ///
    /// let ctx = GpuContext::new()?;
    /// let renderer = GpuRenderer::with_context(&ctx);
    /// let corners = [[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]];
    /// let corners = corners.map(DVec3::from_array);
    /// let quad = TriangleMesh::from_raw("quad", &corners, &[[0, 2, 1], [0, 3, 2]])
    ///     .unwrap();
    /// let light = RectLight::new(DVec3::new(0.0, 4.0, 0.0), -DVec3::Y, DVec3::X, DVec2::ONE).unwrap();
    /// let mut scene = GpuScene::new(&renderer, &[(&quad, DMat4::IDENTITY)], light);
    ///
    /// let size = (320, 240);
    /// let view = view::look_at_mat4(DVec3::new(0.0, 3.0, 5.0), DVec3::ZERO, DVec3::Y);
    /// let projection = directx::perspective_infinite_reverse(0.8, 320.0 / 240.0, 0.01);
    /// let camera = FrameCamera::from_matrices(&view, &projection, size).unwrap();
    /// let inputs = FrameInputs { camera, technique: Technique::WedgesBlend };
    /// let gbuffer = GBuffer::new(&ctx.device, size);
    /// // The application's own R32Float target (RENDER_ATTACHMENT).
    /// let target = penumbra::gpu::visibility_target(&ctx.device, size);
    /// let view = target.create_view(&Default::default());
    ///
    /// let mut encoder = ctx.device.create_command_encoder(&Default::default());
    /// scene.record_depth(&mut encoder, &camera, &gbuffer)?;
    /// scene.record(&mut encoder, &inputs, &gbuffer, &view)?;
    /// ctx.queue.submit([encoder.finish()]);
    /// # Ok::<(), penumbra::gpu::GpuError>(())
    /// ```
    pub fn new(
        renderer: &GpuRenderer,
        meshes: &[(&TriangleMesh, DMat4)],
        light: impl Into<Light>,
    ) -> Self {
        let stored: Vec<StoredMesh> = meshes
            .iter()
            .map(|&(m, t)| {
                let outward = outward_sign(m, &HalfEdgeMesh::build(m));
                StoredMesh::new(m, t, centre(&m.positions), outward)
            })
            .collect();
        let light = SceneLight::new(light.into(), &stored);
        Self::with_stored(renderer, stored, light)
    }

    /// [`GpuScene::new`] with the meshes stored and the light made.
    fn with_stored(renderer: &GpuRenderer, stored: Vec<StoredMesh>, light: SceneLight) -> Self {
        let ctx = renderer.context();
        let device = &ctx.device;
        let mut corners: Vec<[f32; 3]> = Vec::new();
        let mut vertex_ranges = Vec::with_capacity(stored.len());
        for m in &stored {
            let start = corners.len() as u32;
            corners.extend(
                m.mesh
                    .triangles
                    .iter()
                    .flatten()
                    .map(|&i| m.stored[i as usize]),
            );
            vertex_ranges.push(start..corners.len() as u32);
        }
        let vertices = buffer(
            device,
            "meshes",
            &corners,
            wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
        );
        let uploads = Uploads {
            geometry: std::mem::size_of_val(corners.as_slice()) as u64,
            ..Default::default()
        };
        let copy = wgpu::BufferUsages::COPY_DST;
        let uniforms = buffer(
            device,
            "frame",
            &[<FrameUniforms as bytemuck::Zeroable>::zeroed()],
            wgpu::BufferUsages::UNIFORM | copy,
        );
        let identity = glam::Mat4::IDENTITY.to_cols_array_2d();
        let models = buffer(
            device,
            "models",
            &vec![identity; stored.len().max(1)],
            wgpu::BufferUsages::STORAGE | copy,
        );
        let pipelines = renderer.pipelines().clone();
        let frame = frame_group(device, &pipelines.frame_layout, &uniforms, &models);
        let cube = buffer(
            device,
            "unit cube",
            &unit_cube(),
            wgpu::BufferUsages::VERTEX,
        );
        GpuScene {
            complexity: ComplexityState::new(ctx.info.device_type),
            ctx: ctx.clone(),
            pipelines,
            vertices,
            vertex_ranges,
            light,
            meshes: stored,
            shadows: None,
            kept: Vec::new(),
            uniforms,
            models,
            frame,
            written: None,
            cube,
            scratch: Scratch::default(),
            uploads,
            builder: ShadowBuilder::default(),
            wedge_pass: WedgePass::for_device(ctx.info.device_type),
            built: None,
            built_fresh: false,
            corners_stale: false,
        }
    }

    /// The meshes of `scene` (world space, stored relative to the eye: the one-shot renderer's
    /// exact layout) for a frame of `technique`, with the silhouettes' products of `volumes`,
    /// built for `scene`, uploaded unless the GPU builds its own.
    pub(crate) fn for_scene(
        renderer: &GpuRenderer,
        scene: &LitScene,
        volumes: &Volumes,
        technique: Technique,
    ) -> Self {
        let mut s = Self::of_scene(renderer, scene, |i| volumes.occluders[i].outward);
        if technique != Technique::WedgesBlend && s.builds_on_gpu() {
            return s;
        }
        let (shadows, bytes) = Shadows::build(
            &s.ctx.device,
            &s.meshes,
            s.light.rect(),
            volumes,
            &scene.triangles(),
        );
        s.uploads.shadows += bytes;
        s.shadows = Some(shadows);
        s
    }

    /// The meshes of `scene` in the one-shot renderer's layout (in the world, placed by the
    /// identity, stored relative to the eye), mesh `i` with the outward sign `outward(i)`, lit
    /// by the scene's light: a distant light through the scene's own warp, as every frame of a
    /// [`GpuScene`] renders one; nothing built for the light yet.
    pub(crate) fn of_scene(
        renderer: &GpuRenderer,
        scene: &LitScene,
        outward: impl Fn(usize) -> f64,
    ) -> Self {
        let eye = scene.world_camera().eye;
        let stored = scene
            .world_meshes()
            .iter()
            .enumerate()
            .map(|(i, m)| StoredMesh::new(&m.mesh, DMat4::IDENTITY, eye, outward(i)))
            .collect();
        Self::with_stored(renderer, stored, SceneLight::of_scene(scene))
    }

    /// How many meshes it holds.
    pub fn mesh_count(&self) -> usize {
        self.meshes.len()
    }

    /// Mesh `mesh`'s transform into the world.
    pub fn transform(&self, mesh: usize) -> DMat4 {
        self.meshes[mesh].transform
    }

    /// Moves mesh `mesh` into the world by `transform` from the next frame on.
    ///
    /// # Panics
    ///
    /// If there is no mesh `mesh`.
    pub fn set_transform(&mut self, mesh: usize, transform: DMat4) {
        let m = &mut self.meshes[mesh];
        if m.transform != transform {
            m.transform = transform;
            self.meshes_moved();
        }
    }

    /// Moves mesh `mesh`'s vertices to `positions` (in its own space, one per vertex, in the
    /// order it was given) from the next frame on: a deforming mesh (skinned, simulated). Only
    /// the positions are written to the GPU; under [`ShadowBuilder::Gpu`], `hard` and `wedges`
    /// build their shadows from them there.
    ///
    /// # Panics
    ///
    /// If there is no mesh `mesh`.
    pub fn set_positions(&mut self, mesh: usize, positions: &[DVec3]) -> Result<(), GpuError> {
        let count = self.meshes[mesh].mesh.positions.len();
        if positions.len() != count {
            return Err(GpuError::PositionCount {
                mesh,
                expected: count,
                given: positions.len(),
            });
        }
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(GpuError::NonFinitePosition { mesh, vertex });
        }
        self.meshes[mesh].move_vertices(positions);
        self.built();
        let m = &self.meshes[mesh];
        let stored = bytemuck::cast_slice::<[f32; 3], u8>(&m.stored);
        match &self.built {
            Some(Ok(built)) => {
                let at = 12 * u64::from(built.first_vertex[mesh]);
                self.ctx.queue.write_buffer(&built.positions, at, stored);
                self.corners_stale = true;
            }
            _ => {
                // The corners written from here: the GPU cannot expand them.
                let corners: Vec<[f32; 3]> = m
                    .mesh
                    .triangles
                    .iter()
                    .flatten()
                    .map(|&i| m.stored[i as usize])
                    .collect();
                let at = 12 * u64::from(self.vertex_ranges[mesh].start);
                let bytes = bytemuck::cast_slice(&corners);
                self.ctx.queue.write_buffer(&self.vertices, at, bytes);
                self.uploads.geometry += bytes.len() as u64;
            }
        }
        self.uploads.geometry += stored.len() as u64;
        self.meshes_moved();
        Ok(())
    }

    /// Drops what was built for the meshes where they were.
    fn meshes_moved(&mut self) {
        self.shadows = None;
        self.kept.clear();
        self.built_fresh = false;
        self.complexity.light_changed();
    }

    /// Where `hard` and `wedges` build their shadows from the next frame on
    /// ([`ShadowBuilder::Gpu`] unless set).
    pub fn set_shadow_builder(&mut self, builder: ShadowBuilder) {
        self.builder = builder;
    }

    /// Where they do.
    pub fn shadow_builder(&self) -> ShadowBuilder {
        self.builder
    }

    /// How `wedges` and `wedges-blend` evaluate their wedges from the next frame on (by default
    /// [`WedgePass::for_device`] of the scene's device).
    pub fn set_wedge_pass(&mut self, pass: WedgePass) {
        self.wedge_pass = pass;
    }

    /// How it does.
    pub fn wedge_pass(&self) -> WedgePass {
        self.wedge_pass
    }

    /// The build's buffers, made (and the topology uploaded) on first use; `None` where the
    /// scene is too large for them.
    fn built(&mut self) -> Option<&Built> {
        if self.built.is_none() {
            let p = &self.pipelines;
            let built = Built::new(
                &self.ctx.device,
                (&p.build, &p.stencil),
                &self.meshes,
                &self.vertices,
                (&self.uniforms, &self.models),
            );
            if let Ok(b) = &built {
                self.uploads.geometry += b.uploaded;
            }
            self.built = Some(built);
        }
        self.built.as_ref().and_then(|b| b.as_ref().ok())
    }

    /// Whether this frame's `hard` or `wedges` shadows are built on the GPU: so asked, the
    /// scene fits the build, and every mesh lies on the light's emitting side, its plane
    /// included (its bounding box's corners, where the passes see them: a room whose ceiling
    /// holds its lamp flush), so that none is cut by it.
    fn builds_on_gpu(&mut self) -> bool {
        if self.builder != ShadowBuilder::Gpu {
            return false;
        }
        let rect = *self.light.rect();
        let warp = self.light.warp().copied();
        let in_front = meshes::world_corners(&self.meshes).into_iter().all(|c| {
            let c = warp.map_or(c, |w| w.point(c));
            rect.to_light_space(c).z >= 0.0
        });
        in_front && self.built().is_some()
    }

    /// The light: a rectangle light, or a distant light.
    pub fn light(&self) -> Light {
        self.light.light()
    }

    /// Lights the scene by `light`, a [`RectLight`] or a [`penumbra_geom::DistantLight`], from
    /// the next frame on. A distant light is rendered through its warp
    /// ([`penumbra_geom::Warp`], `docs/scene-format.md`, "Distant lights"): the G-buffer then
    /// holds the warped scene's points, as [`GpuScene::record_depth`] writes them.
    pub fn set_light(&mut self, light: impl Into<Light>) {
        let light = light.into();
        if self.light.light() == light {
            return;
        }
        let before = *self.light.rect();
        self.light = SceneLight::new(light, &self.meshes);
        let changed = *self.light.rect() != before;
        if changed {
            // Keep what was built for the light left, and take what was kept for this one.
            if let Some(shadows) = self.shadows.take() {
                self.kept.retain(|(l, _)| *l != before);
                self.kept.push((before, shadows));
                if self.kept.len() > KEPT_LIGHTS {
                    self.kept.remove(0);
                }
            }
            self.light_changed();
            if let Some(at) = self.kept.iter().position(|(l, _)| l == self.light.rect()) {
                self.shadows = Some(self.kept.remove(at).1);
            }
        }
    }

    /// The warp a distant light's frames are rendered through, `None` under a rectangle light:
    /// an application that writes its own G-buffer under a distant light writes the points
    /// [`penumbra_geom::Warp::point`] makes of its surface points, relative to the warp's image
    /// of the eye.
    pub fn warp(&self) -> Option<penumbra_geom::Warp> {
        self.light.warp().copied()
    }

    /// Drops what was built for the light.
    fn light_changed(&mut self) {
        self.shadows = None;
        self.built_fresh = false;
        self.complexity.light_changed();
    }

    /// The bytes written to the GPU since the last call (or since the scene was made).
    pub fn take_uploads(&mut self) -> Uploads {
        std::mem::take(&mut self.uploads)
    }

    /// Silhouette edges (one wedge each) of the current light and transforms; 0 until a frame
    /// needed them.
    pub fn wedge_count(&self) -> usize {
        self.shadows.as_ref().map_or(0, |s| s.wedges)
    }

    /// The silhouettes' products, rebuilt if the light or a transform changed.
    fn shadows(&mut self) -> &Shadows {
        if self.shadows.is_none() {
            let (meshes, world) = world(&self.meshes, self.light.warp());
            let volumes = Volumes::build_meshes(&meshes, self.light.rect());
            let (shadows, bytes) = Shadows::build(
                &self.ctx.device,
                &self.meshes,
                self.light.rect(),
                &volumes,
                &world,
            );
            self.uploads.shadows += bytes;
            self.shadows = Some(shadows);
        }
        self.shadows.as_ref().expect("built above")
    }

    /// Writes the frame's uniforms and model matrices where they changed, for the application's
    /// camera `world` and the camera the passes see ([`GpuScene::frame_camera`]).
    fn write_frame(&mut self, world: &FrameCamera, camera: &FrameCamera) {
        let mut uniforms = FrameUniforms::new(camera, self.light.rect());
        if let Some(warp) = self.light.warp() {
            uniforms = uniforms.with_warp(warp, world.eye, camera);
        }
        // A point just in front of a lamp's centre: a closed mesh around it and the eye is a
        // room lit from inside, whose surfaces face the light from within (a distant light is
        // in no room).
        let eye = world.eye;
        let in_front = match self.light.warp() {
            Some(_) => None,
            None => Some(penumbra_volumes::in_front_of(self.light.rect())),
        };
        let models: Vec<ModelMatrix> = self
            .meshes
            .iter_mut()
            .map(|m| {
                // A mirroring transform turns an outward winding inwards.
                let winding = m.outward * m.transform.determinant().signum();
                let mut sign = winding;
                if sign != 0.0 && in_front.is_some_and(|p| m.is_room(p, eye)) {
                    sign = -sign;
                }
                model_matrix(world.eye, &m.transform, m.origin, (sign, winding))
            })
            .collect();
        let bytes = |u: &FrameUniforms| bytemuck::bytes_of(u).to_vec();
        let (same_u, same_m) = match &self.written {
            Some((u, m)) => (bytes(u) == bytes(&uniforms), *m == models),
            None => (false, false),
        };
        let queue = &self.ctx.queue;
        if !same_u {
            queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
            self.uploads.frame += std::mem::size_of::<FrameUniforms>() as u64;
        }
        if !same_m && !models.is_empty() {
            queue.write_buffer(&self.models, 0, bytemuck::cast_slice(&models));
            self.uploads.frame += std::mem::size_of_val(models.as_slice()) as u64;
        }
        self.written = Some((uniforms, models));
    }
}
