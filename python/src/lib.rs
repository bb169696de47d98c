//! `stokesian._stokesian`: the solver of the `stokesian` crate as a Python module.
//!
//! Two classes: `PySystem` (`stokesian.System`, every confinement and truncation, the
//! dense mobility, matrix-free products, velocities, the resistance with lubrication,
//! Brownian trajectories) and `NBody` (`stokesian.NBody`, libMobility's interface in
//! free space and above a wall); and `confinements()`, every confinement with its
//! declared parameters, which `System(..., confinement=NAME, params={...})` takes. Every error of the library is raised as `ValueError`
//! with the library's message; the arithmetic runs with the GIL released.
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
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use stokesian::{
    declaration, lanczos_sqrt, Brownian, Confinement, Dimension, ExternalForces, Isa,
    LubricatedDynamics, Lubrication, Moments, Noise, ParamError, Particle, Precision, Run, Scheme,
    System, DECLARATIONS,
};

/// A library error as `ValueError` with its message.
fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The lubrication settings of `pair_tolerance` (the library's default without it),
/// checked; a tolerance without `lubrication` is an error.
fn lubrication_settings(lubrication: bool, pair_tolerance: Option<f64>) -> PyResult<Lubrication> {
    let lub = Lubrication::default();
    let Some(tol) = pair_tolerance else {
        return Ok(lub);
    };
    if !lubrication {
        return Err(PyValueError::new_err(
            "pair_tolerance applies with lubrication=True only",
        ));
    }
    let lub = lub.with_pair_tolerance(tol);
    lub.check().map_err(value_error)?;
    Ok(lub)
}

/// A NumPy array (or anything `numpy.asarray` accepts) as `f64`s in C order: borrowed
/// without a copy when NumPy already holds them contiguously, copied otherwise.
struct Floats<'py> {
    array: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
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

impl<'a, 'py> FromPyObject<'a, 'py> for Floats<'py> {
    type Error = PyErr;
    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        Ok(Floats {
            array: ob.extract()?,
        })
    }
}

/// `(N, 3)` or `(3N,)`: the number of rows `N`.
fn rows_of_three(name: &str, shape: &[usize]) -> PyResult<usize> {
    match *shape {
        [n, 3] => Ok(n),
        [m] if m % 3 == 0 => Ok(m / 3),
        _ => Err(PyValueError::new_err(format!(
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
        _ => Err(PyValueError::new_err(format!(
            "moments = {name:?}: must be \"F\", \"FT\" or \"FTS\""
        ))),
    }
}

/// `"double"` or `"single"`.
fn precision(name: &str) -> PyResult<Precision> {
    match name {
        "double" => Ok(Precision::Double),
        "single" => Ok(Precision::Single),
        _ => Err(PyValueError::new_err(format!(
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
        return Err(PyValueError::new_err(format!(
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
    let a = Array2::from_shape_vec((r, c).f(), m.data.into()).map_err(value_error)?;
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
        return Err(PyValueError::new_err(format!(
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
            stokesian::strain_components(&e).map_err(value_error)
        }
        shape => Err(PyValueError::new_err(format!(
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
    let decl = declaration(&name.replace('-', "_")).map_err(value_error)?;
    let mut values: Vec<(String, f64)> = Vec::new();
    if let Some(d) = params {
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                PyValueError::new_err(format!("params: the names must be strings, found {k}"))
            })?;
            let value: f64 = v.extract().map_err(|_| {
                PyValueError::new_err(format!("params[{key:?}] must be a number, found {v}"))
            })?;
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
            return Err(PyValueError::new_err(format!(
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
        PyValueError::new_err(message)
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
    m.add_class::<PySystem>()?;
    m.add_class::<NBody>()?;
    m.add_function(wrap_pyfunction!(confinements, m)?)?;
    Ok(())
}
