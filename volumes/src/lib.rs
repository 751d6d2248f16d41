//! Silhouettes, shadow volumes and penumbra wedges, evaluated on the CPU (Forest, Barthe &
//! Paulin, "Realistic Soft Shadows by Penumbra-Wedges Blending", 2006). Filled by the volumes
//! issue; for now it only re-exports the geometry it builds on.
#![warn(missing_docs)]

pub use penumbra_geom as geom;
