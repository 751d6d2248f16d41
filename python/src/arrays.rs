//! numpy arrays in and out: vectors, mesh arrays and sensor points, checked for shape and
//! values with messages that name the argument.

use glam::DVec3;
use numpy::ndarray::ArrayView2;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A 3-vector from any sequence of three numbers.
pub fn vec3(what: &str, v: &Bound<'_, PyAny>) -> PyResult<DVec3> {
    let xs: Vec<f64> = v
        .extract()
        .map_err(|_| PyValueError::new_err(format!("{what} must be three numbers")))?;
    match xs[..] {
        [x, y, z] => Ok(DVec3::new(x, y, z)),
        _ => Err(PyValueError::new_err(format!(
            "{what} must be three numbers, not {}",
            xs.len()
        ))),
    }
}

/// `numpy.asarray(obj, dtype)`.
fn asarray<'py>(obj: &Bound<'py, PyAny>, dtype: Option<&str>) -> PyResult<Bound<'py, PyAny>> {
    let np = obj.py().import("numpy")?;
    match dtype {
        Some(d) => np.call_method1("asarray", (obj, d)),
        None => np.call_method1("asarray", (obj,)),
    }
}

/// The shape of a numpy array, or a `ValueError` unless it is `(n, 3)`.
fn rows_of_three(what: &str, shape: &[usize]) -> PyResult<usize> {
    match shape {
        [n, 3] => Ok(*n),
        _ => Err(PyValueError::new_err(format!(
            "{what} must have the shape (n, 3), not {shape:?}"
        ))),
    }
}

/// An `(n, 3)` array of floats (anything numpy converts to `float64`) as points, read as
/// [`Rows`].
pub fn points(what: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<DVec3>> {
    let rows = Rows::new(what, &asarray(obj, Some("float64"))?, None)?;
    let mut out = vec![DVec3::ZERO; rows.len()];
    rows.view().read(0, &mut out);
    Ok(out)
}

/// An `(m, 3)` array of integers as triangles' vertex indices.
pub fn faces(obj: &Bound<'_, PyAny>) -> PyResult<Vec<[u32; 3]>> {
    let a = asarray(obj, None)?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "i" | "u") {
        return Err(PyValueError::new_err(format!(
            "faces must be integers, not {}",
            a.getattr("dtype")?.str()?
        )));
    }
    let a: PyReadonlyArray2<i64> = asarray(&a, Some("int64"))?.extract().map_err(|_| {
        PyValueError::new_err(format!(
            "faces must have the shape (m, 3), not {}",
            shape_of(obj)
        ))
    })?;
    rows_of_three("faces", a.shape())?;
    a.as_array()
        .rows()
        .into_iter()
        .enumerate()
        .map(|(k, r)| {
            let mut t = [0u32; 3];
            for (i, &v) in r.iter().enumerate() {
                t[i] = u32::try_from(v).map_err(|_| {
                    PyValueError::new_err(format!("faces[{k}] holds the index {v}"))
                })?;
            }
            Ok(t)
        })
        .collect()
}

/// `obj`'s shape as numpy gives it, for messages.
fn shape_of(obj: &Bound<'_, PyAny>) -> String {
    asarray(obj, None)
        .and_then(|a| a.getattr("shape"))
        .and_then(|s| s.str().map(|s| s.to_string()))
        .unwrap_or_else(|_| "not an array".into())
}

/// Sensor points or normals as numpy holds them: `float64` or `float32`, any strides; read
/// in slices so that no copy of the whole is made.
pub enum Rows<'py> {
    /// `float64` rows.
    F64(PyReadonlyArray2<'py, f64>),
    /// `float32` rows.
    F32(PyReadonlyArray2<'py, f32>),
}

/// Sensor points and their normals as [`Rows`]: `points` `(n, 3)`, `normals` `(n, 3)` or one
/// `(3,)` normal for all, refused unless as many.
pub fn sensor_rows<'py>(
    points: &Bound<'py, PyAny>,
    normals: &Bound<'py, PyAny>,
) -> PyResult<(Rows<'py>, Rows<'py>)> {
    let p = Rows::new("points", points, None)?;
    let n = Rows::new("normals", normals, Some(p.len()))?;
    if n.len() != p.len() {
        return Err(PyValueError::new_err(format!(
            "{} points and {} normals: give one normal per point, or one for all",
            p.len(),
            n.len()
        )));
    }
    Ok((p, n))
}

/// A view of [`Rows`] that another thread can read.
#[derive(Clone, Copy)]
pub enum RowsView<'a> {
    /// `float64` rows.
    F64(ArrayView2<'a, f64>),
    /// `float32` rows.
    F32(ArrayView2<'a, f32>),
}

impl<'py> Rows<'py> {
    /// `obj` as `(n, 3)` rows (a `(3,)` vector repeated `n` times where `repeat` gives `n`),
    /// kept in its own precision where that is `float32` or `float64`.
    pub fn new(what: &str, obj: &Bound<'py, PyAny>, repeat: Option<usize>) -> PyResult<Self> {
        let mut a = asarray(obj, None)?;
        let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
        if !matches!(kind.as_str(), "f" | "i" | "u") {
            return Err(PyValueError::new_err(format!(
                "{what} must be numbers, not {}",
                a.getattr("dtype")?.str()?
            )));
        }
        let size: usize = a.getattr("dtype")?.getattr("itemsize")?.extract()?;
        if kind != "f" || !matches!(size, 4 | 8) {
            a = asarray(&a, Some("float64"))?;
        }
        let ndim: usize = a.getattr("ndim")?.extract()?;
        if let (1, Some(n)) = (ndim, repeat) {
            let np = obj.py().import("numpy")?;
            let width = a.len()?;
            // A view that repeats the one row: no copy.
            a = np.call_method1("broadcast_to", (a, (n, width)))?;
        }
        let rows = if let Ok(r) = a.extract::<PyReadonlyArray2<f64>>() {
            Rows::F64(r)
        } else if let Ok(r) = a.extract::<PyReadonlyArray2<f32>>() {
            Rows::F32(r)
        } else {
            return Err(PyValueError::new_err(format!(
                "{what} must have the shape (n, 3), not {}",
                shape_of(&a)
            )));
        };
        rows_of_three(what, rows.shape())?;
        Ok(rows)
    }

    fn shape(&self) -> &[usize] {
        match self {
            Rows::F64(a) => a.shape(),
            Rows::F32(a) => a.shape(),
        }
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.shape()[0]
    }

    /// Every row.
    pub fn to_vec(&self) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; self.len()];
        self.view().read(0, &mut out);
        out
    }

    /// A view for another thread.
    pub fn view(&self) -> RowsView<'_> {
        match self {
            Rows::F64(a) => RowsView::F64(a.as_array()),
            Rows::F32(a) => RowsView::F32(a.as_array()),
        }
    }
}

impl RowsView<'_> {
    /// Rows `start..start + out.len()` into `out`.
    pub fn read(&self, start: usize, out: &mut [DVec3]) {
        for (k, o) in out.iter_mut().enumerate() {
            let i = start + k;
            *o = match self {
                RowsView::F64(a) => DVec3::new(a[[i, 0]], a[[i, 1]], a[[i, 2]]),
                RowsView::F32(a) => DVec3::new(
                    f64::from(a[[i, 0]]),
                    f64::from(a[[i, 1]]),
                    f64::from(a[[i, 2]]),
                ),
            };
        }
    }
}
