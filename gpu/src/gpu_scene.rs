//! A scene on the GPU, uploaded once and rendered every frame into an application's targets:
//! its meshes' vertices stay on the device; per frame only the camera, the meshes' model
//! matrices and (for `wedges-blend`) the blend's tile lists are written. The silhouettes, shadow
//! volumes and wedges depend on the light and on where the meshes are: they are rebuilt on the
//! CPU and uploaded again only in frames where the light or a mesh's transform changed.

use std::ops::Range;

use glam::{DMat4, DVec3};
use penumbra_geom::{HalfEdgeMesh, RectLight, Scene, Technique, TriangleMesh};
use penumbra_volumes::Volumes;
use penumbra_volumes::outward_sign;

use crate::context::{GpuContext, GpuError};
use crate::frame::{FrameCamera, FrameUniforms, ModelMatrix, frame_group, model_matrix};
use crate::passes::blend::{FINAL_WORDS, SILHOUETTE_FORMATS};
use crate::passes::wedge::{OCCLUSION_FORMAT, WedgeInstance, unit_cube};
use crate::passes::{buffer, texture, view};
use crate::renderer::{GpuRenderer, Pipelines};
use crate::scene_data::{ReceiverClusters, nearest_edges, volume_vertices, wedge_instances};

/// Bytes written to the GPU's buffers, by kind ([`GpuScene::take_uploads`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Uploads {
    /// The meshes' vertices: written when the scene is made, never again.
    pub geometry: u64,
    /// Shadow volumes and wedge instances: written in frames where the light or a mesh's
    /// transform changed.
    pub shadows: u64,
    /// The frame: uniforms and model matrices when they changed, and the blend's tile lists.
    pub frame: u64,
}

