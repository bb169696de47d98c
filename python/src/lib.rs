//! `stokesian._stokesian`: the solver of the `stokesian` crate as a Python module.
//!
//! Two classes: `PySystem` (`stokesian.System`, every confinement and truncation, the
//! dense mobility, matrix-free products, velocities, the resistance with lubrication,
//! Brownian trajectories) and `NBody` (`stokesian.NBody`, libMobility's interface in
//! free space and above a wall). Every error of the library is raised as `ValueError`
//! with the library's message; the arithmetic runs with the GIL released.
//!
//! The crate forbids `unsafe` in its own code; PyO3's and rust-numpy's macros expand to
//! `unsafe` blocks in this crate, which `forbid` would reject (it cannot be overridden
//! by their `#[allow]`), so the lint is `deny`: any `unsafe` written here is still an
//! error.
#![deny(unsafe_code)]

use numpy::ndarray::{Array2, Array3, ShapeBuilder};
use numpy::PyUntypedArrayMethods;
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArray3, PyArrayLikeDyn, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use stokesian::{
    lanczos_sqrt, Brownian, Confinement, ExternalForces, Isa, LubricatedDynamics, Lubrication,
    Moments, Noise, Particle, Precision, Run, Scheme, System,
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

/// Spheres in Stokes flow: the whole solver.
///
/// Units: any consistent set (SI: positions and radii in m, viscosity in Pa s, forces in
/// N, torques in N m); velocities come out in length/time, rotation rates in rad/time.
/// Sign: forces, torques and stresslets are those the particles exert on the fluid,
/// equal to the external force and torque on each particle (a sphere sinking under
/// gravity has a force of -(buoyant weight) along z). Matrices are moment-major: all U
/// (3N: U1x, U1y, U1z, U2x, ...), then all Omega (3N), then all E (5N, orthonormal
/// strain basis), the rows mapping (F, L, S) to (U - U_inf, Omega - Omega_inf, -E_inf).
#[pyclass(name = "System", module = "stokesian", frozen)]
struct PySystem {
    system: System,
}

#[pymethods]
impl PySystem {
    #[new]
    #[pyo3(signature = (positions, radii, *, confinement = "wall", viscosity = 1.0, boundary_height = 0.0, lam = None, gap = None, allow_overlap = false))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        positions: Floats,
        radii: &Bound<'_, PyAny>,
        confinement: &str,
        viscosity: f64,
        boundary_height: f64,
        lam: Option<f64>,
        gap: Option<f64>,
        allow_overlap: bool,
    ) -> PyResult<Self> {
        let name = confinement.replace('-', "_");
        let inapplicable = |option: &str| {
            PyValueError::new_err(format!(
                "{option} does not apply to confinement {confinement:?}"
            ))
        };
        if lam.is_some() && name != "interface" {
            return Err(inapplicable("lam"));
        }
        if gap.is_some() && name != "slit" {
            return Err(inapplicable("gap"));
        }
        let params: Vec<f64> = match name.as_str() {
            "free" if boundary_height != 0.0 => return Err(inapplicable("boundary_height")),
            "free" => vec![],
            "interface" => vec![
                boundary_height,
                lam.ok_or_else(|| {
                    PyValueError::new_err(
                        "confinement \"interface\" needs lam (the viscosity ratio of the \
                         liquid beyond the interface to the liquid holding the spheres)",
                    )
                })?,
            ],
            "slit" => vec![
                boundary_height,
                gap.ok_or_else(|| {
                    PyValueError::new_err(
                        "confinement \"slit\" needs gap (the distance from the lower wall \
                         to the upper wall)",
                    )
                })?,
            ],
            _ => vec![boundary_height],
        };
        let conf = Confinement::from_name(&name, &params).ok_or_else(|| {
            PyValueError::new_err(format!(
                "confinement {confinement:?}: must be one of {}",
                Confinement::NAMES.join(", ")
            ))
        })?;
        let ps = particles(&positions, radii)?;
        let system = py
            .detach(|| System::new(conf, viscosity, ps, allow_overlap))
            .map_err(value_error)?;
        Ok(PySystem { system })
    }

    /// Number of spheres.
    fn __len__(&self) -> usize {
        self.system.len()
    }

    /// The centres, `(N, 3)`.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let x = self.system.particles().iter().flat_map(|p| p.x).collect();
        shaped(py, x, &[self.system.len(), 3])
    }

    /// The radii, `(N,)`.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let a: Vec<f64> = self.system.particles().iter().map(|p| p.a).collect();
        PyArray1::from_vec(py, a)
    }

    /// The confinement's name (`free`, `wall`, `free_surface`, `interface`, `slit`).
    #[getter]
    fn confinement(&self) -> &'static str {
        self.system.confinement().name()
    }

    /// The viscosity.
    #[getter]
    fn viscosity(&self) -> f64 {
        self.system.viscosity()
    }

    /// The dense grand mobility, `(kN, kN)` with k = 3, 6, 11 for F, FT, FTS.
    #[pyo3(signature = (moments = "F"))]
    fn mobility<'py>(&self, py: Python<'py>, moments: &str) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let m = self::moments(moments)?;
        let s = &self.system;
        // assembled straight into NumPy's array (column-major: Fortran order), whose
        // allocator asks for transparent huge pages for large arrays, as
        // `stokesian::linalg::LargeMatrix` does for the command line
        let dim = m.per_particle() * s.len();
        let out = PyArray2::<f64>::zeros(py, [dim, dim], true);
        {
            let mut values = out.readwrite();
            let values = values.as_slice_mut().map_err(value_error)?;
            py.detach(|| s.mobility_into(m, values));
        }
        Ok(out)
    }

    /// `M x` without forming `M`: `x` of length kN, moment-major; `precision`
    /// `"single"` runs the `f32` lanes.
    #[pyo3(signature = (moments, x, *, precision = "double"))]
    fn apply<'py>(
        &self,
        py: Python<'py>,
        moments: &str,
        x: Floats,
        precision: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let m = self::moments(moments)?;
        let p = self::precision(precision)?;
        let expected = m.per_particle() * self.system.len();
        let x = x.values();
        if x.len() != expected {
            return Err(PyValueError::new_err(format!(
                "x has {} entries; {moments} for {} particles needs {expected}",
                x.len(),
                self.system.len()
            )));
        }
        let s = &self.system;
        let x: &[f64] = &x;
        Ok(PyArray1::from_vec(
            py,
            py.detach(|| s.apply_with(m, x, Isa::best(), p)),
        ))
    }

    /// Velocities `(N, 3)` and rotation rates `(N, 3)` (None at the F level) of spheres
    /// under `forces` and `torques` (`(N, 3)` or `(3N,)`) and the imposed strain.
    #[pyo3(signature = (forces, torques = None, strain = None, lubrication = false, pair_tolerance = None))]
    fn velocities<'py>(
        &self,
        py: Python<'py>,
        forces: Floats,
        torques: Option<Floats>,
        strain: Option<Floats>,
        lubrication: bool,
        pair_tolerance: Option<f64>,
    ) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
        let n = self.system.len();
        let m = match (&strain, &torques) {
            (Some(_), _) => Moments::FTS,
            (None, Some(_)) => Moments::FT,
            (None, None) if lubrication => Moments::FT,
            (None, None) => Moments::F,
        };
        let mut x = vec_of(n, "forces", &forces)?;
        match &torques {
            Some(t) => x.extend(vec_of(n, "torques", t)?),
            None if m != Moments::F => x.extend(vec![0.0; 3 * n]),
            None => {}
        }
        let e = match &strain {
            None => [0.0; 5],
            Some(s) => strain_basis(s)?,
        };
        let lub = lubrication_settings(lubrication, pair_tolerance)?;
        let s = &self.system;
        let v = py
            .detach(|| s.velocities(m, &x, &e, lubrication.then_some(&lub)))
            .map_err(value_error)?;
        let (lin, ang) = split(py, v.u, n)?;
        Ok((
            lin,
            if torques.is_some() || m != Moments::F {
                ang
            } else {
                None
            },
        ))
    }

    /// The grand resistance `(kN, kN)` (FT or FTS), with lubrication (Eq. 19) or the
    /// inverse of the far-field mobility.
    #[pyo3(signature = (moments = "FT", lubrication = true, pair_tolerance = None))]
    fn resistance<'py>(
        &self,
        py: Python<'py>,
        moments: &str,
        lubrication: bool,
        pair_tolerance: Option<f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let m = self::moments(moments)?;
        // without lubrication, R = M^-1
        let lub = match lubrication_settings(lubrication, pair_tolerance)? {
            _ if !lubrication => Lubrication::none(),
            lub => lub,
        };
        let s = &self.system;
        matrix(
            py,
            py.detach(|| s.resistance(m, &lub)).map_err(value_error)?,
        )
    }

    /// The Brownian drift `div M` (3N at F, 6N at FT: rows U then Omega), from the
    /// generated divergence kernels.
    #[pyo3(signature = (moments = "F"))]
    fn divergence<'py>(
        &self,
        py: Python<'py>,
        moments: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let m = self::moments(moments)?;
        if m == Moments::FTS {
            return Err(PyValueError::new_err(
                "the divergence is of the F or FT mobility",
            ));
        }
        let s = &self.system;
        Ok(PyArray1::from_vec(py, py.detach(|| s.divergence_at(m))))
    }

    /// Overdamped Brownian dynamics (see the stub for the options); returns the frames,
    /// `(frames, N, 3)` at F and `(frames, N, 7)` at FT (centre, then orientation
    /// quaternion w, x, y, z).
    #[pyo3(signature = (steps, dt, kt = 1.0, seed = 0, *, moments = "F", weight = 0.0, repulsion_strength = 0.0, debye_length = 1.0, torque = None, trap = 0.0, scheme = "euler-maruyama", lanczos = None, drift = true, lubrication = false, rfd_step = 1e-3, pair_tolerance = None, every = 1, max_rejections = 1000, hydrodynamics = true))]
    #[allow(clippy::too_many_arguments)]
    fn brownian<'py>(
        &self,
        py: Python<'py>,
        steps: usize,
        dt: f64,
        kt: f64,
        seed: u64,
        moments: &str,
        weight: f64,
        repulsion_strength: f64,
        debye_length: f64,
        torque: Option<[f64; 3]>,
        trap: f64,
        scheme: &str,
        lanczos: Option<f64>,
        drift: bool,
        lubrication: bool,
        rfd_step: f64,
        pair_tolerance: Option<f64>,
        every: usize,
        max_rejections: usize,
        hydrodynamics: bool,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let m = self::moments(moments)?;
        let lub = lubrication_settings(lubrication, pair_tolerance)?;
        let scheme = match scheme {
            "euler-maruyama" | "euler_maruyama" => Scheme::EulerMaruyama,
            "fixman" => Scheme::FixmanMidpoint,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "scheme = {scheme:?}: must be \"euler-maruyama\" or \"fixman\""
                )))
            }
        };
        let bd = Brownian {
            kt,
            dt,
            drift,
            forces: ExternalForces {
                weight,
                strength: repulsion_strength,
                debye: debye_length,
                trap,
                torque: torque.unwrap_or([0.0; 3]),
            },
            noise: match lanczos {
                None => Noise::Cholesky,
                Some(tol) => Noise::Lanczos { tol },
            },
            hydrodynamics,
            moments: m,
            scheme,
            lubrication: lubrication.then_some(LubricatedDynamics {
                lubrication: lub,
                rfd_step,
            }),
        };
        let run = Run {
            steps,
            every,
            seed,
            max_rejections,
        };
        let n = self.system.len();
        let width = if m == Moments::FT { 7 } else { 3 };
        let system = self.system.clone();
        let frames = py
            .detach(|| {
                let mut out = Vec::with_capacity((steps / every.max(1) + 1) * n * width);
                system
                    .brownian_run(&bd, &run, |_, s, q| {
                        for (p, q) in s.particles().iter().zip(q) {
                            out.extend(p.x);
                            if width == 7 {
                                out.extend(q);
                            }
                        }
                    })
                    .map(|_| out)
            })
            .map_err(value_error)?;
        let count = frames.len() / (n * width);
        let a = Array3::from_shape_vec((count, n, width), frames).map_err(value_error)?;
        Ok(PyArray3::from_owned_array(py, a))
    }

    fn __repr__(&self) -> String {
        format!(
            "stokesian.System({} spheres, confinement {:?}, viscosity {})",
            self.system.len(),
            self.system.confinement(),
            self.system.viscosity()
        )
    }
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

