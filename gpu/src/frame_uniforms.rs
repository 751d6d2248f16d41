//! The per-frame uniforms shared by every pass, laid out identically in Rust and WGSL
//! (`struct Frame` in `shaders/common.wgsl`), the camera they are made from ([`FrameCamera`]) and
//! the meshes' model matrices. Positions on the GPU are relative to the eye, in `f32`, so that
//! precision does not depend on where the scene sits in the world.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, DVec4, Vec3};
use penumbra_geom::{Camera, RectLight, Warp};

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
    /// Under a distant light's warp ([`penumbra_geom::Warp`]): its direction `D` and `k`; all
    /// zero otherwise, and the passes place vertices in the world.
    pub warp_direction: [f32; 4],
    /// The warp's origin `o` minus the world's eye (`w` unused).
    pub warp_origin: [f32; 4],
    /// The warp's origin `o` minus the warped eye `H(eye)` (`w` unused).
    pub warp_image: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 192);

/// A mesh's model matrix as the shaders read it (`models` in `common.wgsl`): its stored vertices
/// to eye-relative world, column-major. The shaders use its rows x, y and z; row w, unused by an
/// affine map, carries in column 0 the mesh's outward sign for the depth pre-pass's normals
/// (turned for a room seen from inside) and in column 1 the sign the shadows' build takes (the
/// winding in the world, as the CPU's volumes take it).
pub type ModelMatrix = [[f32; 4]; 4];

/// The matrix that places a mesh's vertices, stored relative to `origin` in its own space,
/// moved into the world by `transform`, relative to `eye`: `T(-eye) · transform · T(origin)`,
/// composed in `f64` so that only the result is rounded; with `outward` (+1 or -1 for a closed
/// mesh wound outwards or inwards as the normals take it, 0 for an open one) in column 0's w and
/// `winding` (the same for the shadows' build) in column 1's.
pub fn model_matrix(
    eye: DVec3,
    transform: &DMat4,
    origin: DVec3,
    (outward, winding): (f64, f64),
) -> ModelMatrix {
    let mut m = (DMat4::from_translation(-eye) * *transform * DMat4::from_translation(origin))
        .as_mat4()
        .to_cols_array_2d();
    m[0][3] = outward as f32;
    m[1][3] = winding as f32;
    m
}

/// Why the camera of a frame was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// A view matrix that is not an invertible affine map.
    #[error("the view matrix is not an invertible affine map: {0:?}")]
    View(Box<DMat4>),
    /// A projection other than reversed depth with an infinite far plane.
    #[error(
        "the projection must have reversed depth and an infinite far plane (third row (0, 0, 0, near > 0), fourth row ending in 0), as glam's dcamera::rh::proj::directx::perspective_infinite_reverse makes: {0:?}"
    )]
    Projection(Box<DMat4>),
    /// An empty image.
    #[error("the image is {0} x {1} pixels: both must be at least 1")]
    Size(u32, u32),
}

/// The camera of one frame as the passes take it: the eye and the eye-relative view-projection,
/// with reversed depth (1 at the near plane, 0 at infinity) so that `Depth32Float` keeps its
/// precision far away and points at infinity (`w = 0`, the shadow volumes' far ends) land
/// exactly on depth 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCamera {
    /// The eye, world space.
    pub eye: DVec3,
    /// Eye-relative world (`world - eye`) to clip space.
    pub view_proj: DMat4,
    /// Image width and height in pixels.
    pub size: (u32, u32),
}

impl FrameCamera {
    /// The camera of an application's `view` matrix (world to camera space, affine) and
    /// `projection` (reversed depth, infinite far plane: glam's
    /// `dcamera::rh::proj::directx::perspective_infinite_reverse` or the same matrix made
    /// otherwise), for an image of `size` pixels.
    ///
    /// ```
    /// use penumbra::glam::DVec3;
    /// use penumbra::glam::dcamera::rh::{proj::directx, view};
    /// use penumbra::gpu::FrameCamera;
    ///
    /// let view = view::look_at_mat4(DVec3::new(0.0, 2.0, 5.0), DVec3::ZERO, DVec3::Y);
    /// let projection = directx::perspective_infinite_reverse(0.8, 4.0 / 3.0, 0.01);
    /// let camera = FrameCamera::from_matrices(&view, &projection, (320, 240))?;
    /// assert!((camera.eye - DVec3::new(0.0, 2.0, 5.0)).length() < 1e-12);
    /// // A standard projection (finite far plane, depth 0 at the near plane) is refused.
    /// let standard = directx::perspective(0.8, 4.0 / 3.0, 0.01, 100.0);
    /// assert!(FrameCamera::from_matrices(&view, &standard, (320, 240)).is_err());
    /// # Ok::<(), penumbra::gpu::CameraError>(())
    /// ```
    pub fn from_matrices(
        view: &DMat4,
        projection: &DMat4,
        size: (u32, u32),
    ) -> Result<Self, CameraError> {
        if size.0 == 0 || size.1 == 0 {
            return Err(CameraError::Size(size.0, size.1));
        }
        let affine = view.row(3) == DVec4::W && view.is_finite();
        let det = view.determinant();
        if !(affine && det.is_normal()) {
            return Err(CameraError::View(Box::new(*view)));
        }
        let z = projection.row(2);
        if !(projection.is_finite()
            && z.truncate() == DVec3::ZERO
            && z.w > 0.0
            && projection.row(3).w == 0.0)
        {
            return Err(CameraError::Projection(Box::new(*projection)));
        }
        let eye = view.inverse().transform_point3(DVec3::ZERO);
        // view(x) = A x + t = A (x - eye): the eye-relative view is A alone.
        let mut linear = *view;
        linear.w_axis = DVec4::W;
        Ok(FrameCamera {
            eye,
            view_proj: *projection * linear,
            size,
        })
    }

