//! The per-frame uniforms shared by every pass, laid out identically in Rust and WGSL
//! (`struct Frame` in each shader). Positions on the GPU are relative to the eye, in `f32`, so
//! that precision does not depend on where the scene sits in the world.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, DVec4, Mat4, Vec3};
use penumbra_geom::Scene;

/// Near plane of the camera's projection, relative to the scene's size.
pub const NEAR_FRACTION: f64 = 1e-3;

/// Uniforms of one frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    /// Eye-relative world position to clip space: reversed-z, infinite far plane.
    pub view_proj: [[f32; 4]; 4],
    /// Light centre minus eye (`w` unused).
    pub light_center: [f32; 4],
    /// Light normal (`w` unused).
    pub light_normal: [f32; 4],
    /// Image width and height in pixels; the number of leading scene vertices that belong to
    /// closed meshes wound outwards (0 but for the shadow-map techniques); one unused lane.
    pub size: [f32; 4],
    /// Light tangent and half the first side.
    pub light_tangent: [f32; 4],
    /// Light bitangent and half the second side.
    pub light_bitangent: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 144);

/// The camera's eye-relative view-projection: right-handed look-at, vertical field of view,
/// reversed depth (1 at the near plane, 0 at infinity) so that `Depth32Float` keeps its
/// precision far away and points at infinity (`w = 0`) land exactly on depth 0.
///
/// With `f = 1 / tan(fov_y / 2)`, `a = width / height` and the view frame's rows `right`,
/// `true_up` and `-forward`, a point `v` (eye-relative, homogeneous) goes to
/// `(f/a · right·v, f · true_up·v, near · v.w, forward·v)`: depth `near / (forward·v)` is 1 on the
/// near plane and falls to 0 at infinity, where `v.w = 0` gives exactly 0.
pub fn view_proj(scene: &Scene, scene_radius: f64) -> Mat4 {
    view_proj_f64(scene, scene_radius).as_mat4()
}

/// [`view_proj`] in `f64`, for the CPU's own projections of the frame.
pub fn view_proj_f64(scene: &Scene, scene_radius: f64) -> DMat4 {
    let c = &scene.camera;
    let aspect = c.width as f64 / c.height as f64;
    let near = (scene_radius * NEAR_FRACTION).max(1e-6);
    let f = 1.0 / (c.fov_y_deg.to_radians() * 0.5).tan();
    let rows = [
        (c.right * (f / aspect)).extend(0.0),
        (c.true_up * f).extend(0.0),
        DVec4::new(0.0, 0.0, 0.0, near),
        c.forward.extend(0.0),
    ];
    DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose()
}

impl FrameUniforms {
    /// Uniforms for `scene`, whose geometry lies within `scene_radius` of the eye.
    pub fn new(scene: &Scene, scene_radius: f64) -> Self {
        let m = view_proj(scene, scene_radius);
        let l = &scene.light;
        let lc = (l.center - scene.camera.eye).as_vec3();
        let n = l.normal.as_vec3();
        let (t, b, h) = (
            l.tangent.as_vec3(),
            l.bitangent.as_vec3(),
            l.half_size().as_vec2(),
        );
        FrameUniforms {
            light_tangent: [t.x, t.y, t.z, h.x],
            light_bitangent: [b.x, b.y, b.z, h.y],
            view_proj: m.to_cols_array_2d(),
            light_center: [lc.x, lc.y, lc.z, 0.0],
            light_normal: [n.x, n.y, n.z, 0.0],
            size: [
                scene.camera.width as f32,
                scene.camera.height as f32,
                0.0,
                0.0,
            ],
        }
    }
}

/// The vertices of `triangles` relative to `eye`, in `f32`.
pub fn eye_relative(eye: DVec3, triangles: &[[DVec3; 3]]) -> Vec<[f32; 3]> {
    triangles
        .iter()
        .flatten()
        .map(|&v| (v - eye).as_vec3().to_array())
        .collect()
}

/// The radius around the eye that holds every eye-relative vertex of `vertices` (at least 1e-3),
/// for [`FrameUniforms::new`].
pub fn scene_radius(vertices: &[[f32; 3]]) -> f64 {
    vertices
        .iter()
        .map(|v| Vec3::from(*v).length() as f64)
        .fold(1e-3, f64::max)
}

/// The bind group of `uniforms` in `layout` (`passes::frame_layout`); it keeps its buffer alive.
pub fn frame_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    uniforms: &FrameUniforms,
) -> wgpu::BindGroup {
    let buffer = crate::passes::buffer(
        device,
        "frame",
        std::slice::from_ref(uniforms),
        wgpu::BufferUsages::UNIFORM,
    );
    crate::passes::bind_group(device, "frame", layout, &[buffer.as_entire_binding()])
}
