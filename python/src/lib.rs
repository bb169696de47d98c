//! `stokesian._stokesian`: the solver of the `stokesian` crate as a Python module.
//!
//! Two classes: `PySystem` (`stokesian.System`, every confinement and truncation, the
//! dense mobility, matrix-free products, velocities, the resistance with lubrication,
//! Brownian trajectories) and `NBody` (`stokesian.NBody`, libMobility's interface in
//! free space and above a wall); and `confinements()`, every confinement with its
//! declared parameters, which `System(..., confinement=NAME, params={...})` takes.
//!
//! Every error of the library and every refused input is raised as `stokesian.InputError`
//! with the library's message: a subclass of both `ValueError` (what `System`'s users
//! catch) and `RuntimeError` (what libMobility raises, and its users catch). Arrays come
//! in as NumPy arrays, anything `numpy.asarray` reads, or any CPU array offering
//! `__dlpack__` (torch, jax, cupy on the CPU); `NBody` returns its results in the kind of
//! array it was given (see [`Floats`]). The arithmetic runs with the GIL released.
//!
//! The crate forbids `unsafe` in its own code; PyO3's and rust-numpy's macros expand to
//! `unsafe` blocks in this crate, which `forbid` would reject (it cannot be overridden
//! by their `#[allow]`), so the lint is `deny`: any `unsafe` written here is still an
//! error.
#![deny(unsafe_code)]

mod nbody;
mod system;

use nbody::NBody;
use system::PySystem;

use numpy::ndarray::{Array2, Array3, ShapeBuilder};
use numpy::PyUntypedArrayMethods;
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArray3, PyArrayLikeDyn, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList, PyTuple, PyType};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use stokesian::{
    declaration, BoxLengths, Brownian, Confinement, Dimension, ExternalForces, Isa,
    LubricatedDynamics, Lubrication, Moments, Noise, Overlap, ParamError, Particle, PeriodicBox,
    Precision, Run, Scheme, System, DECLARATIONS,
};

/// `stokesian.InputError`, made once: `class InputError(RuntimeError, ValueError)`.
static INPUT_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// The docstring of `stokesian.InputError`.
const INPUT_ERROR_DOC: &str = "An input the solver refuses, or an error of the library, with \
the library's message. Both a RuntimeError (what libMobility raises, so that its scripts and \
tests catch it) and a ValueError (what the arguments' values cause).";

