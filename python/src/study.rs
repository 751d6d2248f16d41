//! Sun studies: `_sun_hours` sums the sun's visibility over a run of steps (`penumbra.study`
//! splits a study into runs, here or on Ray).

use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1};
use penumbra::{RenderOptions, SunStep, SunStudy, SunTarget};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{sensor_rows, vec3};
use crate::errors;
use crate::run::{Progress, off_interpreter};
use crate::scene::{Scene, backend, technique};

/// The indices of the steps the library renders ([`SunStudy::is_day`]): any of the sun's disk
/// of `angular_size_deg` above the horizon, and a weight that is not zero.
#[pyfunction]
#[pyo3(signature = (elevation_deg, hours, angular_size_deg=0.53))]
pub fn _daylight<'py>(
    py: Python<'py>,
    elevation_deg: PyReadonlyArray1<'py, f64>,
    hours: PyReadonlyArray1<'py, f64>,
    angular_size_deg: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let (el, w) = (elevation_deg.as_slice()?, hours.as_slice()?);
    if el.len() != w.len() {
        return Err(PyValueError::new_err(format!(
            "{} elevations and {} hours: give one of each per step",
            el.len(),
            w.len()
        )));
    }
    let study = SunStudy {
        angular_size_deg,
        ..SunStudy::default()
    };
    let days: Vec<i64> = el
        .iter()
        .zip(w)
        .enumerate()
        .filter(|&(_, (&elevation_deg, &hours))| {
            study.is_day(&SunStep {
                azimuth_deg: 0.0,
                elevation_deg,
                hours,
            })
        })
        .map(|(k, _)| k as i64)
        .collect();
    Ok(days.into_pyarray(py).into_any())
}

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
            let (p, n) = sensor_rows(p, n)?;
            Some((p.to_vec(), n.to_vec()))
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
    // The scene's kept renderer: a worker that runs several runs of steps of one scene builds
    // what they share once.
    let mut renderer = scene.take(b);
    let result = off_interpreter(py, Some(&progress), threads, || {
        let target = match &sensors {
            None => SunTarget::Pixels,
            Some((p, n)) => SunTarget::Points {
                points: p,
                normals: n,
            },
        };
        renderer.sun_hours(inner, &study, &steps, target, &|d| progress.set(d as u64))
    });
    scene.give_back(b, renderer);
    let result = result?;
    let sum = result.map_err(errors::render)?;
    let array = sum.into_pyarray(py);
    if sensors.is_some() {
        return Ok(array.into_any());
    }
    let (h, w) = (inner.camera.height as usize, inner.camera.width as usize);
    Ok(array.reshape([h, w])?.into_any())
}
