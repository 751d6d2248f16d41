//! What a [`super::GpuScene`] writes to the GPU, counted by kind.

/// Bytes written to the GPU's buffers, by kind ([`super::GpuScene::take_uploads`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Uploads {
    /// The meshes' vertices, written when the scene is made and when the application moves
    /// them ([`super::GpuScene::set_positions`]), and their topology, written once for the
    /// shadows the GPU builds.
    pub geometry: u64,
    /// Shadow volumes and wedge instances built on the CPU: written in frames where the light or
    /// a mesh moved and the CPU builds them ([`super::ShadowBuilder`]).
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
