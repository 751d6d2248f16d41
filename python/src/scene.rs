//! A scene (from a scene file, or from a camera, lights and meshes), rendered into numpy
//! arrays, and visibility at sensor points.

use std::path::PathBuf;
use std::sync::Mutex;

use glam::{DMat4, DVec3};
use numpy::{IntoPyArray, PyReadonlyArray2};
use penumbra::geom::NamedLight;
use penumbra::{Backend, RenderError, RenderOptions, Renderer, Technique};
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::arrays::sensor_rows;
use crate::errors::{self, value};
use crate::images::to_array;
use crate::objects::{Camera, DistantLight, Mesh, RectLight};
use crate::run::{Progress, off_interpreter};

/// Sensors read from numpy and evaluated per slice: the only copy of the points that is made.
const SLICE: usize = 1 << 16;

/// A scene: a camera, one or more lights and triangle meshes. `Scene.load(path)` reads a scene
/// file (TOML, `docs/scene-format.md`); `Scene(camera, lights, meshes)` builds one from a
/// `Camera`, a light or a list of lights (`RectLight`, `DistantLight`) and a list of meshes,
/// each a `Mesh` or a `(Mesh, matrix)` pair with a 4 x 4 transform (numpy, row-major, columns
/// acting on column vectors).
#[pyclass(module = "penumbra", frozen)]
pub struct Scene {
    inner: penumbra::Scene,
    /// Renderers kept between renders (the ray-casting hierarchy, the GPU's pipelines), one
    /// per render in progress.
    renderers: Mutex<Vec<(Backend, Renderer)>>,
}

impl Scene {
    pub(crate) fn of(inner: penumbra::Scene) -> Scene {
        Scene {
            inner,
            renderers: Mutex::new(Vec::new()),
        }
    }

    /// The library's scene.
    pub(crate) fn inner(&self) -> &penumbra::Scene {
        &self.inner
    }

    /// A kept renderer of `backend`, or a new one.
    pub(crate) fn take(&self, backend: Backend) -> Renderer {
        let mut kept = self.renderers.lock().unwrap_or_else(|e| e.into_inner());
        match kept.iter().position(|(b, _)| *b == backend) {
            Some(i) => kept.swap_remove(i).1,
            None => Renderer::new(backend),
        }
    }

    pub(crate) fn give_back(&self, backend: Backend, renderer: Renderer) {
        let mut kept = self.renderers.lock().unwrap_or_else(|e| e.into_inner());
        kept.push((backend, renderer));
    }

    /// The indices of the lights asked for: `light` by name, else all.
    fn lights(&self, light: Option<&str>) -> PyResult<Vec<usize>> {
        let names = self.inner.light_names();
        match light {
            None => Ok((0..names.len()).collect()),
            Some(n) => names
                .iter()
                .position(|m| *m == n)
                .map(|k| vec![k])
                .ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "light {n:?}: the scene's lights are {}",
                        names
                            .iter()
                            .map(|m| format!("{m:?}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ))
                }),
        }
    }

    /// One array, or a dict from light name to array where the scene names its lights and
    /// no single light was asked for.
    fn one_or_many<'py>(
        &self,
        py: Python<'py>,
        lights: &[usize],
        asked: bool,
        arrays: Vec<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        if asked || self.inner.single_channel() {
            return Ok(arrays.into_iter().next().expect("one light"));
        }
        let names = self.inner.light_names();
        let out = PyDict::new(py);
        for (&k, a) in lights.iter().zip(arrays) {
            out.set_item(names[k], a)?;
        }
        Ok(out.into_any())
    }
}

/// A technique by name, or `ValueError` listing them.
pub(crate) fn technique(name: &str) -> PyResult<Technique> {
    name.parse::<Technique>().map_err(value)
}

/// A back end by name.
pub(crate) fn backend(name: &str) -> PyResult<Backend> {
    match name {
        "auto" => Ok(Backend::Auto),
        "cpu" => Ok(Backend::Cpu),
        "gpu" => Ok(Backend::Gpu),
        _ => Err(PyValueError::new_err(format!(
            "backend {name:?}: one of \"auto\", \"cpu\", \"gpu\""
        ))),
    }
}

/// A 4 x 4 transform from a numpy array or nested lists, rows first.
fn matrix(obj: &Bound<'_, PyAny>) -> PyResult<DMat4> {
    let np = obj.py().import("numpy")?;
    let a: PyReadonlyArray2<f64> = np
        .call_method1("asarray", (obj, "float64"))?
        .extract()
        .map_err(|_| PyValueError::new_err("a mesh's transform must be a 4 x 4 matrix"))?;
    let a = a.as_array();
    if a.shape() != [4, 4] {
        return Err(PyValueError::new_err(format!(
            "a mesh's transform must be a 4 x 4 matrix, not {:?}",
            a.shape()
        )));
    }
    let mut cols = [0.0; 16];
    for c in 0..4 {
        for r in 0..4 {
            cols[c * 4 + r] = a[[r, c]];
        }
    }
    Ok(DMat4::from_cols_array(&cols))
}

