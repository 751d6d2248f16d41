//! The wgpu back end of penumbra: one module and one WGSL file per pass (seed 004, section 4).
//!
//! Implemented so far: the device (any adapter, hardware first, Mesa's lavapipe otherwise), the
//! depth pre-pass, the z-fail stencil pass of the shadow volumes and the resolve pass, which
//! together render the `hard` technique. The wedge and blend passes are the next steps; until
//! then `wedges` and `wedges-blend` run on the CPU oracle of `penumbra-volumes`.
#![warn(missing_docs)]

pub mod context;
pub mod frame;
pub mod hard;
pub mod passes;

pub use context::{GpuContext, GpuError};
pub use hard::GpuHardRenderer;
pub use penumbra_volumes as volumes;
