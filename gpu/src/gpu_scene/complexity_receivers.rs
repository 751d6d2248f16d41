//! What depth-complexity sampling finds of each pixel's receiver besides the depth pre-pass,
//! for the counting pass's `count_setup` to check it against: the nearest triangle the pixel's
//! ray meets (`passes::candidates`).

use crate::counters::{Pass, Traffic};
use crate::passes::candidates::{CANDIDATE_DEPTH_FORMAT, CANDIDATE_FORMAT};
use crate::passes::{texture, view};
use crate::pipelines::Pipelines;
use crate::timing::Timer;

/// The targets, at one image size.
pub(super) struct ReceiverTargets {
    /// The receiver candidates and their depth.
    candidate: wgpu::Texture,
    candidate_depth: wgpu::Texture,
}

/// What the receivers' pass reads of the scene: the frame's group 0, depth-complexity
/// sampling's parameters and its triangles (and how many).
pub(super) struct ReceiverInputs<'a> {
    pub(super) frame: &'a wgpu::BindGroup,
    pub(super) params: &'a wgpu::Buffer,
    pub(super) triangles: (&'a wgpu::Buffer, u32),
}

impl ReceiverTargets {
    pub(super) fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let drawn = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let read = drawn | wgpu::TextureUsages::TEXTURE_BINDING;
        ReceiverTargets {
            candidate: texture(device, "receiver candidates", size, CANDIDATE_FORMAT, read),
            candidate_depth: texture(
                device,
                "receiver candidates' depth",
                size,
                CANDIDATE_DEPTH_FORMAT,
                drawn,
            ),
        }
    }

    /// The candidates, which the counting pass reads.
    pub(super) fn candidates(&self) -> wgpu::TextureView {
        view(&self.candidate)
    }

    /// Records the candidates' pass.
    pub(super) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (device, p): (&wgpu::Device, &Pipelines),
        inputs: ReceiverInputs<'_>,
        timer: &Timer,
    ) {
        let (triangles, count) = inputs.triangles;
        let group = p.candidates.inputs(device, inputs.params, triangles);
        let traffic = Traffic::new()
            .reads(inputs.params)
            .reads(triangles)
            .writes(&self.candidate)
            .updates(&self.candidate_depth);
        p.candidates.record(
            encoder,
            (inputs.frame, &group),
            (&view(&self.candidate), &view(&self.candidate_depth)),
            count,
            timer.pass(Pass::Count, traffic),
        );
    }
}
