//! A [`GpuScene`] lit by a distant light: the warp that renders the light as a rectangle
//! ([`Warp`], `docs/scene-format.md`, "Distant lights"), kept from frame to frame while it holds
//! the meshes and the eye, and the camera the passes then see.

use glam::{DMat4, DVec3};
use penumbra_geom::{DistantLight, Light, LitScene, RectLight, Warp};

use super::GpuScene;
use super::meshes::{StoredMesh, world_corners};
use crate::frame_uniforms::FrameCamera;

/// The light of a [`GpuScene`]: a rectangle light, or a distant light with the warp its frames
/// are rendered through and the rectangle that warp makes of it.
pub(super) enum SceneLight {
    /// A rectangle light.
    Rect(RectLight),
    /// A distant light.
    Distant {
        /// The light.
        light: DistantLight,
        /// Its warp, around the meshes and the eye.
        warp: Warp,
        /// The rectangle the warp makes of the light.
        rect: RectLight,
        /// The eye and the meshes' transforms the warp was last found to hold for.
        held: Option<(DVec3, Vec<DMat4>)>,
    },
}

impl SceneLight {
    /// `light`; a distant light with the warp around `meshes` as they are placed now.
    pub(super) fn new(light: Light, meshes: &[StoredMesh]) -> Self {
        match light {
            Light::Rect(l) => SceneLight::Rect(l),
            Light::Distant(l) => SceneLight::distant(l, world_corners(meshes)),
        }
    }

    /// The light of `scene`: under a distant light, with the scene's own warp, which holds its
    /// meshes as they are in the world (placed by the identity) and its eye.
    pub(super) fn of_scene(scene: &LitScene) -> Self {
        match &scene.distant {
            None => SceneLight::Rect(scene.light),
            Some(d) => SceneLight::Distant {
                light: d.light,
                warp: d.warp,
                rect: scene.light,
                held: Some((
                    d.camera.eye,
                    vec![DMat4::IDENTITY; scene.world_meshes().len()],
                )),
            },
        }
    }

    /// The distant light `light` with the warp around `points`.
    fn distant(light: DistantLight, points: Vec<DVec3>) -> Self {
        let warp = Warp::around(points, light.direction);
        SceneLight::Distant {
            light,
            warp,
            rect: warp.light(&light),
            held: None,
        }
    }

    /// The rectangle light the passes render.
    pub(super) fn rect(&self) -> &RectLight {
        match self {
            SceneLight::Rect(l) | SceneLight::Distant { rect: l, .. } => l,
        }
    }

    /// The warp of a distant light.
    pub(super) fn warp(&self) -> Option<&Warp> {
        match self {
            SceneLight::Rect(_) => None,
            SceneLight::Distant { warp, .. } => Some(warp),
        }
    }

    /// The light as it was given.
    pub(super) fn light(&self) -> Light {
        match self {
            SceneLight::Rect(l) => Light::Rect(*l),
            SceneLight::Distant { light, .. } => Light::Distant(*light),
        }
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
    /// now, or the eye have left it. The warp is checked once for each eye and placement of the
    /// meshes.
    pub(super) fn frame_camera(&mut self, camera: &FrameCamera) -> FrameCamera {
        let transforms: Vec<DMat4> = self.meshes.iter().map(|m| m.transform).collect();
        let SceneLight::Distant {
            light, warp, held, ..
        } = &mut self.light
        else {
            return *camera;
        };
        let now = (camera.eye, transforms);
        if held.as_ref() != Some(&now) {
            let mut points = world_corners(&self.meshes);
            points.push(camera.eye);
            if holds(warp, &points) {
                *held = Some(now);
            } else {
                self.light = SceneLight::distant(*light, points);
                if let SceneLight::Distant { held, .. } = &mut self.light {
                    *held = Some(now);
                }
                self.light_changed();
            }
        }
        camera.warped(self.light.warp().expect("a distant light"))
    }
}