/// The class `stokesian.InputError`, built on first use from Python's own
/// `RuntimeError` and `ValueError` (PyO3's exceptions take one base).
fn input_error_type(py: Python<'_>) -> PyResult<&Bound<'_, PyType>> {
    let ty = INPUT_ERROR.get_or_try_init(py, || -> PyResult<Py<PyType>> {
        let builtins = py.import("builtins")?;
        let bases = PyTuple::new(
            py,
            [
                builtins.getattr("RuntimeError")?,
                builtins.getattr("ValueError")?,
            ],
        )?;
        let namespace = PyDict::new(py);
        namespace.set_item("__module__", "stokesian")?;
        namespace.set_item("__doc__", INPUT_ERROR_DOC)?;
        let ty = builtins
            .getattr("type")?
            .call1(("InputError", bases, namespace))?;
        Ok(ty.cast_into::<PyType>()?.unbind())
    })?;
    Ok(ty.bind(py))
}

/// A library error or a refused input as `stokesian.InputError` with its message.
fn input_error(e: impl std::fmt::Display) -> PyErr {
    Python::attach(|py| match input_error_type(py) {
        Ok(ty) => PyErr::from_type(ty.clone(), e.to_string()),
        Err(err) => err,
    })
}

/// The lubrication settings of `pair_tolerance` (the library's default without it),
/// checked; a tolerance without `lubrication` is an error.
fn lubrication_settings(lubrication: bool, pair_tolerance: Option<f64>) -> PyResult<Lubrication> {
    let lub = Lubrication::default();
    let Some(tol) = pair_tolerance else {
        return Ok(lub);
    };
    if !lubrication {
        return Err(input_error(
            "pair_tolerance applies with lubrication=True only",
        ));
    }
    let lub = lub.with_pair_tolerance(tol);
    lub.check().map_err(input_error)?;
    Ok(lub)
}

/// The kind of array an input was: how to hand a result back in the same kind.
/// `None`: NumPy (and what `numpy.asarray` reads, lists included); otherwise the
/// `from_dlpack` of the input's own library, which takes the NumPy result without a copy
/// (the array API's way: every array library offers `from_dlpack`).
pub(crate) struct Kind(Option<Py<PyAny>>);

impl Kind {
    /// NumPy's kind.
    pub(crate) const NUMPY: Kind = Kind(None);

    /// The same kind (a new reference).
    pub(crate) fn clone_ref(&self, py: Python<'_>) -> Kind {
        Kind(self.0.as_ref().map(|f| f.clone_ref(py)))
    }

    /// The NumPy array `a` as an array of this kind.
    pub(crate) fn wrap<'py>(&self, a: Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        match &self.0 {
            None => Ok(a),
            Some(from_dlpack) => from_dlpack.bind(a.py()).call1((a,)),
        }
    }

    /// The kind of `ob`, an array offering `__dlpack__` that is not NumPy's: the
    /// `from_dlpack` of its array API namespace (`__array_namespace__()`: jax, cupy), or
    /// of the top-level module of its type (torch); NumPy's when it has neither.
    fn of_dlpack(ob: &Bound<'_, PyAny>) -> Kind {
        let py = ob.py();
        let namespace = if ob.hasattr("__array_namespace__").unwrap_or(false) {
            ob.call_method0("__array_namespace__").ok()
        } else {
            ob.get_type()
                .module()
                .ok()
                .and_then(|m| {
                    let top = m.to_string();
                    let top = top.split('.').next().unwrap_or_default().to_string();
                    py.import(top).ok()
                })
                .map(|m| m.into_any())
        };
        Kind(
            namespace
                .and_then(|ns| ns.getattr("from_dlpack").ok())
                .map(Bound::unbind),
        )
    }
}

/// An array as `f64`s in C order: a NumPy array (or anything `numpy.asarray` accepts),
/// borrowed without a copy when NumPy already holds them contiguously, copied otherwise;
/// or any array offering `__dlpack__` (torch, jax, cupy, ... on the CPU), read through
/// `numpy.from_dlpack` without a copy, and its [`Kind`] kept for the results.
struct Floats<'py> {
    array: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    kind: Kind,
}

impl<'py> Floats<'py> {
    fn shape(&self) -> Vec<usize> {
        self.array.shape().to_vec()
    }

    /// The values, in C order (borrowed only from a C-contiguous array: a Fortran-ordered
    /// one is contiguous too, in the other order).
    fn values(&self) -> std::borrow::Cow<'_, [f64]> {
        match self.array.as_slice() {
            Ok(s) if self.array.is_c_contiguous() => std::borrow::Cow::Borrowed(s),
            _ => std::borrow::Cow::Owned(self.array.as_array().iter().copied().collect()),
        }
    }
}

/// DLPack's device type of the CPU (`kDLCPU`).
const DLPACK_CPU: i32 = 1;

impl<'a, 'py> FromPyObject<'a, 'py> for Floats<'py> {
    type Error = PyErr;
    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let ob = ob.to_owned();
        if ob.is_instance_of::<numpy::PyUntypedArray>() || !ob.hasattr("__dlpack__")? {
            return Ok(Floats {
                array: ob.extract()?,
                kind: Kind::NUMPY,
            });
        }
        // another library's array: on the CPU (the device is optional in DLPack's
        // protocol; without it, NumPy's from_dlpack refuses what it cannot read)
        if ob.hasattr("__dlpack_device__")? {
            let (device, id): (i32, i32) = ob.call_method0("__dlpack_device__")?.extract()?;
            if device != DLPACK_CPU {
                return Err(input_error(format!(
                    "an array on DLPack device ({device}, {id}): only arrays on the CPU \
                     (device type {DLPACK_CPU}) are read; move it with the library's own \
                     .cpu() or to_device"
                )));
            }
        }
        let numpy = ob.py().import("numpy")?;
        let array = numpy
            .call_method1("from_dlpack", (&ob,))
            .map_err(|e| input_error(format!("cannot read the array through DLPack: {e}")))?;
        Ok(Floats {
            array: array.extract()?,
            kind: Kind::of_dlpack(&ob),
        })
    }
}

