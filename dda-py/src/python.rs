//! The `dda._native` module: what the Python package calls. Every call
//! that can fail returns `dda.DdaError` with the whole message; runs
//! release the GIL; a panic is caught and reported as an error too.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use dda_contact::LawRegistry;
use pyo3::exceptions::{PyException, PyKeyError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use pyo3::IntoPyObjectExt;

use crate::columns::{read_columns, Column};
use crate::scene::EditableScene;
use crate::tree::{Given, Node};

pyo3::create_exception!(
    dda,
    DdaError,
    PyException,
    "A scene, run or result file is wrong; the message names the file, the place and the fix."
);

/// An error of the library as `dda.DdaError`, with its whole chain.
fn dda_error(e: anyhow::Error) -> PyErr {
    DdaError::new_err(format!("{e:#}"))
}

/// Runs `f`, turning a panic into an error rather than unwinding into
/// Python.
fn guarded<T>(what: &str, f: impl FnOnce() -> anyhow::Result<T>) -> anyhow::Result<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(panic) => {
            let message = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "no message".into());
            Err(anyhow::anyhow!(
                "{what}: internal error (a bug, please report it): {message}"
            ))
        }
    }
}

/// Runs a scene file into `out`; returns the summary as JSON text.
#[pyfunction]
fn run_file(py: Python<'_>, scene: PathBuf, out: PathBuf) -> PyResult<String> {
    py.detach(|| {
        guarded(&scene.display().to_string(), || {
            let loaded = EditableScene::load(&scene)?;
            let summary = loaded.run(&out, &LawRegistry::with_builtin())?;
            Ok(summary_json(&summary))
        })
    })
    .map_err(dda_error)
}

/// The summary as the JSON text of `summary.json`.
fn summary_json(summary: &dda::Summary) -> String {
    serde_json::to_string(summary).unwrap_or_else(|_| "{}".into())
}

/// The columns of a results CSV as a dict of lists, in header order.
#[pyfunction]
fn read_table<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let columns = py
        .detach(|| guarded(&path.display().to_string(), || read_columns(&path)))
        .map_err(dda_error)?;
    let dict = PyDict::new(py);
    for (name, column) in columns {
        match column {
            Column::Int(v) => dict.set_item(name, PyList::new(py, v)?)?,
            Column::Float(v) => dict.set_item(name, PyList::new(py, v)?)?,
            Column::Text(v) => dict.set_item(name, PyList::new(py, v)?)?,
        }
    }
    Ok(dict)
}

/// Runs the study in `study` into `out` with `jobs` runs at once (default
/// one per core); its errors come back as `DdaError`.
#[pyfunction]
#[pyo3(signature = (study, out, jobs=None))]
fn run_study(py: Python<'_>, study: PathBuf, out: PathBuf, jobs: Option<usize>) -> PyResult<()> {
    py.detach(|| {
        guarded(&study.display().to_string(), || {
            let options = dda::study::Options {
                out: out.clone(),
                jobs,
                shard: None,
                progress: false,
            };
            dda::study::run(&study, &options).map(|_| ())
        })
    })
    .map_err(dda_error)
}

/// A scene held in Rust: read, changed by path and run.
#[pyclass(name = "NativeScene", module = "dda._native")]
struct NativeScene {
    inner: EditableScene,
}

