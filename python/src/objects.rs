//! The things a scene is made of, built in Python: a camera, lights (each with a name) and
//! triangle meshes from numpy arrays. Each constructor checks its values as the library's
//! does and raises `ValueError` naming the field.

use glam::{DVec2, DVec3};
use penumbra::geom::Light;
use pyo3::prelude::*;

use crate::arrays::{points, vec3};
use crate::errors::value;

/// A pinhole camera looking from `eye` at `target`, `up` the image's up, `fov_y_deg` the
/// vertical field of view in degrees, and an image of `width` x `height` pixels.
#[pyclass(module = "penumbra", frozen, from_py_object)]
#[derive(Clone)]
pub struct Camera {
    pub inner: penumbra::Camera,
}

#[pymethods]
impl Camera {
    #[new]
    #[pyo3(signature = (eye, target, up=None, fov_y_deg=45.0, width=320, height=240))]
    fn new(
        eye: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        up: Option<&Bound<'_, PyAny>>,
        fov_y_deg: f64,
        width: u32,
        height: u32,
    ) -> PyResult<Self> {
        let up = match up {
            Some(u) => vec3("up", u)?,
            None => DVec3::Y,
        };
        let inner = penumbra::Camera::look_at(
            vec3("eye", eye)?,
            vec3("target", target)?,
            up,
            fov_y_deg,
            width,
            height,
        )
        .map_err(value)?;
        Ok(Camera { inner })
    }

    /// The eye's position.
    #[getter]
    fn eye(&self) -> (f64, f64, f64) {
        self.inner.eye.into()
    }

    /// The image's width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.width
    }

    /// The image's height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.height
    }

    fn __repr__(&self) -> String {
        let c = &self.inner;
        format!(
            "Camera(eye={:?}, fov_y_deg={}, width={}, height={})",
            <(f64, f64, f64)>::from(c.eye),
            c.fov_y_deg,
            c.width,
            c.height
        )
    }
}

/// A rectangular area light: its `center`, the `normal` it emits along, a `tangent` (the
/// direction of its first side) and its `size` (the two sides' lengths), named `name`.
#[pyclass(module = "penumbra", frozen, from_py_object)]
#[derive(Clone)]
pub struct RectLight {
    pub inner: penumbra::RectLight,
    pub name: Option<String>,
}

#[pymethods]
impl RectLight {
    #[new]
    #[pyo3(signature = (center, normal, tangent, size, name=None))]
    fn new(
        center: &Bound<'_, PyAny>,
        normal: &Bound<'_, PyAny>,
        tangent: &Bound<'_, PyAny>,
        size: (f64, f64),
        name: Option<String>,
    ) -> PyResult<Self> {
        let inner = penumbra::RectLight::new(
            vec3("center", center)?,
            vec3("normal", normal)?,
            vec3("tangent", tangent)?,
            DVec2::new(size.0, size.1),
        )
        .map_err(value)?;
        Ok(RectLight { inner, name })
    }

    /// A light at `center` facing `target`, of `size`; its tangent is chosen by the library's
    /// documented rule (`RectLight::aimed`).
    #[staticmethod]
    #[pyo3(signature = (center, target, size, name=None))]
    fn aimed(
        center: &Bound<'_, PyAny>,
        target: &Bound<'_, PyAny>,
        size: (f64, f64),
        name: Option<String>,
    ) -> PyResult<Self> {
        let inner = penumbra::RectLight::aimed(
            vec3("center", center)?,
            vec3("target", target)?,
            DVec2::new(size.0, size.1),
        )
        .map_err(value)?;
        Ok(RectLight { inner, name })
    }

    /// The light's centre.
    #[getter]
    fn center(&self) -> (f64, f64, f64) {
        self.inner.center.into()
    }

    /// The unit normal it emits along.
    #[getter]
    fn normal(&self) -> (f64, f64, f64) {
        self.inner.normal.into()
    }

    /// Its name, or `None`.
    #[getter]
    fn name(&self) -> Option<String> {
        self.name.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "RectLight(center={:?}, normal={:?}, size={:?}, name={:?})",
            self.center(),
            self.normal(),
            <(f64, f64)>::from(self.inner.size),
            self.name
        )
    }
}