#[pymethods]
impl Scene {
    #[new]
    fn new(
        camera: &Camera,
        lights: &Bound<'_, PyAny>,
        meshes: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let list: Vec<Bound<'_, PyAny>> = if lights.is_instance_of::<pyo3::types::PyList>()
            || lights.is_instance_of::<PyTuple>()
        {
            lights.try_iter()?.collect::<PyResult<_>>()?
        } else {
            vec![lights.clone()]
        };
        let mut named = Vec::new();
        for (k, l) in list.iter().enumerate() {
            let (name, light) = if let Ok(r) = l.cast::<RectLight>() {
                r.get().light()
            } else if let Ok(d) = l.cast::<DistantLight>() {
                d.get().light()
            } else {
                return Err(PyValueError::new_err(format!(
                    "lights[{k}] is not a RectLight or a DistantLight"
                )));
            };
            named.push((name, light));
        }
        let mut scene = penumbra::Scene::new(camera.inner);
        if named.len() == 1 && named[0].0.is_none() {
            scene = scene.with_light(named.remove(0).1);
        } else if named.is_empty() {
            return Err(PyValueError::new_err("a scene needs at least one light"));
        } else {
            let lights = named
                .into_iter()
                .enumerate()
                .map(|(k, (name, light))| {
                    NamedLight::new(&name.unwrap_or_else(|| format!("light{k}")), light)
                })
                .collect::<Result<Vec<_>, _>>()
                .map_err(value)?;
            scene = scene.with_lights(lights).map_err(value)?;
        }
        for (k, m) in meshes.try_iter()?.enumerate() {
            let m = m?;
            let (mesh, transform) = if let Ok(mesh) = m.cast::<Mesh>() {
                (mesh.get().clone(), DMat4::IDENTITY)
            } else if let Ok((mesh, t)) = m.extract::<(Mesh, Bound<'_, PyAny>)>() {
                (mesh, matrix(&t)?)
            } else {
                return Err(PyValueError::new_err(format!(
                    "meshes[{k}] is not a Mesh or a (Mesh, 4 x 4 matrix) pair"
                )));
            };
            scene = scene.with_mesh(&mesh.name, &mesh.inner, transform);
        }
        if let Some(problem) = scene.out_of_range() {
            return Err(value(problem));
        }
        Ok(Scene::of(scene))
    }

