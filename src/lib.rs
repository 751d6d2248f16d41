//! penumbra: physically based soft shadows built from geometry.
//!
//! This facade re-exports the workspace's crates, in the order data flows through them:
//! [`params`] (the shadow-map techniques' parameters), [`geom`] (meshes, scenes, rays, the
//! references), [`volumes`] (silhouettes, shadow volumes, penumbra wedges on the CPU) and
//! [`gpu`] (the wgpu passes).
//!
//! The front door is [`Renderer`]: give it a [`Scene`] (loaded from a scene file, see
//! `docs/scene-format.md`, or made in code with [`Scene::new`]) and a [`Technique`], get a
//! [`VisibilityImage`]: the share of the light's area each pixel's surface point sees. A scene
//! of several lights (`[[light]]`) renders with [`Renderer::render_lights`] into
//! [`VisibilityChannels`], one image per light.
//!
//! ```
//! use penumbra::{Backend, RenderOptions, Renderer, Scene, Technique};
//!
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/scenes/nonmanifold.toml");
//! let scene = Scene::load(std::path::Path::new(path))?;
//! // The GPU where there is one for the techniques that can use it, the CPU otherwise.
//! let mut renderer = Renderer::new(Backend::Auto);
//! let exact = renderer.render(&scene, Technique::DepthComplexity, &RenderOptions::default())?;
//! let wedges = renderer.render(&scene, Technique::WedgesBlend, &RenderOptions::default())?;
//! let c = penumbra::compare(&wedges, &exact)?;
//! assert!(c.penumbra.pixels > 1000 && c.all.mae < 0.05);
//! let out = std::env::temp_dir().join(format!("nonmanifold-{}.exr", std::process::id()));
//! exact.write_exr(&out)?;
//! # std::fs::remove_file(out)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A scene made in code needs only this crate's names: a [`Camera`], its lights (each a
//! [`RectLight`], for instance [`RectLight::aimed`] at a point, or a [`DistantLight`], for
//! instance [`DistantLight::sun`] by azimuth and elevation), and [`TriangleMesh`]es placed by
//! `glam` matrices (re-exported as [`glam`]).
//!
//! ```
//! use penumbra::glam::{DMat4, DVec2, DVec3};
//! use penumbra::{Backend, Camera, RectLight, RenderOptions, Renderer, Scene, Technique, TriangleMesh};
//!
//! let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 64, 48)?;
//! // A 1 x 1 lamp 5 above the origin, facing it.
//! let light = RectLight::aimed(DVec3::new(0.0, 5.0, 0.0), DVec3::ZERO, DVec2::splat(1.0))?;
//! // The unit quad scaled to an 8 x 8 ground, and a sphere of radius 0.5 one above it.
//! let ground = DMat4::from_scale(DVec3::splat(8.0));
//! let ball = DMat4::from_translation(DVec3::new(0.0, 1.0, 0.0)) * DMat4::from_scale(DVec3::splat(0.5));
//! // Lights and meshes are added in any order.
//! let scene = Scene::new(camera)
//!     .with_light(light)
//!     .with_mesh("ground", &TriangleMesh::quad(), ground)
//!     .with_mesh("ball", &TriangleMesh::uv_sphere(12, 16), ball);
//! let v = Renderer::new(Backend::Cpu).render(&scene, Technique::WedgesBlend, &RenderOptions::default())?;
//! // The ball's shadow falls straight below it, in the middle of the image; the corners are lit.
//! assert_eq!(v.get(0, 47), 1.0);
//! assert!(v.data.iter().any(|&x| x == 0.0));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! **In a wgpu application's own frame**, [`GpuScene`] takes the place of the renderer: the
//! meshes are uploaded once, each frame's camera ([`FrameCamera`], from the application's view
//! and projection matrices), meshes' transforms and light may change, and
//! [`GpuScene::record`] writes V into a texture the application owns, in its own command
//! encoder ([`GBuffer`] documents the depth and position inputs; `examples/animated.rs` is a
//! whole program, and `docs/gpu.md` the reference).
//!
//! Where each render runs, GPU or CPU, is one policy: [`backend`] states its rules and
//! [`backend::choose`] applies them.
#![warn(missing_docs)]

pub mod backend;
mod cpu;
mod error;
mod options;
mod rendered_frame;
mod renderer;
mod runs;
mod sensors;
mod sun_hours;

#[cfg(test)]
mod backend_tests;

pub use glam;
pub use penumbra_geom as geom;
pub use penumbra_geom::CameraError;
pub use penumbra_geom::ImageError;
pub use penumbra_geom::MeshError;
pub use penumbra_geom::RangeError;
pub use penumbra_geom::{
    Camera, Channel, DistantLight, Light, LightError, LitScene, NamedLight, RectLight, Scene,
    SceneError, Technique, TriangleMesh, VisibilityChannels, VisibilityImage,
};
pub use penumbra_geom::{Comparison, compare};
pub use penumbra_gpu as gpu;
pub use penumbra_gpu::{FrameCamera, FrameInputs, GBuffer, GpuRenderer, GpuScene, Uploads};
pub use penumbra_params as params;
pub use penumbra_volumes as volumes;

pub use backend::{Backend, MAX_GPU_BLEND_UNITS, MAX_GPU_SAMPLES};
pub use error::{MissingGpu, RenderError};
pub use options::{MAX_SAMPLES, RenderOptions};
pub use rendered_frame::{Frame, Warning};
pub use renderer::Renderer;
pub use runs::Runs;
pub use sensors::Sensors;
pub use sun_hours::{SunStep, SunStudy, SunTarget};
