//! `stokesian.NBody`: libMobility's interface over the library's `System`.

use super::*;

/// libMobility's `NBody` solver with our kernels: Rotne-Prager-Yamakawa in free space
/// (`"open", "open", "open"`) and the Swan-Brady wall mobility above a no-slip wall
/// (`"open", "open", "single_wall"`). See the stub for the interface.
#[pyclass(module = "stokesian")]
pub(crate) struct NBody {
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
