//! A scene's state for pickling (Ray's object store, multiprocessing): its path, camera,
//! lights and meshes as plain values and arrays, taken and given back bit for bit.

use glam::{DMat4, DVec2, DVec3};
use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray2};
use penumbra::geom::{NamedLight, SceneMesh};
use penumbra::{Camera, DistantLight, Light, RectLight};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::value;

/// A light's state: its kind, name and frame, the fields as they are.
type LightState = (String, String, [f64; 3], [f64; 3], [f64; 3], [f64; 2]);

/// A scene's state for pickling: its path, camera, lights, meshes (name, transform from its
/// file, world-space positions, triangles) and whether its channels are named. The shadow
/// maps' parameters are not carried: a scene with parameters of its own is refused.
pub fn state<'py>(py: Python<'py>, s: &penumbra::Scene) -> PyResult<Bound<'py, PyAny>> {
    if s.params != penumbra::params::TechniqueParams::default() {
        return Err(PyValueError::new_err(format!(
            "scene {}: its shadow-map parameters ([shadow_map] and the techniques' tables) do not \
             travel with a pickled scene; send its file's path and Scene.load it there",
            s.path.display()
        )));
    }
    let c = &s.camera;
    let camera = (
        c.eye.to_array(),
        c.forward.to_array(),
        c.right.to_array(),
        c.true_up.to_array(),
        c.fov_y_deg,
        c.width,
        c.height,
    );
    let lights: Vec<LightState> = s
        .lights
        .iter()
        .map(|l| match l.light {
            Light::Rect(r) => (
                "rect".to_string(),
                l.name.clone(),
                r.center.to_array(),
                r.normal.to_array(),
                r.tangent.to_array(),
                r.size.to_array(),
            ),
            Light::Distant(d) => (
                "distant".to_string(),
                l.name.clone(),
                d.direction.to_array(),
                d.tangent.to_array(),
                d.bitangent.to_array(),
                d.angular_size_deg.to_array(),
            ),
        })
        .collect();
    let mut meshes = Vec::new();
    for m in s.meshes.iter() {
        let positions: Vec<f64> = m.mesh.positions.iter().flat_map(|p| p.to_array()).collect();
        let triangles: Vec<u32> = m.mesh.triangles.iter().flatten().copied().collect();
        meshes.push((
            m.source.display().to_string(),
            m.transform.to_cols_array(),
            positions
                .into_pyarray(py)
                .reshape([m.mesh.positions.len(), 3])?,
            triangles
                .into_pyarray(py)
                .reshape([m.mesh.triangles.len(), 3])?,
        ));
    }
    let state = (
        s.path.display().to_string(),
        camera,
        lights,
        meshes,
        s.named_channels,
    );
    Ok(state.into_pyobject(py)?.into_any())
}

/// A scene from [`state`]'s state, the same bits.
pub fn restore(state: &Bound<'_, PyAny>) -> PyResult<penumbra::Scene> {
    type CameraState = ([f64; 3], [f64; 3], [f64; 3], [f64; 3], f64, u32, u32);
    type MeshState<'py> = (String, [f64; 16], Bound<'py, PyAny>, Bound<'py, PyAny>);
    type State<'py> = (
        String,
        CameraState,
        Vec<LightState>,
        Vec<MeshState<'py>>,
        bool,
    );
    let (path, camera, lights, meshes, named_channels): State<'_> = state.extract()?;
    let (eye, forward, right, true_up, fov_y_deg, width, height) = camera;
    let mut scene = penumbra::Scene::new(Camera {
        eye: DVec3::from_array(eye),
        forward: DVec3::from_array(forward),
        right: DVec3::from_array(right),
        true_up: DVec3::from_array(true_up),
        fov_y_deg,
        width,
        height,
    });
    scene.path = path.into();
    scene.named_channels = named_channels;
    for (kind, name, a, b, c, size) in lights {
        let (a, b, c) = (
            DVec3::from_array(a),
            DVec3::from_array(b),
            DVec3::from_array(c),
        );
        let light = match kind.as_str() {
            "rect" => Light::Rect(RectLight {
                center: a,
                normal: b,
                tangent: c,
                bitangent: b.cross(c),
                size: DVec2::from_array(size),
            }),
            _ => Light::Distant(DistantLight {
                direction: a,
                tangent: b,
                bitangent: c,
                angular_size_deg: DVec2::from_array(size),
            }),
        };
        scene.lights.push(NamedLight { name, light });
    }
    let mut built = Vec::with_capacity(meshes.len());
    for (source, transform, positions, triangles) in meshes {
        let p: PyReadonlyArray2<'_, f64> = positions.extract()?;
        let t: PyReadonlyArray2<'_, u32> = triangles.extract()?;
        let positions: Vec<DVec3> = p
            .as_array()
            .rows()
            .into_iter()
            .map(|r| DVec3::new(r[0], r[1], r[2]))
            .collect();
        let triangles: Vec<[u32; 3]> = t
            .as_array()
            .rows()
            .into_iter()
            .map(|r| [r[0], r[1], r[2]])
            .collect();
        let mesh =
            penumbra::TriangleMesh::from_raw(&source, &positions, &triangles).map_err(value)?;
        built.push(SceneMesh {
            source: source.into(),
            transform: DMat4::from_cols_array(&transform),
            mesh,
        });
    }
    scene.meshes = std::sync::Arc::new(built);
    Ok(scene)
}