/// `(N, 3)` or `(3N,)`: the number of rows `N`.
fn rows_of_three(name: &str, shape: &[usize]) -> PyResult<usize> {
    match *shape {
        [n, 3] => Ok(n),
        [m] if m % 3 == 0 => Ok(m / 3),
        _ => Err(input_error(format!(
            "{name} must have shape (N, 3) or (3N,), found {shape:?}"
        ))),
    }
}

/// The moment truncation named `F`, `FT` or `FTS`.
fn moments(name: &str) -> PyResult<Moments> {
    match name {
        "F" => Ok(Moments::F),
        "FT" => Ok(Moments::FT),
        "FTS" => Ok(Moments::FTS),
        _ => Err(input_error(format!(
            "moments = {name:?}: must be \"F\", \"FT\" or \"FTS\""
        ))),
    }
}

/// `"double"` or `"single"`.
fn precision(name: &str) -> PyResult<Precision> {
    match name {
        "double" => Ok(Precision::Double),
        "single" => Ok(Precision::Single),
        _ => Err(input_error(format!(
            "precision = {name:?}: must be \"double\" or \"single\""
        ))),
    }
}

/// Radii: one for all `n` spheres, or one each.
fn radii(ob: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<f64>> {
    if let Ok(a) = ob.extract::<f64>() {
        return Ok(vec![a; n]);
    }
    let a: Floats = ob.extract()?;
    let v = a.values().into_owned();
    if a.shape().len() != 1 || v.len() != n {
        return Err(input_error(format!(
            "radii: one number, or one per particle ({n}), found shape {:?}",
            a.shape()
        )));
    }
    Ok(v)
}

/// Particles from `(N, 3)` or `(3N,)` centres and radii.
fn particles(positions: &Floats, radii_ob: &Bound<'_, PyAny>) -> PyResult<Vec<Particle>> {
    let n = rows_of_three("positions", &positions.shape())?;
    let a = radii(radii_ob, n)?;
    let x = positions.values();
    Ok((0..n)
        .map(|i| Particle {
            x: [x[3 * i], x[3 * i + 1], x[3 * i + 2]],
            a: a[i],
        })
        .collect())
}

/// A vector of `3N` values as an array of `shape`.
fn shaped<'py>(py: Python<'py>, v: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    let a = PyArray1::from_vec(py, v);
    Ok(a.reshape(shape.to_vec())?.into_any())
}

/// A dense matrix (column-major) as a Fortran-ordered NumPy array, without a copy.
fn matrix(py: Python<'_>, m: nalgebra::DMatrix<f64>) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let (r, c) = m.shape();
    let a = Array2::from_shape_vec((r, c).f(), m.data.into()).map_err(input_error)?;
    Ok(PyArray2::from_owned_array(py, a))
}

/// `U` and `Omega` (moment-major, `3N` each) as `(N, 3)` arrays; `Omega` `None` at F.
fn split<'py>(
    py: Python<'py>,
    u: Vec<f64>,
    n: usize,
) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
    let omega = (u.len() == 6 * n).then(|| u[3 * n..].to_vec());
    let lin = shaped(py, u[..3 * n].to_vec(), &[n, 3])?;
    let ang = omega.map(|w| shaped(py, w, &[n, 3])).transpose()?;
    Ok((lin, ang))
}

/// `3N` numbers from an `(N, 3)` or `(3N,)` array.
fn vec_of(n: usize, name: &str, a: &Floats) -> PyResult<Vec<f64>> {
    let rows = rows_of_three(name, &a.shape())?;
    if rows != n {
        return Err(input_error(format!(
            "{name}: {rows} rows for {n} particles"
        )));
    }
    Ok(a.values().into_owned())
}

/// A uniform strain as 5 components in the orthonormal basis, from those 5 or from the
/// symmetric traceless 3x3 Cartesian tensor.
fn strain_basis(s: &Floats) -> PyResult<[f64; 5]> {
    let v = s.values();
    match s.shape().as_slice() {
        [5] => Ok([v[0], v[1], v[2], v[3], v[4]]),
        [3, 3] => {
            let e = [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]];
            stokesian::strain_components(&e).map_err(input_error)
        }
        shape => Err(input_error(format!(
            "strain must have shape (5,) (orthonormal basis) or (3, 3) (Cartesian), found {shape:?}"
        ))),
    }
}

