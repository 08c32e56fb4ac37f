//! `lucent._native`: the extension module under the `lucent` Python
//! package (`python/lucent`). It is a thin client of the library's public
//! API: scenes go in through the library's loader, renders run through
//! `render_into` as in the command-line program, images are written and
//! read by the library. The Python package adds NumPy arrays, the scene
//! builder on dicts, progress bars and notebook display.

mod denoise;
mod errors;
mod image;
mod partial;
mod render;
mod scene;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MAX_SPP", lucent::loader::MAX_SPP)?;
    m.add_class::<scene::Source>()?;
    m.add_class::<render::Accumulation>()?;
    m.add_class::<partial::Partial>()?;
    m.add_function(wrap_pyfunction!(scene::describe, m)?)?;
    m.add_function(wrap_pyfunction!(image::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(image::read_image_file, m)?)?;
    m.add_function(wrap_pyfunction!(image::diff, m)?)?;
    m.add_function(wrap_pyfunction!(denoise::denoise, m)?)?;
    Ok(())
}