/// libMobility's `NBody` solver with our kernels: Rotne-Prager-Yamakawa in free space
/// (`"open", "open", "open"`) and the Swan-Brady wall mobility above a no-slip wall
/// (`"open", "open", "single_wall"`). See the stub for the interface.
#[pyclass(module = "stokesian")]
struct NBody {
    wall: bool,
    wall_height: f64,
    viscosity: Option<f64>,
    radius: Option<Vec<f64>>,
    angular: bool,
    tolerance: f64,
    rng: ChaCha8Rng,
    system: Option<System>,
    shape: Vec<usize>,
}

impl NBody {
    /// The system, or the error libMobility gives before `setPositions`.
    fn system(&self) -> PyResult<&System> {
        self.system.as_ref().ok_or_else(|| {
            PyValueError::new_err(
                "the number of particles is not set: call initialize and setPositions first",
            )
        })
    }

    /// The moments of this solver: F, or FT with `includeAngular`.
    fn moments(&self) -> Moments {
        if self.angular {
            Moments::FT
        } else {
            Moments::F
        }
    }

    /// `(linear, angular)` shaped like `shape` from a moment-major vector.
    fn outputs<'py>(
        &self,
        py: Python<'py>,
        v: Vec<f64>,
        shape: &[usize],
    ) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
        let n = v.len() / if self.angular { 6 } else { 3 };
        let lin = shaped(py, v[..3 * n].to_vec(), shape)?;
        let ang = if self.angular {
            Some(shaped(py, v[3 * n..].to_vec(), shape)?)
        } else {
            None
        };
        Ok((lin, ang))
    }

    /// `prefactor M^{1/2} W`, moment-major, `W` standard normal from this solver's
    /// generator, by Lanczos to the tolerance of `initialize`.
    fn sqrt_m_w(&mut self, py: Python<'_>, prefactor: f64) -> PyResult<Vec<f64>> {
        let m = self.moments();
        let system = self.system()?.clone();
        let w: Vec<f64> = (0..m.per_particle() * system.len())
            .map(|_| self.rng.sample::<f64, _>(StandardNormal))
            .collect();
        let tol = self.tolerance;
        let (y, _) = py
            .detach(|| lanczos_sqrt(|x| system.apply(m, x), &w, tol, w.len()))
            .map_err(value_error)?;
        Ok(y.into_iter().map(|v| v * prefactor).collect())
    }

    /// `M [F; T]` (moment-major) and the shape of the outputs, from optional forces and
    /// torques.
    fn m_dot(
        &self,
        py: Python<'_>,
        forces: Option<Floats>,
        torques: Option<Floats>,
    ) -> PyResult<(Vec<f64>, Option<Vec<usize>>)> {
        let system = self.system()?;
        let n = system.len();
        if torques.is_some() && !self.angular {
            return Err(PyValueError::new_err(
                "torques given, but the solver was initialized without includeAngular: \
                 call initialize(..., includeAngular=True) to use torques",
            ));
        }
        let shape = forces.as_ref().or(torques.as_ref()).map(|a| a.shape());
        let mut x = match &forces {
            Some(f) => vec_of(n, "forces", f)?,
            None => vec![0.0; 3 * n],
        };
        if self.angular {
            match &torques {
                Some(t) => x.extend(vec_of(n, "torques", t)?),
                None => x.extend(vec![0.0; 3 * n]),
            }
        }
        if let Some((i, v)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "force or torque component {i} is {v}, not a finite number"
            )));
        }
        let m = self.moments();
        Ok((py.detach(|| system.apply(m, &x)), shape))
    }
}

