//! The wgpu back end of penumbra: one module and one WGSL file per pass. Filled by the wgpu
//! issue; for now it only re-exports the CPU crates it builds on.
#![warn(missing_docs)]

pub use penumbra_volumes as volumes;
