//! Which volumes and wedges a frame of `hard`, `wedges` or the tiled `wedges-blend` draws:
//! those the GPU built ([`Built`]) or those the CPU built and uploaded ([`Shadows`]), as the
//! stencil and wedge passes take them.

use std::ops::Range;

use super::built::Built;
use super::shadows::Shadows;
use crate::passes::stencil::VolumeDraws;
use crate::passes::wedge_tiles::two_parts;

/// The volumes and wedges of a frame.
#[derive(Clone, Copy)]
pub(super) enum FrameShadows<'a> {
    /// Built on the GPU this frame or before.
    Built(&'a Built),
    /// Built on the CPU and uploaded.
    Uploaded(&'a Shadows),
}

/// The wedges as a wedge pass draws them: the instance buffer, and either the range of it to
/// draw or the draw's arguments (buffer and offset) the build wrote.
pub(super) struct WedgeSource<'a> {
    pub(super) buffer: &'a wgpu::Buffer,
    pub(super) range: Range<u32>,
    pub(super) indirect: Option<(&'a wgpu::Buffer, u64)>,
}

impl<'a> FrameShadows<'a> {
    /// The volumes for the stencil pass, and the bytes it binds.
    pub(super) fn volumes(self) -> (VolumeDraws<'a>, u64) {
        match self {
            FrameShadows::Built(b) => (
                VolumeDraws::Built {
                    group: &b.stencil_group,
                    faces: b.faces,
                    args: &b.args,
                },
                b.volume_bytes(),
            ),
            FrameShadows::Uploaded(s) => (
                VolumeDraws::Vertices {
                    vertices: &s.volume,
                    ranges: &s.volume_ranges,
                },
                s.volume.size(),
            ),
        }
    }

    /// The wedges for the rasterised wedge pass.
    pub(super) fn wedges(self) -> WedgeSource<'a> {
        match self {
            FrameShadows::Built(b) => WedgeSource {
                buffer: &b.wedges,
                range: 0..0,
                indirect: Some((&b.args, 16)),
            },
            FrameShadows::Uploaded(s) => WedgeSource {
                buffer: &s.instance_buffer,
                range: 0..s.instances.len() as u32,
                indirect: None,
            },
        }
    }

    /// The wedges for the tiled wedge pass: in two bindings of at most `max_binding` bytes
    /// each, with the arguments whose word 5 counts them; `None` when two bindings cannot hold
    /// them.
    pub(super) fn tiled(
        self,
        max_binding: u64,
    ) -> Option<([wgpu::BufferBinding<'a>; 2], &'a wgpu::Buffer)> {
        match self {
            FrameShadows::Built(b) => two_parts(&b.wedges, b.wedge_capacity, &b.spare, max_binding)
                .map(|parts| (parts, &b.args)),
            // No instance: the stand-in holds the one the bindings need, and none counts.
            FrameShadows::Uploaded(s) if s.instances.is_empty() => {
                two_parts(&s.spare, 1, &s.spare, max_binding).map(|parts| (parts, &s.args))
            }
            FrameShadows::Uploaded(s) => two_parts(
                &s.instance_buffer,
                s.instances.len() as u64,
                &s.spare,
                max_binding,
            )
            .map(|parts| (parts, &s.args)),
        }
    }
}