    /// The scene of the scene file `path` (TOML; `docs/scene-format.md`), its meshes read
    /// relative to it. A missing file raises `FileNotFoundError`; a bad one `ValueError`
    /// naming the file and line.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let loaded = off_interpreter(py, None, None, || penumbra::Scene::load(&path))?;
        Ok(Scene::of(loaded.map_err(|e| errors::scene(&path, e))?))
    }

    /// The same scene seen at `width` x `height` pixels.
    fn with_size(&self, width: u32, height: u32) -> PyResult<Self> {
        let mut s = self.inner.clone();
        s.camera.width = width;
        s.camera.height = height;
        if let Some(problem) = s.out_of_range() {
            return Err(value(problem));
        }
        Ok(Scene::of(s))
    }

    /// The image's width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.camera.width
    }

    /// The image's height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.camera.height
    }

    /// The lights' names, in the scene's order.
    #[getter]
    fn light_names(&self) -> Vec<String> {
        self.inner
            .light_names()
            .into_iter()
            .map(String::from)
            .collect()
    }

    /// The number of triangles.
    #[getter]
    fn triangle_count(&self) -> usize {
        self.inner.triangle_count()
    }

    /// The visibility image by `technique` (`penumbra.techniques()` lists them): a
    /// `(height, width)` float32 array, or a dict from light name to array for a scene of
    /// several (named) lights; `light` renders that light alone. `samples` (a perfect square)
    /// and `jitter` as the command's; `backend` is `"auto"` (the GPU where there is one for the
    /// techniques that can use it), `"cpu"` or `"gpu"`. The same pixels as `penumbra render`.
    /// `threads` gives the render a pool of that many threads of its own (a batch of renders on
    /// as many Python threads, one thread each); by default every render shares one pool of a
    /// thread per core.
    #[pyo3(signature = (technique="wedges-blend", samples=256, backend="auto", jitter=false, light=None, threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        technique: &str,
        samples: usize,
        backend: &str,
        jitter: bool,
        light: Option<&str>,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let t = self::technique(technique)?;
        let b = self::backend(backend)?;
        let options = RenderOptions { samples, jitter };
        options.pattern_for(t).map_err(errors::render)?;
        let lights = self.lights(light)?;
        let mut renderer = self.take(b);
        let rows = u64::from(self.inner.camera.height);
        let progress = Progress::new(technique.to_string(), rows * lights.len() as u64);
        let scene = &self.inner;
        let result = off_interpreter(py, Some(&progress), threads, || {
            let mut images = Vec::new();
            for (n, &k) in lights.iter().enumerate() {
                let base = n as u64 * rows;
                let frame = renderer.render_frame(&scene.lit(k), t, &options, None, &|r| {
                    progress.set(base + r)
                })?;
                images.push(frame.image);
            }
            Ok::<_, RenderError>(images)
        });
        self.give_back(b, renderer);
        let images = result?.map_err(errors::render)?;
        let arrays = images
            .into_iter()
            .map(|i| to_array(py, i).into_any())
            .collect();
        self.one_or_many(py, &lights, light.is_some(), arrays)
    }

    /// The visibility of sensor points: `points` and `normals` `(n, 3)` arrays (float32 or
    /// float64, any strides; `normals` may be one `(3,)` vector for all), giving a `(n,)`
    /// float32 array (a dict from light name to array for a scene of several lights, unless
    /// `light` names one). A sensor sees the light samples in front of its plane that nothing
    /// hides; one within 1e-5 of the scene's extent of a surface stands on it. `technique` is
    /// `"depth-complexity"` (exact for its samples) or `"reference"` (rays); sensor `k` takes
    /// the samples of camera pixel `k`. `threads` as for `render`.
    #[pyo3(signature = (points, normals, light=None, samples=1024, technique="depth-complexity", jitter=false, threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn visibility_at<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        normals: &Bound<'py, PyAny>,
        light: Option<&str>,
        samples: usize,
        technique: &str,
        jitter: bool,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let t = self::technique(technique)?;
        let options = RenderOptions { samples, jitter };
        let (p, n) = sensor_rows(points, normals)?;
        let lights = self.lights(light)?;
        let count = p.len();
        // The results, a float32 per point and light, and a slice of points and normals.
        let needed = (count as u64)
            .saturating_mul(4 * lights.len() as u64)
            .saturating_add(48 * SLICE as u64);
        let available = penumbra::geom::available_memory().unwrap_or(u64::MAX);
        if needed > available {
            return Err(PyMemoryError::new_err(format!(
                "{count} points: their results need {:.1} GB and {:.1} GB of memory are available",
                needed as f64 / 1e9,
                available as f64 / 1e9
            )));
        }
        let (pv, nv) = (p.view(), n.view());
        let mut renderer = self.take(Backend::Cpu);
        let progress = Progress::new("sensors".to_string(), (count * lights.len()) as u64);
        let scene = &self.inner;
        let result = off_interpreter(py, Some(&progress), threads, || {
            let mut outs = Vec::new();
            for (l, &k) in lights.iter().enumerate() {
                let sensors = renderer.sensors(scene, k, t, &options)?;
                let mut out = vec![0.0f32; count];
                let mut at = vec![DVec3::ZERO; SLICE.min(count)];
                let mut normal = at.clone();
                for start in (0..count).step_by(SLICE) {
                    let end = (start + SLICE).min(count);
                    let (a, m) = (&mut at[..end - start], &mut normal[..end - start]);
                    pv.read(start, a);
                    nv.read(start, m);
                    let base = (l * count + start) as u64;
                    sensors.fill(a, m, start as u64, &mut out[start..end], &|d| {
                        progress.set(base + d)
                    })?;
                }
                outs.push(out);
            }
            Ok::<_, RenderError>(outs)
        });
        self.give_back(Backend::Cpu, renderer);
        let outs = result?.map_err(errors::render)?;
        let arrays = outs
            .into_iter()
            .map(|o| o.into_pyarray(py).into_any())
            .collect();
        self.one_or_many(py, &lights, light.is_some(), arrays)
    }

    /// Pickling (Ray's object store, multiprocessing): the scene's state, the same bits on
    /// the other side; its meshes travel as arrays, not as files.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyAny>,))> {
        let state = crate::scene_state::state(py, &self.inner)?;
        let restore = py
            .import("penumbra._penumbra")?
            .getattr("_scene_from_state")?;
        Ok((restore, (state,)))
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}, {} x {} pixels, lights {:?}, {} triangles)",
            self.inner.path.display().to_string(),
            self.inner.camera.width,
            self.inner.camera.height,
            self.inner.light_names(),
            self.inner.triangle_count()
        )
    }
}

/// A scene from the state its `__reduce__` gave, for unpickling.
#[pyfunction]
pub fn _scene_from_state(state: &Bound<'_, PyAny>) -> PyResult<Scene> {
    Ok(Scene::of(crate::scene_state::restore(state)?))
}

/// The techniques' names, as `render` takes them.
#[pyfunction]
pub fn techniques() -> Vec<&'static str> {
    Technique::ALL.iter().map(|t| t.name()).collect()
}