/// The keyword aliases of `System` (the keywords of the first confinements, kept
/// beside `params`) and the declared parameter each stands for.
const ALIASES: [(&str, &str); 3] = [
    ("boundary_height", "height"),
    ("lam", "lambda"),
    ("gap", "gap"),
];

/// The confinement called `name` (`-` read as `_`) with the declared parameters of
/// `params` (a dict of numbers by name) and of the keyword aliases given (`aliases`: the
/// values of [`ALIASES`]' keywords, in order), the others at their defaults. Unknown,
/// missing, repeated (an alias and its name in `params`) and non-finite parameters are
/// `ValueError`s with the library's message (`ParamError`), naming the keyword where the
/// parameter came from one.
fn declared_confinement(
    name: &str,
    params: Option<&Bound<'_, PyDict>>,
    aliases: [Option<f64>; 3],
) -> PyResult<Confinement> {
    let decl = declaration(&name.replace('-', "_")).map_err(input_error)?;
    let mut values: Vec<(String, f64)> = Vec::new();
    if let Some(d) = params {
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                input_error(format!("params: the names must be strings, found {k}"))
            })?;
            let value: f64 = v
                .extract()
                .map_err(|_| input_error(format!("params[{key:?}] must be a number, found {v}")))?;
            values.push((key, value));
        }
    }
    let keywords: Vec<(&str, &str, f64)> = ALIASES
        .iter()
        .zip(aliases)
        .filter_map(|(&(keyword, param), v)| v.map(|v| (keyword, param, v)))
        .collect();
    for &(keyword, param, value) in &keywords {
        if values.iter().any(|(k, _)| k == param) {
            return Err(input_error(format!(
                "{keyword} and params[{param:?}] both give the parameter `{param}` \
                 ({keyword} is its other name): give it once"
            )));
        }
        values.push((param.to_string(), value));
    }
    let given: Vec<(&str, f64)> = values.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    decl.with(&given).map_err(|e| {
        let via = |param: &str| keywords.iter().find(|(_, p, _)| *p == param);
        let message = match &e {
            ParamError::Unknown { param, .. } => match via(param) {
                Some((keyword, ..)) => format!("{keyword}: {e}"),
                None => e.to_string(),
            },
            ParamError::NotFinite { param, .. } => match via(param) {
                Some((keyword, ..)) => format!("{keyword}: {e}"),
                None => e.to_string(),
            },
            ParamError::Missing { param, .. } => match ALIASES.iter().find(|(_, p)| p == param) {
                Some((keyword, _)) => format!("{e} (params={{{param:?}: ...}} or {keyword}=...)"),
                None => format!("{e} (params={{{param:?}: ...}})"),
            },
            _ => e.to_string(),
        };
        input_error(message)
    })
}

/// Every confinement with its declared parameters: a list of dicts `name`, `title`,
/// `params` (each `name`, `doc`, `dimension` (`"position"`, `"length"` or `"number"`),
/// `default` (None: must be given) and `example`).
#[pyfunction]
fn confinements(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let out = PyList::empty(py);
    for decl in DECLARATIONS {
        let params = PyList::empty(py);
        for p in decl.params {
            let d = PyDict::new(py);
            d.set_item("name", p.name)?;
            d.set_item("doc", p.doc)?;
            let dimension = match p.dimension {
                Dimension::Position(_) => "position",
                Dimension::Length => "length",
                Dimension::Number => "number",
            };
            d.set_item("dimension", dimension)?;
            d.set_item("default", p.default)?;
            d.set_item("example", p.example)?;
            params.append(d)?;
        }
        let d = PyDict::new(py);
        d.set_item("name", decl.name)?;
        d.set_item("title", decl.title)?;
        d.set_item("params", params)?;
        out.append(d)?;
    }
    Ok(out)
}

/// The module.
#[pymodule]
fn _stokesian(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("InputError", input_error_type(m.py())?)?;
    m.add_class::<PySystem>()?;
    m.add_class::<NBody>()?;
    m.add_function(wrap_pyfunction!(confinements, m)?)?;
    Ok(())
}