/// A distant light (the sun): the rectangle of directions around `direction` (the unit vector
/// towards the light), its sides along `tangent` and the direction normal to both, spanning
/// `angular_size` degrees, named `name`.
#[pyclass(module = "penumbra", frozen, from_py_object)]
#[derive(Clone)]
pub struct DistantLight {
    pub inner: penumbra::DistantLight,
    pub name: Option<String>,
}

#[pymethods]
impl DistantLight {
    #[new]
    #[pyo3(signature = (direction, tangent, angular_size=(0.53, 0.53), name=None))]
    fn new(
        direction: &Bound<'_, PyAny>,
        tangent: &Bound<'_, PyAny>,
        angular_size: (f64, f64),
        name: Option<String>,
    ) -> PyResult<Self> {
        let inner = penumbra::DistantLight::new(
            vec3("direction", direction)?,
            vec3("tangent", tangent)?,
            DVec2::new(angular_size.0, angular_size.1),
        )
        .map_err(value)?;
        Ok(DistantLight { inner, name })
    }

    /// The sun at `azimuth_deg` (clockwise from north, north = -z, east = +x, up = +y) and
    /// `elevation_deg` above the horizon, a square of `angular_size_deg` degrees (the sun is
    /// 0.53).
    #[staticmethod]
    #[pyo3(signature = (azimuth_deg, elevation_deg, angular_size_deg=0.53, name=None))]
    fn sun(
        azimuth_deg: f64,
        elevation_deg: f64,
        angular_size_deg: f64,
        name: Option<String>,
    ) -> PyResult<Self> {
        let inner = penumbra::DistantLight::sun(azimuth_deg, elevation_deg, angular_size_deg)
            .map_err(value)?;
        Ok(DistantLight { inner, name })
    }

    /// The unit vector towards the light.
    #[getter]
    fn direction(&self) -> (f64, f64, f64) {
        self.inner.direction.into()
    }

    /// Its name, or `None`.
    #[getter]
    fn name(&self) -> Option<String> {
        self.name.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "DistantLight(direction={:?}, name={:?})",
            self.direction(),
            self.name
        )
    }
}

impl RectLight {
    pub fn light(&self) -> (Option<String>, Light) {
        (self.name.clone(), self.inner.into())
    }
}

impl DistantLight {
    pub fn light(&self) -> (Option<String>, Light) {
        (self.name.clone(), self.inner.into())
    }
}

/// A triangle mesh: `vertices` an `(n, 3)` array of floats, `faces` an `(m, 3)` array of
/// vertex indices, any winding; open, folded and non-manifold meshes are welcome.
#[pyclass(module = "penumbra", frozen, from_py_object)]
#[derive(Clone)]
pub struct Mesh {
    pub inner: penumbra::TriangleMesh,
    pub name: String,
}

#[pymethods]
impl Mesh {
    #[new]
    #[pyo3(signature = (vertices, faces, name="mesh"))]
    fn new(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        let v = points("vertices", vertices)?;
        let f = crate::arrays::faces(faces)?;
        let inner = penumbra::TriangleMesh::from_raw(name, &v, &f).map_err(value)?;
        Ok(Mesh {
            inner,
            name: name.to_string(),
        })
    }

    /// The mesh of a `trimesh.Trimesh` (its `vertices` and `faces`), named `name` or after
    /// the mesh's own name.
    #[staticmethod]
    #[pyo3(signature = (mesh, name=None))]
    fn from_trimesh(mesh: &Bound<'_, PyAny>, name: Option<String>) -> PyResult<Self> {
        let name = match name {
            Some(n) => n,
            None => mesh
                .getattr("metadata")
                .and_then(|m| m.call_method1("get", ("name",)))
                .and_then(|n| n.extract::<String>())
                .unwrap_or_else(|_| "mesh".to_string()),
        };
        Mesh::new(&mesh.getattr("vertices")?, &mesh.getattr("faces")?, &name)
    }

    /// Its vertices, `(n, 3)` float64.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        let rows: Vec<Vec<f64>> = self
            .inner
            .positions
            .iter()
            .map(|p| vec![p.x, p.y, p.z])
            .collect();
        numpy::PyArray2::from_vec2(py, &rows).expect("rows of three")
    }

    /// The number of triangles.
    #[getter]
    fn triangle_count(&self) -> usize {
        self.inner.triangles.len()
    }

    /// Its name.
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh(name={:?}, vertices={}, triangles={})",
            self.name,
            self.inner.positions.len(),
            self.inner.triangles.len()
        )
    }
}