    /// The camera of a scene: right-handed look-at, the camera's vertical field of view, near
    /// plane at `near`.
    ///
    /// With `f = 1 / tan(fov_y / 2)`, `a = width / height` and the view frame's rows `right`,
    /// `true_up` and `-forward`, a point `v` (eye-relative, homogeneous) goes to
    /// `(f/a · right·v, f · true_up·v, near · v.w, forward·v)`: depth `near / (forward·v)` is 1
    /// on the near plane and falls to 0 at infinity, where `v.w = 0` gives exactly 0.
    ///
    /// The camera of a scene under a distant light (its warp, [`penumbra_geom::Warp`]) has a
    /// frame that is not orthonormal: the rows are then those of the frame's inverse, so that
    /// `v = x right + y true_up + z forward` still goes to `(f/a · x, f · y, near · v.w, z)`.
    pub fn from_camera(c: &Camera, near: f64) -> Self {
        let aspect = c.width as f64 / c.height as f64;
        let f = 1.0 / (c.fov_y_deg.to_radians() * 0.5).tan();
        let [right, up, forward] = view_rows(c);
        let rows = [
            (right * (f / aspect)).extend(0.0),
            (up * f).extend(0.0),
            DVec4::new(0.0, 0.0, 0.0, near),
            forward.extend(0.0),
        ];
        FrameCamera {
            eye: c.eye,
            view_proj: DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose(),
            size: (c.width, c.height),
        }
    }

    /// The camera that sees a scene warped by `warp` (a distant light's,
    /// [`penumbra_geom::Warp`]) as this one sees the world: its eye the warped eye, and its
    /// matrix this one's composed with the warp's inverse, `VP · T(-eye) · H⁻¹ · T(H(eye))`, so
    /// that a warped point lands on the pixel and at the depth of the world point it is the image
    /// of (the homogeneous factor the warp's inverse brings is positive and divides out).
    pub fn warped(&self, warp: &Warp) -> FrameCamera {
        let eye = warp.point(self.eye);
        FrameCamera {
            eye,
            view_proj: self.view_proj
                * DMat4::from_translation(-self.eye)
                * warp.inverse_matrix()
                * DMat4::from_translation(eye),
            size: self.size,
        }
    }

    /// The camera of a one-shot render of `scene` ([`crate::GpuRenderer::render`]): its camera
    /// in the world (a [`crate::GpuScene`] under a distant light warps it, [`FrameCamera::warped`]),
    /// with the near plane a thousandth of the scene's extent around the eye, or half the
    /// distance to the nearest triangle where that is closer.
    pub fn of_scene(scene: &penumbra_geom::LitScene) -> Self {
        let camera = scene.world_camera();
        Self::for_scene(camera, &eye_relative(camera.eye, &scene.world_triangles()))
    }

    /// [`FrameCamera::from_camera`] with the near plane the one-shot renderers use for a scene
    /// whose eye-relative vertices ([`eye_relative`]) are `vertices`: a thousandth of the
    /// distance from the eye that holds the scene ([`scene_radius`]), or half the distance to
    /// the nearest triangle ([`nearest_distance`]) where that is closer (an eye just above a
    /// ground it looks along), so that no surface in view is clipped; the reversed depth keeps
    /// its relative precision however small the near plane.
    pub(crate) fn for_scene(c: &Camera, vertices: &[[f32; 3]]) -> Self {
        let radius = scene_radius(vertices);
        let near = (radius * NEAR_FRACTION)
            .min(0.5 * nearest_distance(vertices))
            .max(radius * 1e-9);
        Self::from_camera(c, near * skew_factor(c))
    }
}

impl FrameUniforms {
    /// Uniforms for `camera` and `light`.
    pub fn new(camera: &FrameCamera, light: &RectLight) -> Self {
        let l = light;
        let lc = (l.center - camera.eye).as_vec3();
        let n = l.normal.as_vec3();
        let (t, b, h) = (
            l.tangent.as_vec3(),
            l.bitangent.as_vec3(),
            l.half_size().as_vec2(),
        );
        FrameUniforms {
            light_tangent: [t.x, t.y, t.z, h.x],
            light_bitangent: [b.x, b.y, b.z, h.y],
            view_proj: camera.view_proj.as_mat4().to_cols_array_2d(),
            light_center: [lc.x, lc.y, lc.z, 0.0],
            light_normal: [n.x, n.y, n.z, 0.0],
            size: [camera.size.0 as f32, camera.size.1 as f32, 0.0, 0.0],
            warp_direction: [0.0; 4],
            warp_origin: [0.0; 4],
            warp_image: [0.0; 4],
        }
    }

