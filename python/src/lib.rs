//! The Python module `penumbra._penumbra`, re-exported by the package `penumbra`: scenes from
//! files or arrays, visibility images and sensor points as numpy arrays. Every call goes
//! through the library's front door ([`penumbra::Renderer`]); nothing is rendered here.

use pyo3::prelude::*;

mod arrays;
mod errors;
mod images;
mod objects;
mod run;
mod scene;
mod scene_state;
mod study;

/// Soft shadows from geometry: visibility images and sensor points as numpy arrays.
#[pymodule]
fn _penumbra(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<objects::Camera>()?;
    m.add_class::<objects::RectLight>()?;
    m.add_class::<objects::DistantLight>()?;
    m.add_class::<objects::Mesh>()?;
    m.add_class::<scene::Scene>()?;
    m.add_function(wrap_pyfunction!(images::write_exr, m)?)?;
    m.add_function(wrap_pyfunction!(images::read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(images::compare, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_colour_map, m)?)?;
    m.add_function(wrap_pyfunction!(scene::techniques, m)?)?;
    m.add_function(wrap_pyfunction!(study::_sun_hours, m)?)?;
    m.add_function(wrap_pyfunction!(study::_daylight, m)?)?;
    m.add_function(wrap_pyfunction!(scene::_scene_from_state, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
