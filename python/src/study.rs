//! Sun studies and scenes sent to other processes: `_sun_hours` sums the sun's visibility over
//! a run of steps (`penumbra.study` splits a study into runs, here or on Ray), and a scene's
//! state, which pickling takes and gives back bit for bit.

use glam::{DMat4, DVec2, DVec3};
use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use penumbra::geom::{NamedLight, SceneMesh};
use penumbra::{
    Camera, DistantLight, Light, RectLight, RenderOptions, Renderer, SunStep, SunStudy, SunTarget,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{points, vec3};
use crate::errors::{self, value};
use crate::run::{Progress, off_interpreter};
use crate::scene::{Scene, backend, technique};

/// The hours of direct sun over one run of steps (`azimuth_deg`, `elevation_deg`, `hours`, as
/// many of each): float64, `(height, width)` for the camera's pixels, or `(n,)` for `points`
/// with `normals` (`(n, 3)`, or one normal for all). A step whose sun is wholly below the
/// horizon costs nothing. Added in the steps' order: the same steps give the same bits.
#[pyfunction]
#[pyo3(signature = (scene, azimuth_deg, elevation_deg, hours, angular_size_deg=0.53, technique="depth-complexity", samples=64, backend="cpu", points=None, normals=None, north=None, up=None, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn _sun_hours<'py>(
    py: Python<'py>,
    scene: &Scene,
    azimuth_deg: PyReadonlyArray1<'py, f64>,
    elevation_deg: PyReadonlyArray1<'py, f64>,
    hours: PyReadonlyArray1<'py, f64>,
    angular_size_deg: f64,
    technique: &str,
    samples: usize,
    backend: &str,
    points: Option<&Bound<'py, PyAny>>,
    normals: Option<&Bound<'py, PyAny>>,
    north: Option<&Bound<'py, PyAny>>,
    up: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    let (az, el, w) = (
        azimuth_deg.as_slice()?,
        elevation_deg.as_slice()?,
        hours.as_slice()?,
    );
    if az.len() != el.len() || az.len() != w.len() {
        return Err(PyValueError::new_err(format!(
            "{} azimuths, {} elevations and {} hours: give one of each per step",
            az.len(),
            el.len(),
            w.len()
        )));
    }
    let steps: Vec<SunStep> = (0..az.len())
        .map(|i| SunStep {
            azimuth_deg: az[i],
            elevation_deg: el[i],
            hours: w[i],
        })
        .collect();
    let defaults = SunStudy::default();
    let study = SunStudy {
        north: north
            .map(|n| vec3("north", n))
            .transpose()?
            .unwrap_or(defaults.north),
        up: up
            .map(|u| vec3("up", u))
            .transpose()?
            .unwrap_or(defaults.up),
        angular_size_deg,
        technique: self::technique(technique)?,
        options: RenderOptions {
            samples,
            jitter: false,
        },
    };
    let sensors = match (points, normals) {
        (None, None) => None,
        (Some(p), Some(n)) => {
            let p = self::points("points", p)?;
            let mut n = self::points(
                "normals",
                &n.py().import("numpy")?.call_method1("atleast_2d", (n,))?,
            )?;
            if n.len() == 1 && p.len() != 1 {
                n = vec![n[0]; p.len()];
            }
            Some((p, n))
        }
        _ => {
            return Err(PyValueError::new_err(
                "give points and normals together, or neither for the camera's pixels",
            ));
        }
    };
    let b = self::backend(backend)?;
    let inner = scene.inner();
    let progress = Progress::new("sun steps".to_string(), steps.len() as u64);
    let result = off_interpreter(py, Some(&progress), threads, || {
        let mut renderer = Renderer::new(b);
        let target = match &sensors {
            None => SunTarget::Pixels,
            Some((p, n)) => SunTarget::Points {
                points: p,
                normals: n,
            },
        };
        renderer.sun_hours(inner, &study, &steps, target, &|d| progress.set(d as u64))
    })?;
    let sum = result.map_err(errors::render)?;
    let array = sum.into_pyarray(py);
    if sensors.is_some() {
        return Ok(array.into_any());
    }
    let (h, w) = (inner.camera.height as usize, inner.camera.width as usize);
    Ok(array.reshape([h, w])?.into_any())
}

/// A light's state: its kind, name and frame, the fields as they are.
type LightState = (String, String, [f64; 3], [f64; 3], [f64; 3], [f64; 2]);

/// A scene's state for pickling: its path, camera, lights, meshes (name, transform from its
/// file, world-space positions, triangles) and whether its channels are named. The shadow maps' parameters are
/// not carried: a scene with parameters of its own is refused.
#[pyfunction]
pub fn _scene_state<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyAny>> {
    let s = scene.inner();
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

/// A scene from [`_scene_state`]'s state, the same bits.
#[pyfunction]
pub fn _scene_from_state(state: &Bound<'_, PyAny>) -> PyResult<Scene> {
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
    Ok(Scene::of(scene))
}