#[pymethods]
impl NBody {
    /// Always double precision.
    #[classattr]
    #[allow(non_upper_case_globals)]
    const precision: &'static str = "double";

    #[new]
    #[pyo3(signature = (periodicityX, periodicityY, periodicityZ))]
    #[allow(non_snake_case)]
    fn new(periodicityX: &str, periodicityY: &str, periodicityZ: &str) -> PyResult<Self> {
        let wall = match (periodicityX, periodicityY, periodicityZ) {
            ("open", "open", "open") => false,
            ("open", "open", "single_wall") => true,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "NBody supports periodicity (\"open\", \"open\", \"open\") (free space) \
                     and (\"open\", \"open\", \"single_wall\") (a no-slip wall below the \
                     particles); found ({periodicityX:?}, {periodicityY:?}, \
                     {periodicityZ:?}): periodic boundaries and two walls are not \
                     implemented"
                )))
            }
        };
        Ok(NBody {
            wall,
            wall_height: 0.0,
            viscosity: None,
            radius: None,
            angular: false,
            tolerance: 1e-4,
            rng: ChaCha8Rng::seed_from_u64(0),
            system: None,
            shape: Vec::new(),
        })
    }

    /// libMobility's NBody parameters: only `wallHeight` matters here.
    #[pyo3(signature = (algorithm = "advise", Nbatch = -1, NperBatch = -1, wallHeight = Some(0.0), delta = None))]
    #[allow(non_snake_case)]
    fn setParameters(
        &mut self,
        algorithm: &str,
        Nbatch: i64,
        NperBatch: i64,
        wallHeight: Option<f64>,
        delta: Option<f64>,
    ) -> PyResult<()> {
        let _ = (Nbatch, NperBatch, delta);
        if !["advise", "naive", "fast", "block"].contains(&algorithm) {
            return Err(PyValueError::new_err(format!(
                "algorithm = {algorithm:?}: must be \"advise\", \"naive\", \"fast\" or \"block\" \
                 (accepted for libMobility's scripts; every one computes the same here)"
            )));
        }
        let h = wallHeight.unwrap_or(0.0);
        if !h.is_finite() {
            return Err(PyValueError::new_err(format!(
                "wallHeight = {h}: must be a finite number"
            )));
        }
        if h != 0.0 && !self.wall {
            return Err(PyValueError::new_err(
                "wallHeight applies only with periodicityZ = \"single_wall\"",
            ));
        }
        self.wall_height = h;
        Ok(())
    }

    /// Viscosity, radius (one, or one per particle), angular velocities, Lanczos
    /// tolerance and the seed of the noise (None: from the operating system).
    #[pyo3(signature = (viscosity, hydrodynamicRadius, includeAngular = false, tolerance = 1e-4, seed = None))]
    #[allow(non_snake_case)]
    fn initialize(
        &mut self,
        viscosity: f64,
        hydrodynamicRadius: &Bound<'_, PyAny>,
        includeAngular: bool,
        tolerance: f64,
        seed: Option<u64>,
    ) -> PyResult<()> {
        if !(viscosity > 0.0 && viscosity.is_finite()) {
            return Err(value_error(stokesian::InputError::BadViscosity(viscosity)));
        }
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "tolerance = {tolerance}: must be a positive finite number"
            )));
        }
        let radius = match hydrodynamicRadius.extract::<f64>() {
            Ok(a) => vec![a],
            Err(_) => {
                let a: Floats = hydrodynamicRadius.extract().map_err(|_| {
                    PyTypeError::new_err("hydrodynamicRadius: a number or an array of N numbers")
                })?;
                if a.shape().len() != 1 {
                    return Err(PyValueError::new_err(format!(
                        "hydrodynamicRadius: a number or an array of N numbers, found shape {:?}",
                        a.shape()
                    )));
                }
                a.values().into_owned()
            }
        };
        self.viscosity = Some(viscosity);
        self.radius = Some(radius);
        self.angular = includeAngular;
        self.tolerance = tolerance;
        self.rng = match seed {
            Some(s) => ChaCha8Rng::seed_from_u64(s),
            None => ChaCha8Rng::seed_from_u64(rand::thread_rng().gen()),
        };
        self.system = None;
        Ok(())
    }

    /// The positions, `(N, 3)` or `(3N,)`; later outputs take this shape. Invalid
    /// positions raise ValueError and leave the previous ones in place.
    #[allow(non_snake_case)]
    fn setPositions(&mut self, py: Python<'_>, positions: Floats) -> PyResult<()> {
        let (Some(eta), Some(radius)) = (self.viscosity, self.radius.clone()) else {
            return Err(PyValueError::new_err("call initialize before setPositions"));
        };
        let shape = positions.shape();
        let n = rows_of_three("positions", &shape)?;
        let a = if radius.len() == 1 {
            vec![radius[0]; n]
        } else if radius.len() == n {
            radius
        } else {
            return Err(PyValueError::new_err(format!(
                "{} hydrodynamic radii for {n} particles",
                radius.len()
            )));
        };
        let x = positions.values();
        let ps: Vec<Particle> = (0..n)
            .map(|i| Particle {
                x: [x[3 * i], x[3 * i + 1], x[3 * i + 2]],
                a: a[i],
            })
            .collect();
        let conf = if self.wall {
            Confinement::Wall {
                height: self.wall_height,
            }
        } else {
            Confinement::Free
        };
        // on an error the previous positions stay
        let system = py
            .detach(|| System::new(conf, eta, ps, false))
            .map_err(value_error)?;
        self.system = Some(system);
        self.shape = shape;
        Ok(())
    }

    /// `(linear, angular) = M [F; T]`.
    #[pyo3(signature = (forces = None, torques = None))]
    #[allow(non_snake_case)]
    fn Mdot<'py>(
        &self,
        py: Python<'py>,
        forces: Option<Floats>,
        torques: Option<Floats>,
    ) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
        let (v, shape) = self.m_dot(py, forces, torques)?;
        let shape = shape
            .ok_or_else(|| PyValueError::new_err("Mdot needs forces or torques (at least one)"))?;
        self.outputs(py, v, &shape)
    }

    /// `(linear, angular) = prefactor M^{1/2} W`.
    #[pyo3(signature = (prefactor = 1.0))]
    #[allow(non_snake_case)]
    fn sqrtMdotW<'py>(
        &mut self,
        py: Python<'py>,
        prefactor: f64,
    ) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
        let v = self.sqrt_m_w(py, prefactor)?;
        let shape = self.shape.clone();
        self.outputs(py, v, &shape)
    }

    /// `(linear, angular) = prefactor div M`.
    #[pyo3(signature = (prefactor = 1.0))]
    #[allow(non_snake_case)]
    fn divM<'py>(
        &self,
        py: Python<'py>,
        prefactor: f64,
    ) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
        let system = self.system()?;
        let m = self.moments();
        let d = py.detach(|| system.divergence_at(m));
        self.outputs(
            py,
            d.into_iter().map(|v| v * prefactor).collect(),
            &self.shape,
        )
    }

    /// `M [F; T] + sqrt(2 kbt / dt) M^{1/2} W + kbt div M`.
    #[pyo3(signature = (dt, kbt, forces = None, torques = None))]
    #[allow(non_snake_case)]
    fn LangevinVelocities<'py>(
        &mut self,
        py: Python<'py>,
        dt: f64,
        kbt: f64,
        forces: Option<Floats>,
        torques: Option<Floats>,
    ) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "dt = {dt}: the time step must be a positive finite number"
            )));
        }
        if !(kbt >= 0.0 && kbt.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "kbt = {kbt}: the thermal energy must be a finite number >= 0"
            )));
        }
        let (mut v, shape) = self.m_dot(py, forces, torques)?;
        if kbt != 0.0 {
            let noise = self.sqrt_m_w(py, (2.0 * kbt / dt).sqrt())?;
            let system = self.system()?;
            let m = self.moments();
            let div = py.detach(|| system.divergence_at(m));
            for ((v, w), d) in v.iter_mut().zip(noise).zip(div) {
                *v += w + kbt * d;
            }
        }
        let shape = shape.unwrap_or_else(|| self.shape.clone());
        self.outputs(py, v, &shape)
    }

    /// Forget the positions (and parameters): `initialize` and `setPositions` again
    /// before the next product.
    fn clean(&mut self) {
        self.system = None;
        self.viscosity = None;
        self.radius = None;
    }
}

/// The module.
#[pymodule]
fn _stokesian(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySystem>()?;
    m.add_class::<NBody>()?;
    Ok(())
}
