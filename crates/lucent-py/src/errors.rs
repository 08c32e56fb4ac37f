//! The library's errors as Python exceptions.
//!
//! `lucent.SceneError` and `lucent.PartialError` are Python classes (in
//! `lucent/_errors.py`, where they are documented and pickle like any
//! exception); this module builds them from the library's error values,
//! with the location as attributes.

use lucent::scene::SceneError;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// An instance of the exception class `name` of `lucent._errors`, made
/// with the message `text` and the keyword attributes `kwargs`; a plain
/// `ValueError` if the package is not importable (the extension module
/// used on its own).
fn lucent_error(py: Python<'_>, name: &str, text: String, kwargs: Option<&Bound<'_, PyDict>>) -> PyErr {
    let made =
        py.import("lucent._errors").and_then(|m| m.getattr(name)).and_then(|cls| cls.call((text.clone(),), kwargs));
    match made {
        Ok(exception) => PyErr::from_value(exception),
        Err(_) => PyValueError::new_err(text),
    }
}

/// `lucent.SceneError` for a scene that cannot be loaded or built: the
/// library's complete message (with the offending line and a caret) as its
/// text, and `path`, `line`, `column`, `message` and `line_text`.
pub fn scene_error(py: Python<'_>, e: &SceneError) -> PyErr {
    let kwargs = PyDict::new(py);
    let attributes = (|| -> PyResult<()> {
        kwargs.set_item("message", &e.message)?;
        kwargs.set_item("path", e.path.as_ref().map(|p| p.to_string_lossy().into_owned()))?;
        kwargs.set_item("line", e.location.map(|l| l.line))?;
        kwargs.set_item("column", e.location.map(|l| l.column))?;
        kwargs.set_item("line_text", &e.line_text)?;
        Ok(())
    })();
    match attributes {
        Ok(()) => lucent_error(py, "SceneError", e.to_string(), Some(&kwargs)),
        Err(err) => err,
    }
}

/// `lucent.PartialError`: partial renders that cannot be merged, or
/// damaged partial-render data.
pub fn partial_error(py: Python<'_>, message: impl std::fmt::Display) -> PyErr {
    lucent_error(py, "PartialError", message.to_string(), None)
}

/// `OSError` for a file that cannot be read or written, `ValueError` for
/// what is wrong with the request itself (an unknown extension, a size).
pub fn io_error(message: impl std::fmt::Display, is_io: bool) -> PyErr {
    if is_io {
        PyOSError::new_err(message.to_string())
    } else {
        PyValueError::new_err(message.to_string())
    }
}

/// `RuntimeError` for a failure that is neither the user's input nor a
/// file (a render worker that panicked, threads that cannot start).
pub fn runtime_error(message: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(message.to_string())
}