#[pymethods]
impl NativeScene {
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py
            .detach(|| guarded(&path.display().to_string(), || EditableScene::load(&path)))
            .map_err(dda_error)?;
        Ok(NativeScene { inner })
    }

    #[staticmethod]
    fn from_ron(text: &str, origin: &str) -> PyResult<Self> {
        let inner = guarded(origin, || EditableScene::from_ron(text, origin)).map_err(dda_error)?;
        Ok(NativeScene { inner })
    }

    fn get<'py>(&self, py: Python<'py>, path: &str) -> PyResult<Bound<'py, PyAny>> {
        let node = self
            .inner
            .get(path)
            .map_err(|e| PyKeyError::new_err(e.to_string()))?;
        to_python(py, &node)
    }

    fn set(&mut self, path: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let given = from_python(value)?;
        let origin = self.inner.scene.origin().to_string();
        let inner = &mut self.inner;
        guarded(&origin, || inner.set(path, &given)).map_err(dda_error)
    }

    fn to_ron(&self) -> String {
        self.inner.scene.to_ron()
    }

    fn origin(&self) -> String {
        self.inner.scene.origin().to_string()
    }

    fn dimension(&self) -> u32 {
        self.inner.scene.dimension
    }

    fn block_count(&self) -> usize {
        self.inner.scene.block_count()
    }

    fn run(&self, py: Python<'_>, out: PathBuf) -> PyResult<String> {
        let inner = self.inner.clone();
        py.detach(|| {
            guarded(inner.scene.origin(), || {
                let summary = inner.run(&out, &LawRegistry::with_builtin())?;
                Ok(summary_json(&summary))
            })
        })
        .map_err(dda_error)
    }
}

/// A value of the scene tree as Python: numbers, strings, lists, dicts; a
/// unit variant is its name, any other variant `{name: value}`.
fn to_python<'py>(py: Python<'py>, node: &Node) -> PyResult<Bound<'py, PyAny>> {
    Ok(match node {
        Node::Bool(b) => b.into_bound_py_any(py)?,
        Node::Int(i) => i.into_bound_py_any(py)?,
        Node::Float(x) => x.into_bound_py_any(py)?,
        Node::Char(c) => c.into_bound_py_any(py)?,
        Node::Str(s) | Node::Name(s) | Node::Raw(s) => s.into_bound_py_any(py)?,
        Node::None | Node::Unit => py.None().into_bound(py),
        Node::Some(inner) | Node::Wrapped(_, inner) => to_python(py, inner)?,
        Node::Seq(items) | Node::Tuple(_, items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(to_python(py, item)?)?;
            }
            list.into_any()
        }
        Node::Map(entries) => {
            let dict = PyDict::new(py);
            for (key, value) in entries {
                dict.set_item(to_python(py, key)?, to_python(py, value)?)?;
            }
            dict.into_any()
        }
        Node::Struct(_, fields) => {
            let dict = PyDict::new(py);
            for (name, value) in fields {
                dict.set_item(name, to_python(py, value)?)?;
            }
            dict.into_any()
        }
        Node::Newtype(name, inner) => {
            let dict = PyDict::new(py);
            dict.set_item(name, to_python(py, inner)?)?;
            dict.into_any()
        }
    })
}

/// A Python value to put into the scene tree.
fn from_python(value: &Bound<'_, PyAny>) -> PyResult<Given> {
    if value.is_none() {
        return Ok(Given::None);
    }
    if value.is_instance_of::<PyBool>() {
        return Ok(Given::Bool(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(Given::Int(value.extract()?));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(Given::Float(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(Given::Str(value.extract()?));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut entries = Vec::new();
        for (k, v) in dict.iter() {
            entries.push((k.str()?.to_string(), from_python(&v)?));
        }
        return Ok(Given::Dict(entries));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: PyResult<Vec<Given>> = value.try_iter()?.map(|v| from_python(&v?)).collect();
        return Ok(Given::List(items?));
    }
    // numpy scalars and other numbers: as floats.
    if let Ok(x) = value.extract::<f64>() {
        return Ok(Given::Float(x));
    }
    Err(DdaError::new_err(format!(
        "a scene value is a number, string, bool, None, list or dict, not {}",
        value.get_type().name()?
    )))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("DdaError", m.py().get_type::<DdaError>())?;
    m.add_function(wrap_pyfunction!(run_file, m)?)?;
    m.add_function(wrap_pyfunction!(read_table, m)?)?;
    m.add_function(wrap_pyfunction!(run_study, m)?)?;
    m.add_class::<NativeScene>()?;
    Ok(())
}
