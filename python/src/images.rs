//! Visibility images as numpy arrays: `(height, width)` float32, row 0 the image's top; EXR
//! files with the library's rules (one channel `V`, or `<light>.V` per light); comparisons by
//! the library's metrics.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use penumbra::geom::Metrics;
use penumbra::{Channel, VisibilityChannels, VisibilityImage};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::errors::{file, value};

/// An image as a `(height, width)` float32 array.
pub fn to_array<'py>(py: Python<'py>, image: VisibilityImage) -> Bound<'py, PyArray2<f32>> {
    let (w, h) = (image.width as usize, image.height as usize);
    image
        .data
        .into_pyarray(py)
        .reshape([h, w])
        .expect("an image holds width x height values")
}

/// A `(height, width)` array of numbers as an image; `what` names it in errors.
pub fn from_array(what: &str, obj: &Bound<'_, PyAny>) -> PyResult<VisibilityImage> {
    let np = obj.py().import("numpy")?;
    let a = np.call_method1("asarray", (obj, "float32"))?;
    let a: PyReadonlyArray2<f32> = a.extract().map_err(|_| {
        PyValueError::new_err(format!(
            "{what} must be a 2-D array (height, width), not of shape {}",
            a.getattr("shape")
                .map(|s| s.to_string())
                .unwrap_or_default()
        ))
    })?;
    let [h, w] = [a.shape()[0], a.shape()[1]];
    let (Ok(width), Ok(height)) = (u32::try_from(w), u32::try_from(h)) else {
        return Err(PyValueError::new_err(format!("{what}: {w} x {h} pixels")));
    };
    let image = VisibilityImage {
        width,
        height,
        data: a.as_array().iter().copied().collect(),
    };
    image
        .check()
        .map_err(|e| PyValueError::new_err(format!("{what}: {e}")))?;
    Ok(image)
}

/// Writes `v` to the EXR file `path`: a `(height, width)` array as the one channel `V`, or a
/// dict of such arrays, one channel per light (`{"key": a, "fill": b}` or with the keys'
/// `.V` given, as `read_exr` returns them). The file is written whole or not at all.
#[pyfunction]
pub fn write_exr(path: PathBuf, v: &Bound<'_, PyAny>) -> PyResult<()> {
    let written = if let Ok(d) = v.cast::<PyDict>() {
        if d.is_empty() {
            return Err(PyValueError::new_err(
                "write_exr: the dict holds no channel (one array per light)",
            ));
        }
        let mut channels = Vec::new();
        for (k, a) in d.iter() {
            let key: String = k
                .cast::<PyString>()
                .map_err(|_| PyValueError::new_err("the channels' names must be strings"))?
                .to_string();
            let name = if key == "V" || key.ends_with(".V") {
                key.clone()
            } else {
                format!("{key}.V")
            };
            channels.push(Channel {
                name,
                image: from_array(&format!("channel {key:?}"), &a)?,
            });
        }
        VisibilityChannels::new(channels)
            .map_err(value)?
            .write_exr(&path)
    } else {
        from_array("v", v)?.write_exr(&path)
    };
    written.map_err(value)
}

/// The visibility channels of the EXR file `path`: a dict from each channel's name (`V`, or
/// `<light>.V`) to its `(height, width)` float32 array, in the file's order of lights.
#[pyfunction]
pub fn read_exr(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let channels = VisibilityChannels::read_exr(&path).map_err(|e| file(&path, e))?;
    let out = PyDict::new(py);
    for c in channels.into_channels() {
        out.set_item(c.name, to_array(py, c.image))?;
    }
    Ok(out)
}

/// Compares `a` against the reference `b` (arrays of one shape): over all pixels (`mae`,
/// `rmse`, `p99`, `max`, `share_over` the share of errors over 0.05, `equal` the share of
/// identical pixels, `pixels`), over the penumbra pixels of `b`, 0.02 < V < 0.98 (the same
/// with `penumbra_` before them, and `penumbra_signed`, the mean of a - b there), and
/// `umbra_pixels` with `umbra_lit`, the share of them that `a` shows lit.
#[pyfunction]
pub fn compare<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyAny>,
    b: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let c = penumbra::compare(&from_array("a", a)?, &from_array("b", b)?).map_err(value)?;
    let out = PyDict::new(py);
    let put = |prefix: &str, m: &Metrics| -> PyResult<()> {
        out.set_item(format!("{prefix}mae"), m.mae)?;
        out.set_item(format!("{prefix}rmse"), m.rmse)?;
        out.set_item(format!("{prefix}p99"), m.p99)?;
        out.set_item(format!("{prefix}max"), m.max)?;
        out.set_item(format!("{prefix}share_over"), m.share_over)?;
        out.set_item(format!("{prefix}equal"), m.equal)?;
        out.set_item(format!("{prefix}pixels"), m.pixels)?;
        Ok(())
    };
    put("", &c.all)?;
    put("penumbra_", &c.penumbra)?;
    out.set_item("penumbra_signed", c.penumbra_signed)?;
    out.set_item("umbra_pixels", c.umbra_pixels)?;
    out.set_item("umbra_lit", c.umbra_lit)?;
    Ok(out)
}

/// Writes `values` (a `(height, width)` array of numbers from 0 up, such as hours of sun) to
/// the PNG file `path` as a colour map from 0 to their maximum (viridis) with a legend at the
/// right in `unit` (`"h"` for hours, or `""`). Written whole or not at all.
#[pyfunction]
#[pyo3(signature = (path, values, unit="h"))]
pub fn write_colour_map(path: PathBuf, values: &Bound<'_, PyAny>, unit: &str) -> PyResult<()> {
    let np = values.py().import("numpy")?;
    let a = np.call_method1("asarray", (values, "float32"))?;
    let a: PyReadonlyArray2<f32> = a
        .extract()
        .map_err(|_| PyValueError::new_err("values must be a 2-D array (height, width)"))?;
    let [h, w] = [a.shape()[0], a.shape()[1]];
    if w == 0 || h == 0 {
        return Err(PyValueError::new_err(format!("values: {w} x {h} pixels")));
    }
    let data: Vec<f32> = a.as_array().iter().copied().collect();
    if let Some(i) = data.iter().position(|v| !v.is_finite() || *v < 0.0) {
        return Err(PyValueError::new_err(format!(
            "values: pixel ({}, {}) is {}: give finite numbers from 0 up",
            i % w,
            i / w,
            data[i]
        )));
    }
    let u = match unit {
        "h" => 'h',
        "" => ' ',
        _ => {
            return Err(PyValueError::new_err(format!(
                "unit {unit:?}: \"h\" (hours) or \"\" (none)"
            )));
        }
    };
    let (pw, ph, rgb) = penumbra::geom::colour_map(&data, w, h, u);
    penumbra::geom::write_png_bytes(
        &path,
        pw as u32,
        ph as u32,
        penumbra::geom::PngColor::Rgb,
        &rgb,
    )
    .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))
}
