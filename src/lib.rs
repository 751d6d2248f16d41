//! penumbra: physically based soft shadows built from geometry.
//!
//! This facade re-exports the workspace's crates, in the order data flows through them:
//! [`params`] (the shadow-map techniques' parameters), [`geom`] (meshes, scenes, rays, the
//! references), [`volumes`] (silhouettes, shadow volumes, penumbra wedges on the CPU) and
//! [`gpu`] (the wgpu passes).
//!
//! The front door is [`Renderer`]: give it a [`Scene`] (loaded from a scene file, see
//! `docs/scene-format.md`, or made in code with [`Scene::new`]) and a [`Technique`], get a
//! [`VisibilityImage`]: the share of the light's area each pixel's surface point sees.
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
//! let c = penumbra::geom::compare(&wedges, &exact)?;
//! assert!(c.penumbra.pixels > 1000 && c.all.mae < 0.05);
//! let out = std::env::temp_dir().join(format!("nonmanifold-{}.exr", std::process::id()));
//! exact.write_exr(&out)?;
//! # std::fs::remove_file(out)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! **In a wgpu application's own frame**, [`GpuScene`] takes the place of the renderer: the
//! meshes are uploaded once, each frame's camera ([`FrameCamera`], from the application's view
//! and projection matrices), meshes' transforms and light may change, and
//! [`GpuScene::record`] writes V into a texture the application owns, in its own command
//! encoder ([`GBuffer`] documents the depth and position inputs; `examples/animated.rs` is a
//! whole program, and `docs/gpu.md` the reference).
#![warn(missing_docs)]

mod render;
mod runs;

pub use glam;
pub use penumbra_geom as geom;
pub use penumbra_geom::{Scene, Technique, VisibilityImage};
pub use penumbra_gpu as gpu;
pub use penumbra_gpu::{FrameCamera, FrameInputs, GBuffer, GpuRenderer, GpuScene, Uploads};
pub use penumbra_params as params;
pub use penumbra_volumes as volumes;
pub use render::{Backend, Frame, MAX_SAMPLES, RenderError, RenderOptions, Renderer};
pub use runs::Runs;