impl Uploads {
    /// All bytes.
    pub fn total(&self) -> u64 {
        self.geometry + self.shadows + self.frame
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

/// One mesh as stored: its own-space mesh, its vertices relative to `origin` in `f32`, and where
/// it is.
pub(crate) struct StoredMesh {
    pub(crate) mesh: TriangleMesh,
    /// `penumbra_volumes::outward_sign` of the mesh in its own space.
    pub(crate) outward: f64,
    pub(crate) origin: DVec3,
    pub(crate) transform: DMat4,
    pub(crate) stored: Vec<[f32; 3]>,
}

/// The silhouettes' products for the current light and transforms.
pub(crate) struct Shadows {
    /// Shadow-volume vertices ([`volume_vertices`]) and each blending unit's mesh and range.
    pub(crate) volume: wgpu::Buffer,
    pub(crate) volume_ranges: Vec<(u32, Range<u32>)>,
    /// Wedge instances, on both sides, and each blending unit's range of them.
    pub(crate) instances: Vec<WedgeInstance>,
    pub(crate) instance_buffer: wgpu::Buffer,
    pub(crate) instance_ranges: Vec<Range<u32>>,
    /// Each unit's nearest silhouette edge (light space), and the receivers' clusters.
    pub(crate) nearest: Vec<f64>,
    pub(crate) clusters: ReceiverClusters,
    /// Silhouette edges, for reports.
    pub(crate) wedges: usize,
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
    pub(crate) ctx: GpuContext,
    pub(crate) pipelines: std::sync::Arc<Pipelines>,
    pub(crate) meshes: Vec<StoredMesh>,
    pub(crate) vertices: wgpu::Buffer,
    pub(crate) vertex_ranges: Vec<Range<u32>>,
    pub(crate) light: RectLight,
    pub(crate) shadows: Option<Shadows>,
    pub(crate) uniforms: wgpu::Buffer,
    pub(crate) models: wgpu::Buffer,
    pub(crate) frame: wgpu::BindGroup,
    /// What `uniforms` and `models` hold.
    written: Option<(FrameUniforms, Vec<ModelMatrix>)>,
    pub(crate) cube: wgpu::Buffer,
    pub(crate) scratch: Scratch,
    pub(crate) uploads: Uploads,
    /// Depth-complexity sampling: what it keeps of the scene (dropped with `shadows`), its
    /// frame's buffers, its samples per axis and its edge list's entries (0: not yet sized).
    pub(crate) complexity: Option<crate::complexity::ComplexityScene>,
    pub(crate) complexity_frame: Option<crate::complexity::ComplexityFrame>,
    pub(crate) samples_per_axis: u32,
    pub(crate) list_capacity: u32,
    pub(crate) loop_budget: u32,
}

/// The techniques' own targets at one image size, made the first time a frame needs them and
/// kept while the size stays.
#[derive(Default)]
pub(crate) struct Scratch {
    size: (u32, u32),
    /// `wedges`: the per-part occlusion.
    pub(crate) occlusion: Option<wgpu::TextureView>,
    /// `wedges-blend`: the silhouette buffer's targets and the final buffer.
    pub(crate) silhouettes: Option<(Vec<wgpu::TextureView>, wgpu::Buffer)>,
}

impl Scratch {
    /// Makes what `technique` needs at `size`.
    pub(crate) fn prepare(
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
                    sampled,
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

/// Centre of the bounding box of `positions` (the origin when there are none).
fn centre(positions: &[DVec3]) -> DVec3 {
    let (lo, hi) = positions
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    if lo.x <= hi.x {
        (lo + hi) * 0.5
    } else {
        DVec3::ZERO
    }
}

impl GpuScene {
    /// Uploads `meshes`, each given in its own space with its transform into the world, lit by
    /// `light`.
    ///
    /// ```no_run
    /// use glam::dcamera::rh::{proj::directx, view};
    /// use glam::{DMat4, DVec2, DVec3};
    /// use penumbra_geom::{RectLight, Technique, TriangleMesh};
    /// use std::path::Path;
    /// use penumbra_gpu::{FrameCamera, FrameInputs, GBuffer, GpuContext, GpuRenderer, GpuScene};
    ///
    /// let ctx = GpuContext::new()?;
    /// let renderer = GpuRenderer::with_context(&ctx);
    /// let corners = [[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]];
    /// let corners = corners.map(DVec3::from_array);
    /// let quad = TriangleMesh::from_raw("quad", &corners, &[[0, 2, 1], [0, 3, 2]])
    ///     .unwrap();
    /// let light = RectLight::new(DVec3::new(0.0, 4.0, 0.0), -DVec3::Y, DVec3::X, DVec2::ONE);
    /// let mut scene = GpuScene::new(&renderer, &[(&quad, DMat4::IDENTITY)], light);
    ///
    /// let size = (320, 240);
    /// let view = view::look_at_mat4(DVec3::new(0.0, 3.0, 5.0), DVec3::ZERO, DVec3::Y);
    /// let projection = directx::perspective_infinite_reverse(0.8, 320.0 / 240.0, 0.01);
    /// let camera = FrameCamera::from_matrices(&view, &projection, size).unwrap();
    /// let inputs = FrameInputs { camera, technique: Technique::WedgesBlend };
    /// let gbuffer = GBuffer::new(&ctx.device, size);
    /// // The application's own R32Float target (RENDER_ATTACHMENT).
    /// let target = penumbra_gpu::passes::depth::visibility_target(&ctx.device, size);
    /// let view = target.create_view(&Default::default());
    ///
    /// let mut encoder = ctx.device.create_command_encoder(&Default::default());
    /// scene.record_depth(&mut encoder, &camera, &gbuffer)?;
    /// scene.record(&mut encoder, &inputs, &gbuffer, &view)?;
    /// ctx.queue.submit([encoder.finish()]);
    /// # Ok::<(), penumbra_gpu::GpuError>(())
    /// ```
    pub fn new(
        renderer: &GpuRenderer,
        meshes: &[(&TriangleMesh, DMat4)],
        light: RectLight,
    ) -> Self {
        let meshes: Vec<(&TriangleMesh, DMat4, DVec3, f64)> = meshes
            .iter()
            .map(|&(m, t)| {
                let outward = outward_sign(m, &HalfEdgeMesh::build(m));
                (m, t, centre(&m.positions), outward)
            })
            .collect();
        Self::with_origins(renderer, &meshes, light)
    }

    /// [`GpuScene::new`] with each mesh's vertices stored relative to the given origin, and its
    /// outward sign given.
    pub(crate) fn with_origins(
        renderer: &GpuRenderer,
        meshes: &[(&TriangleMesh, DMat4, DVec3, f64)],
        light: RectLight,
    ) -> Self {
        let device = &renderer.ctx.device;
        let mut uploads = Uploads::default();
        let mut corners: Vec<[f32; 3]> = Vec::new();
        let mut vertex_ranges = Vec::with_capacity(meshes.len());
        let stored: Vec<StoredMesh> = meshes
            .iter()
            .map(|&(mesh, transform, origin, outward)| {
                let stored: Vec<[f32; 3]> = mesh
                    .positions
                    .iter()
                    .map(|&p| (p - origin).as_vec3().to_array())
                    .collect();
                let start = corners.len() as u32;
                corners.extend(mesh.triangles.iter().flatten().map(|&i| stored[i as usize]));
                vertex_ranges.push(start..corners.len() as u32);
                StoredMesh {
                    outward,
                    mesh: mesh.clone(),
                    origin,
                    transform,
                    stored,
                }
            })
            .collect();
        let vertices = buffer(device, "meshes", &corners, wgpu::BufferUsages::VERTEX);
        uploads.geometry += std::mem::size_of_val(corners.as_slice()) as u64;
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
        let frame = frame_group(device, &renderer.pipelines.frame_layout, &uniforms, &models);
        let cube = buffer(
            device,
            "unit cube",
            &unit_cube(),
            wgpu::BufferUsages::VERTEX,
        );
        GpuScene {
            ctx: renderer.ctx.clone(),
            pipelines: renderer.pipelines.clone(),
            meshes: stored,
            vertices,
            vertex_ranges,
            light,
            shadows: None,
            uniforms,
            models,
            frame,
            written: None,
            cube,
            scratch: Scratch::default(),
            uploads,
            complexity: None,
            complexity_frame: None,
            samples_per_axis: crate::complexity::DEFAULT_AXIS,
            list_capacity: 0,
            loop_budget: if renderer.ctx.info.device_type == wgpu::DeviceType::Cpu {
                crate::complexity::SOFTWARE_LOOP_BUDGET
            } else {
                u32::MAX
            },
        }
    }

    /// The meshes of `scene` (world space, stored relative to the eye: the one-shot renderer's
    /// exact layout) with the silhouettes' products of `volumes`, built for `scene`.
    pub(crate) fn for_scene(renderer: &GpuRenderer, scene: &Scene, volumes: &Volumes) -> Self {
        let mut s = Self::of_scene(renderer, scene, |i| volumes.occluders[i].outward);
        let world = scene.triangles();
        s.shadows = Some(s.build_shadows(volumes, &world));
        s
    }

    /// The meshes of `scene` in the one-shot renderer's layout (world space, stored relative to
    /// the eye), mesh `i` with the outward sign `outward(i)`; nothing built for the light yet.
    pub(crate) fn of_scene(
        renderer: &GpuRenderer,
        scene: &Scene,
        outward: impl Fn(usize) -> f64,
    ) -> Self {
        let eye = scene.camera.eye;
        let meshes: Vec<(&TriangleMesh, DMat4, DVec3, f64)> = scene
            .meshes
            .iter()
            .enumerate()
            .map(|(i, m)| (&m.mesh, DMat4::IDENTITY, eye, outward(i)))
            .collect();
        Self::with_origins(renderer, &meshes, scene.light)
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
            self.shadows = None;
            self.complexity = None;
        }
    }

    /// The light.
    pub fn light(&self) -> &RectLight {
        &self.light
    }

    /// Lights the scene by `light` from the next frame on.
    pub fn set_light(&mut self, light: RectLight) {
        if self.light != light {
            self.light = light;
            self.shadows = None;
            self.complexity = None;
        }
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

    /// The world-space meshes and their triangles.
    pub(crate) fn world(&self) -> (Vec<TriangleMesh>, Vec<[DVec3; 3]>) {
        let meshes: Vec<TriangleMesh> = self
            .meshes
            .iter()
            .map(|m| m.mesh.transformed(&m.transform))
            .collect();
        let triangles = meshes
            .iter()
            .flat_map(|m| {
                m.triangles
                    .iter()
                    .map(|t| t.map(|i| m.positions[i as usize]))
            })
            .collect();
        (meshes, triangles)
    }

    /// The silhouettes' products of `volumes` (built for the current light and transforms;
    /// `world`: the scene's triangles), uploaded.
    fn build_shadows(&mut self, volumes: &Volumes, world: &[[DVec3; 3]]) -> Shadows {
        let device = &self.ctx.device;
        let stored: Vec<&[[f32; 3]]> = self.meshes.iter().map(|m| m.stored.as_slice()).collect();
        let (vol, ranges) = volume_vertices(volumes, &stored);
        let (instances, instance_ranges) = wedge_instances(&self.light, world, volumes);
        self.uploads.shadows += (std::mem::size_of_val(vol.as_slice())
            + std::mem::size_of_val(instances.as_slice())) as u64;
        Shadows {
            volume: buffer(device, "volume triangles", &vol, wgpu::BufferUsages::VERTEX),
            volume_ranges: ranges,
            instance_buffer: buffer(device, "wedges", &instances, wgpu::BufferUsages::VERTEX),
            instances,
            instance_ranges,
            nearest: nearest_edges(volumes),
            clusters: ReceiverClusters::new(&self.light, world),
            wedges: volumes.wedges.len(),
        }
    }

    /// The silhouettes' products, rebuilt if the light or a transform changed.
    pub(crate) fn shadows(&mut self) -> &Shadows {
        if self.shadows.is_none() {
            let (meshes, world) = self.world();
            let volumes = Volumes::build_meshes(&meshes, &self.light);
            self.shadows = Some(self.build_shadows(&volumes, &world));
        }
        self.shadows.as_ref().expect("built above")
    }

    /// Writes the frame's uniforms and model matrices for `camera` where they changed.
    pub(crate) fn write_frame(&mut self, camera: &FrameCamera) {
        let uniforms = FrameUniforms::new(camera, &self.light);
        let models: Vec<ModelMatrix> = self
            .meshes
            .iter()
            .map(|m| {
                // A mirroring transform turns an outward winding inwards.
                let sign = m.outward * m.transform.determinant().signum();
                model_matrix(camera.eye, &m.transform, m.origin, sign)
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

/// Checks that `technique` is one [`GpuScene::record`] renders.
pub(crate) fn check_technique(technique: Technique) -> Result<(), GpuError> {
    if technique.is_volume() || technique == Technique::DepthComplexity {
        Ok(())
    } else {
        Err(GpuError::Frame(format!(
            "{technique}: a GpuScene records the volume techniques (hard, wedges, wedges-blend) \
             and depth-complexity"
        )))
    }
}
