//! `stokesian.System`: the whole solver over the library's `System`.

use super::*;

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
pub(crate) struct PySystem {
    system: System,
}

#[pymethods]
impl PySystem {
    #[new]
    #[pyo3(signature = (positions, radii, *, confinement = "wall", params = None, viscosity = 1.0, boundary_height = None, lam = None, gap = None, allow_overlap = false, overlap = None, r#box = None, periodic_tolerance = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        positions: Floats,
        radii: &Bound<'_, PyAny>,
        confinement: &str,
        params: Option<&Bound<'_, PyDict>>,
        viscosity: f64,
        boundary_height: Option<f64>,
        lam: Option<f64>,
        gap: Option<f64>,
        allow_overlap: bool,
        overlap: Option<&str>,
        r#box: Option<Vec<f64>>,
        periodic_tolerance: Option<f64>,
    ) -> PyResult<Self> {
        // in the order of ALIASES
        let conf = declared_confinement(confinement, params, [boundary_height, lam, gap])?;
        let ps = particles(&positions, radii)?;
        let overlap = match (overlap, allow_overlap) {
            (None, allow) => Overlap::from(allow),
            (Some(_), true) => {
                return Err(input_error(
                    "allow_overlap=True is overlap=\"far\": give one of them",
                ))
            }
            (Some("refuse"), false) => Overlap::Refuse,
            (Some("far"), false) => Overlap::Far,
            (Some("rpy"), false) => Overlap::Rpy,
            (Some(other), false) => {
                return Err(input_error(format!(
                    "overlap = {other:?}: expected \"refuse\", \"far\" or \"rpy\""
                )))
            }
        };
        let system = py
            .detach(|| System::new(conf, viscosity, ps, overlap))
            .map_err(input_error)?;
        let system = match (r#box, periodic_tolerance) {
            (None, None) => system,
            (None, Some(_)) => {
                return Err(input_error(
                    "periodic_tolerance is for a periodic box: give box too",
                ))
            }
            (Some(b), tol) => {
                let lengths = match *b.as_slice() {
                    [lx, ly, lz] => BoxLengths::Triply([lx, ly, lz]),
                    [lx, ly] => BoxLengths::Lateral([lx, ly]),
                    _ => {
                        return Err(input_error(format!(
                            "box = {b:?}: expected three lengths (Lx, Ly, Lz), a triply periodic box, or two (Lx, Ly), periodic along a wall or a slit's walls"
                        )))
                    }
                };
                let bx = PeriodicBox {
                    lengths,
                    tolerance: tol.unwrap_or(PeriodicBox::TOLERANCE),
                };
                py.detach(|| system.periodic(bx)).map_err(input_error)?
            }
        };
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

    /// The confinement's name (one of `stokesian.confinements()`).
    #[getter]
    fn confinement(&self) -> &'static str {
        self.system.confinement().name()
    }

    /// The confinement's parameters by name, defaults filled in.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, value) in self.system.confinement().params() {
            d.set_item(name, value)?;
        }
        Ok(d)
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
        s.check_overlap(m).map_err(input_error)?;
        // assembled straight into NumPy's array (column-major: Fortran order), whose
        // allocator asks for transparent huge pages for large arrays, as
        // `stokesian::linalg::LargeMatrix` does for the command line
        let dim = m.per_particle() * s.len();
        let out = PyArray2::<f64>::zeros(py, [dim, dim], true);
        {
            let mut values = out.readwrite();
            let values = values.as_slice_mut().map_err(input_error)?;
            py.detach(|| s.mobility_into(m, values));
        }
        Ok(out)
    }

    /// `M x` without forming `M`: `x` of length kN, moment-major; `precision`
    /// `"single"` runs the `f32` lanes.
    #[pyo3(signature = (moments, x, *, precision = "double", fmm = None))]
    fn apply<'py>(
        &self,
        py: Python<'py>,
        moments: &str,
        x: Floats,
        precision: &str,
        fmm: Option<f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let m = self::moments(moments)?;
        let p = self::precision(precision)?;
        self.system.check_overlap(m).map_err(input_error)?;
        let expected = m.per_particle() * self.system.len();
        let x = x.values();
        if x.len() != expected {
            return Err(input_error(format!(
                "x has {} entries; {moments} for {} particles needs {expected}",
                x.len(),
                self.system.len()
            )));
        }
        let s = &self.system;
        let x: &[f64] = &x;
        let out = match fmm {
            Some(eps) => py.detach(|| s.apply_fmm(m, x, eps)).map_err(input_error)?,
            None => py.detach(|| s.apply_with(m, x, Isa::best(), p)),
        };
        Ok(PyArray1::from_vec(py, out))
    }

    /// Velocities `(N, 3)` and rotation rates `(N, 3)` (None at the F level) of spheres
    /// under `forces` and `torques` (`(N, 3)` or `(3N,)`) and the imposed strain.
    #[pyo3(signature = (forces, torques = None, strain = None, lubrication = false, pair_tolerance = None, fmm = None))]
    #[allow(clippy::too_many_arguments)]
    fn velocities<'py>(
        &self,
        py: Python<'py>,
        forces: Floats,
        torques: Option<Floats>,
        strain: Option<Floats>,
        lubrication: bool,
        pair_tolerance: Option<f64>,
        fmm: Option<f64>,
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
        if fmm.is_some() && (lubrication || m == Moments::FTS) {
            return Err(input_error(
                "fmm: the fast product is the far-field product of forces and torques \
                 (without lubrication or strain)",
            ));
        }
        let fast = match fmm {
            Some(eps) => Some(self.system.clone().with_fmm(eps).map_err(input_error)?),
            None => None,
        };
        let s = fast.as_ref().unwrap_or(&self.system);
        let v = py
            .detach(|| s.velocities(m, &x, &e, lubrication.then_some(&lub)))
            .map_err(input_error)?;
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
            py.detach(|| s.resistance(m, &lub)).map_err(input_error)?,
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
            return Err(input_error("the divergence is of the F or FT mobility"));
        }
        let s = &self.system;
        s.check_drift().map_err(input_error)?;
        Ok(PyArray1::from_vec(py, py.detach(|| s.divergence_at(m))))
    }

    /// Overdamped Brownian dynamics (see the stub for the options); returns the frames,
    /// `(frames, N, 3)` at F and `(frames, N, 7)` at FT (centre, then orientation
    /// quaternion w, x, y, z).
    #[pyo3(signature = (steps, dt, kt = 1.0, seed = 0, *, moments = "F", weight = 0.0, repulsion_strength = 0.0, debye_length = 1.0, torque = None, trap = 0.0, scheme = "euler-maruyama", lanczos = None, fmm = None, drift = true, lubrication = false, rfd_step = 1e-3, pair_tolerance = None, every = 1, max_rejections = 1000, hydrodynamics = true))]
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
        fmm: Option<f64>,
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
                return Err(input_error(format!(
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
        let system =
            match fmm {
                Some(_) if lanczos.is_none() => return Err(input_error(
                    "fmm: the fast product serves the Lanczos noise's products (give lanczos=TOL)",
                )),
                Some(eps) => self.system.clone().with_fmm(eps).map_err(input_error)?,
                None => self.system.clone(),
            };
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
            .map_err(input_error)?;
        let count = frames.len() / (n * width);
        let a = Array3::from_shape_vec((count, n, width), frames).map_err(input_error)?;
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
