//! A [`GpuScene`] lit by a distant light: the warp that renders the light as a rectangle
//! ([`Warp`], `docs/scene-format.md`, "Distant lights"), kept from frame to frame while it holds
//! the meshes and the eye, and the camera the passes then see.

use glam::DVec3;
use penumbra_geom::{DistantLight, RectLight, Warp};

use super::GpuScene;
use super::meshes::{StoredMesh, world_corners};
use crate::frame_uniforms::FrameCamera;

/// A distant light and the warp its frames are rendered through.
pub(super) struct Distant {
    pub(super) light: DistantLight,
    pub(super) warp: Warp,
}

impl Distant {
    /// `light` with the warp around `meshes` as they are placed now.
    pub(super) fn new(light: DistantLight, meshes: &[StoredMesh]) -> Self {
        Distant {
            light,
            warp: Warp::around(world_corners(meshes), light.direction),
        }
    }

    /// The rectangle light the warp makes of the light.
    pub(super) fn rectangle(&self) -> RectLight {
        self.warp.light(&self.light)
    }
}

/// Whether `warp` keeps every one of `points` well in front of the plane it sends to infinity:
/// nowhere magnified more than four times (`(x - o)·D + k >= k / 4`).
fn holds(warp: &Warp, points: &[DVec3]) -> bool {
    points
        .iter()
        .all(|p| (*p - warp.origin).dot(warp.direction) + warp.k >= 0.25 * warp.k)
}

impl GpuScene {
    /// The camera the passes see for the application's `camera`: itself under a rectangle
    /// light; under a distant light, the camera of the warped scene ([`FrameCamera::warped`]),
    /// the warp renewed first (and what was built for it dropped) where the meshes, as placed
    /// now, or the eye have left it.
    pub(super) fn frame_camera(&mut self, camera: &FrameCamera) -> FrameCamera {
        let Some(d) = &self.distant else {
            return *camera;
        };
        let mut points = world_corners(&self.meshes);
        points.push(camera.eye);
        if !holds(&d.warp, &points) {
            let renewed = Distant {
                light: d.light,
                warp: Warp::around(points, d.light.direction),
            };
            self.light = renewed.rectangle();
            self.distant = Some(renewed);
            self.light_changed();
        }
        let warp = self.distant.as_ref().expect("a distant light").warp;
        camera.warped(&warp)
    }
}