    /// The uniforms with the vertices of the meshes, placed relative to `world_eye` by their
    /// model matrices, carried by `warp` to positions relative to the warped eye, the eye of
    /// `camera` ([`FrameCamera::warped`]).
    pub fn with_warp(mut self, warp: &Warp, world_eye: DVec3, camera: &FrameCamera) -> Self {
        let d = warp.direction.as_vec3();
        let o = (warp.origin - world_eye).as_vec3();
        let i = (warp.origin - camera.eye).as_vec3();
        self.warp_direction = [d.x, d.y, d.z, warp.k as f32];
        self.warp_origin = [o.x, o.y, o.z, 0.0];
        self.warp_image = [i.x, i.y, i.z, 0.0];
        self
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

/// Whether the camera's frame is orthonormal (within rounding), as a look-at camera's is.
fn is_orthonormal(c: &Camera) -> bool {
    [c.right, c.true_up, c.forward]
        .iter()
        .all(|v| (v.length() - 1.0).abs() < 1e-12)
        && c.right.dot(c.true_up).abs() < 1e-12
        && c.right.dot(c.forward).abs() < 1e-12
        && c.true_up.dot(c.forward).abs() < 1e-12
}

/// The rows that take an eye-relative point to its coordinates along the camera's frame
/// `(right, true_up, forward)`: the frame itself where it is orthonormal (a look-at camera),
/// else the rows of its inverse (the warped camera of a distant light).
fn view_rows(c: &Camera) -> [DVec3; 3] {
    let frame = [c.right, c.true_up, c.forward];
    if is_orthonormal(c) {
        return frame;
    }
    let inverse = glam::DMat3::from_cols(c.right, c.true_up, c.forward).inverse();
    [inverse.row(0), inverse.row(1), inverse.row(2)]
}

/// How much nearer than for an orthonormal frame a point at a given distance can lie along
/// the camera's `forward` coordinate: 1 for a look-at camera; for a warped one, the ratio of
/// the longest ray direction `forward + x right + y true_up` in view to an orthonormal frame's.
fn skew_factor(c: &Camera) -> f64 {
    if is_orthonormal(c) {
        return 1.0;
    }
    let ty = (c.fov_y_deg.to_radians() * 0.5).tan();
    let tx = ty * c.width as f64 / c.height as f64;
    let longest = c.forward.length() + tx * c.right.length() + ty * c.true_up.length();
    ((1.0 + tx + ty) / longest).min(1.0)
}

/// The radius around the eye that holds every eye-relative vertex of `vertices` (at least 1e-3),
/// for [`FrameUniforms::new`].
pub fn scene_radius(vertices: &[[f32; 3]]) -> f64 {
    vertices
        .iter()
        .map(|v| Vec3::from(*v).length() as f64)
        .fold(1e-3, f64::max)
}

/// The distance from the origin (the eye) to the nearest of the triangles whose corners are
/// `vertices`, three by three, in `f64`.
pub fn nearest_distance(vertices: &[[f32; 3]]) -> f64 {
    vertices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(t[k]).as_dvec3());
            point_triangle_distance(DVec3::ZERO, a, b, c)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The distance from `p` to the triangle `abc` (Ericson, "Real-Time Collision Detection",
/// 2005, 5.1.5: the closest point by its Voronoi region).
fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v - p).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w - p).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w - p).length();
    }
    let denom = va + vb + vc;
    if denom == 0.0 || !denom.is_finite() {
        // A degenerate triangle: the nearest of its corners.
        return ap.length().min(bp.length()).min(cp.length());
    }
    let (v, w) = (vb / denom, vc / denom);
    (a + ab * v + ac * w - p).length()
}

/// The bind group of `uniforms` and of the meshes' matrices `models` (a storage buffer of
/// [`ModelMatrix`]) in `layout` (`passes::frame_layout`); it keeps its buffers alive.
pub fn frame_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
    models: &wgpu::Buffer,
) -> wgpu::BindGroup {
    crate::passes::bind_group(
        device,
        "frame",
        layout,
        &[uniforms.as_entire_binding(), models.as_entire_binding()],
    )
}

/// [`frame_group`] of fresh buffers holding `uniforms` and the identity as the one model
/// matrix: for passes whose vertices are already eye-relative.
pub fn single_frame_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    uniforms: &FrameUniforms,
) -> wgpu::BindGroup {
    let uniforms = crate::passes::buffer(
        device,
        "frame",
        std::slice::from_ref(uniforms),
        wgpu::BufferUsages::UNIFORM,
    );
    let models = crate::passes::buffer(
        device,
        "models",
        &[glam::Mat4::IDENTITY.to_cols_array_2d()],
        wgpu::BufferUsages::STORAGE,
    );
    frame_group(device, layout, &uniforms, &models)
}
