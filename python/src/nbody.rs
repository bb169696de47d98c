//! `stokesian.NBody`: libMobility's interface over the library's `System`, in batches.
//!
//! Batches (libMobility's `Nbatch`, `NperBatch`): the particles are `Nbatch` consecutive
//! groups of `NperBatch`, independent systems without any interaction between them, so
//! the mobility is block diagonal and each product, square root and divergence is taken
//! batch by batch (the square root of a block-diagonal matrix is block diagonal).

use super::*;

/// The systems of the batches, in order, each with its particles' slice.
struct Batches {
    systems: Vec<System>,
}

impl Batches {
    /// Number of particles of all batches.
    fn len(&self) -> usize {
        self.systems.iter().map(System::len).sum()
    }

    /// `f` batch by batch: each batch's system with its slice of the moment-major vector
    /// `x` (`k` moments of 3 per particle: all batches' first moment, then the second),
    /// and its result (the same layout within the batch) put back in the whole layout.
    /// One batch: `f` of the whole vector, untouched.
    fn each(&self, k: usize, x: &[f64], f: impl Fn(&System, &[f64]) -> Vec<f64>) -> Vec<f64> {
        if let [system] = self.systems.as_slice() {
            return f(system, x);
        }
        let n = self.len();
        let range =
            |q: usize, start: usize, len: usize| 3 * (q * n + start)..3 * (q * n + start + len);
        let mut out = vec![0.0; 3 * k * n];
        let mut start = 0;
        for system in &self.systems {
            let len = system.len();
            let xb: Vec<f64> = if x.is_empty() {
                Vec::new()
            } else {
                (0..k)
                    .flat_map(|q| x[range(q, start, len)].iter().copied())
                    .collect()
            };
            let yb = f(system, &xb);
            for q in 0..k {
                out[range(q, start, len)].copy_from_slice(&yb[3 * q * len..3 * (q + 1) * len]);
            }
            start += len;
        }
        out
    }

    /// `M x`, moment-major.
    fn apply(&self, m: Moments, x: &[f64]) -> Vec<f64> {
        self.each(m.per_particle() / 3, x, |s, xb| s.apply(m, xb))
    }

    /// A square-root factor of `M` applied to `w`, batch by batch
    /// (`System::sqrt_apply`: better conditioned where spheres are damped).
    fn sqrt_apply(
        &self,
        m: Moments,
        w: &[f64],
        tol: f64,
    ) -> Result<Vec<f64>, stokesian::LanczosError> {
        let failed = std::cell::RefCell::new(None);
        let y = self.each(m.per_particle() / 3, w, |s, wb| {
            match s.sqrt_apply(m, wb, tol) {
                Ok((y, _)) => y,
                Err(e) => {
                    failed.borrow_mut().get_or_insert(e);
                    vec![0.0; wb.len()]
                }
            }
        });
        match failed.into_inner() {
            Some(e) => Err(e),
            None => Ok(y),
        }
    }

    /// `div M`, moment-major (of the damped mobility where a sphere cuts the wall); an
    /// error where `System::check_drift` fails.
    fn divergence(&self, m: Moments) -> Result<Vec<f64>, String> {
        for s in &self.systems {
            s.check_drift().map_err(|e| e.to_string())?;
        }
        Ok(self.each(m.per_particle() / 3, &[], |s, _| s.divergence_at(m)))
    }
}

/// The system of one batch, overlaps evaluated as libMobility's NBody does: the RPY
/// overlap forms for overlapping spheres, spheres cutting the wall damped
/// (`stokesian::Overlap::Rpy`; `divM` is the drift of the damped mobility).
fn batch_system(
    confinement: Confinement,
    viscosity: f64,
    particles: Vec<Particle>,
) -> Result<System, stokesian::InputError> {
    System::new(confinement, viscosity, particles, Overlap::Rpy)
}

/// libMobility's `NBody` solver with our kernels: Rotne-Prager-Yamakawa in free space
/// (`"open", "open", "open"`) and the Swan-Brady wall mobility above a no-slip wall
/// (`"open", "open", "single_wall"`), and the periodic boxes. See the stub for the
/// interface.
#[pyclass(module = "stokesian")]
pub(crate) struct NBody {
    wall: bool,
    /// `("periodic", "periodic", "two_walls")`: a slit periodic along its walls, at `zmin`
    /// and `zmax` (as libMobility's DPStokes takes them); `wall` is set too (the lower).
    two_walls: bool,
    /// The upper wall's height, with `two_walls`.
    top: Option<f64>,
    /// `("periodic", "periodic", "periodic")`: a triply periodic box, whose lengths
    /// `setParameters` gives (`Lx`, `Ly`, `Lz`, as libMobility's PSE takes them); with
    /// `wall`, `("periodic", "periodic", "single_wall")`: periodic along the wall (`Lx`,
    /// `Ly` and the wall at `zmin`, as libMobility's DPStokes takes them).
    periodic: bool,
    lengths: Option<BoxLengths>,
    /// The wall's height; None until `setParameters` gives it (required with a wall).
    wall_height: Option<f64>,
    /// `Nbatch` and `NperBatch` as given (negative: libMobility's default).
    batch: (i64, i64),
    /// The fast product's tolerance (`setParameters(fmm_tolerance=...)`): `Mdot` and the
    /// Lanczos products of `sqrtMdotW` by `System::with_fmm`.
    fmm: Option<f64>,
    viscosity: Option<f64>,
    radius: Option<Vec<f64>>,
    angular: bool,
    tolerance: f64,
    rng: ChaCha8Rng,
    batches: Option<Batches>,
    /// The positions' shape and kind of array: those of the outputs without forces.
    shape: Vec<usize>,
    kind: Kind,
}

/// Velocities and angular velocities, each in the shape and kind asked for.
type Output<'py> = (Bound<'py, PyAny>, Option<Bound<'py, PyAny>>);

/// `M [F; T]` (moment-major) with what the outputs take from the inputs: the shapes of
/// the forces and of the torques given, and the kind of array of the forces (else the
/// torques).
struct Product {
    v: Vec<f64>,
    forces: Option<Vec<usize>>,
    torques: Option<Vec<usize>>,
    kind: Option<Kind>,
}

impl NBody {
    /// The batches, or the error libMobility gives before `setPositions`.
    fn batches(&self) -> PyResult<&Batches> {
        self.batches.as_ref().ok_or_else(|| {
            input_error(
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

    /// `(linear, angular)` from a moment-major vector, the linear part shaped `lin`, the
    /// angular part `ang`, both of the array kind `kind`.
    fn outputs<'py>(
        &self,
        py: Python<'py>,
        v: Vec<f64>,
        (lin, ang): (&[usize], &[usize]),
        kind: &Kind,
    ) -> PyResult<Output<'py>> {
        let n = v.len() / if self.angular { 6 } else { 3 };
        let linear = kind.wrap(shaped(py, v[..3 * n].to_vec(), lin)?)?;
        let angular = if self.angular {
            Some(kind.wrap(shaped(py, v[3 * n..].to_vec(), ang)?)?)
        } else {
            None
        };
        Ok((linear, angular))
    }

    /// `prefactor M^{1/2} W`, moment-major, `W` standard normal from this solver's
    /// generator, by Lanczos to the tolerance of `initialize`.
    fn sqrt_m_w(&mut self, py: Python<'_>, prefactor: f64) -> PyResult<Vec<f64>> {
        let m = self.moments();
        let len = m.per_particle() * self.batches()?.len();
        let w: Vec<f64> = (0..len)
            .map(|_| self.rng.sample::<f64, _>(StandardNormal))
            .collect();
        let tol = self.tolerance;
        let batches = self.batches()?;
        let y = py
            .detach(|| batches.sqrt_apply(m, &w, tol))
            .map_err(input_error)?;
        Ok(y.into_iter().map(|v| v * prefactor).collect())
    }

    /// `M [F; T]` from optional forces and torques (zero where not given).
    fn m_dot(
        &self,
        py: Python<'_>,
        forces: Option<Floats>,
        torques: Option<Floats>,
    ) -> PyResult<Product> {
        let batches = self.batches()?;
        let n = batches.len();
        if torques.is_some() && !self.angular {
            return Err(input_error(
                "torques given, but the solver was initialized without includeAngular: \
                 call initialize(..., includeAngular=True) to use torques",
            ));
        }
        let forces_shape = forces.as_ref().map(Floats::shape);
        let torques_shape = torques.as_ref().map(Floats::shape);
        let kind = forces
            .as_ref()
            .or(torques.as_ref())
            .map(|a| a.kind.clone_ref(py));
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
            return Err(input_error(format!(
                "force or torque component {i} is {v}, not a finite number"
            )));
        }
        let m = self.moments();
        let v = py.detach(|| batches.apply(m, &x));
        Ok(Product {
            v,
            forces: forces_shape,
            torques: torques_shape,
            kind,
        })
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
        let (wall, periodic, two_walls) = match (periodicityX, periodicityY, periodicityZ) {
            ("open", "open", "open") => (false, false, false),
            ("open", "open", "single_wall") => (true, false, false),
            ("periodic", "periodic", "periodic") => (false, true, false),
            ("periodic", "periodic", "single_wall") => (true, true, false),
            ("periodic", "periodic", "two_walls") => (true, true, true),
            _ => {
                return Err(input_error(format!(
                    "NBody supports periodicity (\"open\", \"open\", \"open\") (free space), \
                     (\"open\", \"open\", \"single_wall\") (a no-slip wall below the \
                     particles), (\"periodic\", \"periodic\", \"periodic\") (a triply \
                     periodic box, as libMobility's PSE) and (\"periodic\", \"periodic\", \
                     \"single_wall\") or (\"periodic\", \"periodic\", \"two_walls\") \
                     (periodic along the wall or the walls, as libMobility's DPStokes); \
                     found ({periodicityX:?}, {periodicityY:?}, {periodicityZ:?}): two walls \
                     without periodic x and y, an open z with periodic x and y, and other \
                     mixes are not implemented"
                )))
            }
        };
        Ok(NBody {
            wall,
            two_walls,
            top: None,
            periodic,
            lengths: None,
            wall_height: None,
            fmm: None,
            batch: (-1, -1),
            viscosity: None,
            radius: None,
            angular: false,
            tolerance: 1e-4,
            rng: ChaCha8Rng::seed_from_u64(0),
            batches: None,
            shape: Vec::new(),
            kind: Kind::NUMPY,
        })
    }

    /// libMobility's NBody parameters: the wall's height (required with a wall, refused
    /// without), the batches (checked against the number of particles by
    /// `setPositions`); the algorithm and `delta` are accepted for libMobility's scripts.
    #[pyo3(signature = (algorithm = "advise", Nbatch = -1, NperBatch = -1, wallHeight = None, delta = 1e-3, *, Lx = None, Ly = None, Lz = None, psi = None, shearStrain = None, zmin = None, zmax = None, allowChangingBoxSize = false, allowUnsafeForces = false, fmm_tolerance = None))]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn setParameters(
        &mut self,
        algorithm: &str,
        Nbatch: i64,
        NperBatch: i64,
        wallHeight: Option<f64>,
        delta: f64,
        Lx: Option<f64>,
        Ly: Option<f64>,
        Lz: Option<f64>,
        psi: Option<f64>,
        shearStrain: Option<f64>,
        zmin: Option<f64>,
        zmax: Option<f64>,
        allowChangingBoxSize: bool,
        allowUnsafeForces: bool,
        fmm_tolerance: Option<f64>,
    ) -> PyResult<()> {
        // the fast product (in a periodic box, the box's own fast product with its
        // lattice sums to the tolerance: `System::with_fmm`): its tolerance checked here
        if let Some(eps) = fmm_tolerance {
            stokesian::FastProduct::new(eps).map_err(input_error)?;
        }
        // the box: libMobility's PSE names for a triply periodic one, DPStokes' along a
        // wall; required there, refused otherwise
        let lengths = match (self.periodic, self.wall, Lx, Ly, Lz) {
            (true, false, Some(x), Some(y), Some(z)) => Some(BoxLengths::Triply([x, y, z])),
            (true, false, ..) => {
                return Err(input_error(
                    "Lx, Ly and Lz are required for a periodic box: setParameters(Lx=..., \
                     Ly=..., Lz=...)",
                ))
            }
            (true, true, Some(x), Some(y), None) => Some(BoxLengths::Lateral([x, y])),
            (true, true, ..) => {
                return Err(input_error(
                    "Lx and Ly (and no Lz) are required for a box periodic along the wall: \
                     setParameters(Lx=..., Ly=..., zmin=...)",
                ))
            }
            (false, _, None, None, None) => None,
            (false, ..) => {
                return Err(input_error(
                    "Lx, Ly, Lz apply only with periodicity (\"periodic\", \"periodic\", \
                     \"periodic\") or (\"periodic\", \"periodic\", \"single_wall\")",
                ))
            }
        };
        // DPStokes' wall at zmin (with one wall the top of its grid zmax changes nothing
        // here, nor do its box rounding and its check of the net force in an open z); with
        // two walls the upper one at zmax
        let _ = (allowChangingBoxSize, allowUnsafeForces);
        let top = match (self.two_walls, zmin, zmax) {
            (true, Some(lo), Some(hi)) if lo < hi && hi.is_finite() => Some(hi),
            (true, Some(lo), Some(hi)) => {
                return Err(input_error(format!(
                    "zmin = {lo}, zmax = {hi}: the walls need zmin < zmax, both finite"
                )))
            }
            (true, ..) => {
                return Err(input_error(
                    "zmin and zmax, the walls' heights, are required with two walls: \
                     setParameters(Lx=..., Ly=..., zmin=..., zmax=...)",
                ))
            }
            (false, ..) => None,
        };
        let wallHeight = match (self.periodic && self.wall, zmin, wallHeight) {
            (false, Some(_), _) => {
                return Err(input_error(
                    "zmin applies only with periodicity (\"periodic\", \"periodic\", \
                     \"single_wall\") (the wall's height; wallHeight otherwise)",
                ))
            }
            (true, Some(z), Some(h)) if z != h => {
                return Err(input_error(format!(
                    "zmin = {z} and wallHeight = {h}: both are the wall's height; give one"
                )))
            }
            (_, Some(z), _) => Some(z),
            (_, None, h) => h,
        };
        // PSE's splitting parameter changes only how the same sum is split
        if let Some(p) = psi {
            if !(p >= 0.0 && p.is_finite()) {
                return Err(input_error(format!(
                    "psi = {p}: must be a non-negative finite number"
                )));
            }
        }
        if shearStrain.is_some_and(|s| s != 0.0) {
            return Err(input_error(
                "shearStrain: sheared (Lees-Edwards) boxes are not implemented; only 0",
            ));
        }
        // the random finite difference's step: divM is exact here
        let _ = delta;
        if !["advise", "naive", "fast", "block"].contains(&algorithm) {
            return Err(input_error(format!(
                "algorithm = {algorithm:?}: must be \"advise\", \"naive\", \"fast\" or \"block\" \
                 (accepted for libMobility's scripts; every one computes the same here)"
            )));
        }
        match (self.wall, wallHeight) {
            (true, None) => {
                return Err(input_error(
                    "wallHeight is required for a bottom wall (periodicityZ = \"single_wall\"): \
                     setParameters(wallHeight=...) (zmin=... with periodic x and y)",
                ))
            }
            (false, Some(_)) => {
                return Err(input_error(
                    "wallHeight applies only with periodicityZ = \"single_wall\"",
                ))
            }
            (_, Some(h)) if !h.is_finite() => {
                return Err(input_error(format!(
                    "wallHeight = {h}: must be a finite number"
                )))
            }
            _ => {}
        }
        self.wall_height = wallHeight;
        self.top = top;
        self.lengths = lengths;
        self.batch = (Nbatch, NperBatch);
        self.fmm = fmm_tolerance;
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
            return Err(input_error(stokesian::InputError::BadViscosity(viscosity)));
        }
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return Err(input_error(format!(
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
                    return Err(input_error(format!(
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
        self.batches = None;
        Ok(())
    }

    /// The positions, `(N, 3)` or `(3N,)`, any kind of array; outputs without forces
    /// take this shape and kind. Invalid positions raise InputError and leave the
    /// previous ones in place.
    #[allow(non_snake_case)]
    fn setPositions(&mut self, py: Python<'_>, positions: Floats) -> PyResult<()> {
        let (Some(eta), Some(radius)) = (self.viscosity, self.radius.clone()) else {
            return Err(input_error("call initialize before setPositions"));
        };
        let shape = positions.shape();
        let n = rows_of_three("positions", &shape)?;
        // libMobility's batches: a negative Nbatch is one batch, a negative NperBatch all
        // particles in each; Nbatch * NperBatch must be the number of particles
        let (nbatch, per) = self.batch;
        let count = if nbatch < 0 { 1 } else { nbatch as usize };
        let size = if per < 0 { n } else { per as usize };
        if count.checked_mul(size) != Some(n) {
            return Err(input_error(format!(
                "Invalid batch parameters for NBody: Nbatch = {nbatch}, NperBatch = {per} \
                 for {n} particles; Nbatch * NperBatch must be the number of particles (-1: \
                 one batch, or all particles in each; if in doubt, use the defaults)"
            )));
        }
        let a = if radius.len() == 1 {
            vec![radius[0]; n]
        } else if radius.len() == n {
            radius
        } else {
            return Err(input_error(format!(
                "{} hydrodynamic radii for {n} particles",
                radius.len()
            )));
        };
        if self.periodic && self.lengths.is_none() {
            return Err(input_error(
                "the box is required for a periodic solver: call setParameters(Lx=..., \
                 Ly=..., Lz=...) (or Lx, Ly and zmin along a wall) before setPositions",
            ));
        }
        let lengths = self.lengths;
        let fmm = self.fmm;
        let conf = match (self.wall, self.wall_height, self.top) {
            (false, ..) => Confinement::Free,
            (true, Some(height), Some(top)) => Confinement::Slit {
                height,
                gap: top - height,
            },
            (true, Some(height), None) if !self.two_walls => Confinement::Wall { height },
            (true, ..) => {
                return Err(input_error(
                    "the walls' heights are required: call setParameters(wallHeight=...) \
                     (zmin=..., and zmax=... with two walls) before setPositions",
                ))
            }
        };
        let x = positions.values();
        let ps: Vec<Particle> = (0..n)
            .map(|i| Particle {
                x: [x[3 * i], x[3 * i + 1], x[3 * i + 2]],
                a: a[i],
            })
            .collect();
        // on an error the previous positions stay
        // no particles: one empty batch, which the library refuses with its own message
        let groups: Vec<&[Particle]> = match n {
            0 => vec![&ps],
            _ => ps.chunks(size).collect(),
        };
        let systems = py
            .detach(|| {
                groups
                    .iter()
                    .enumerate()
                    .map(|(b, batch)| {
                        let s = batch_system(conf, eta, batch.to_vec())
                            .map_err(|e| wall_words(e, b * size))?;
                        let s = match lengths {
                            Some(lengths) => s
                                .periodic(stokesian::PeriodicBox {
                                    lengths,
                                    tolerance: stokesian::PeriodicBox::TOLERANCE,
                                })
                                .map_err(|e| periodic_words(e, b * size))?,
                            None => s,
                        };
                        match fmm {
                            Some(eps) => s.with_fmm(eps).map_err(|e| e.to_string()),
                            None => Ok(s),
                        }
                    })
                    .collect::<Result<Vec<_>, _>>()
            })
            .map_err(input_error)?;
        self.batches = Some(Batches { systems });
        self.shape = shape;
        self.kind = positions.kind;
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
    ) -> PyResult<Output<'py>> {
        let p = self.m_dot(py, forces, torques)?;
        // libMobility: each output shaped like its own input, else like the other one
        let (Some(lin), Some(ang)) = (
            p.forces.clone().or(p.torques.clone()),
            p.torques.or(p.forces),
        ) else {
            return Err(input_error("Mdot needs forces or torques (at least one)"));
        };
        let kind = p.kind.unwrap_or(Kind::NUMPY);
        self.outputs(py, p.v, (&lin, &ang), &kind)
    }

    /// `(linear, angular) = prefactor M^{1/2} W`.
    #[pyo3(signature = (prefactor = 1.0))]
    #[allow(non_snake_case)]
    fn sqrtMdotW<'py>(&mut self, py: Python<'py>, prefactor: f64) -> PyResult<Output<'py>> {
        let v = self.sqrt_m_w(py, prefactor)?;
        self.outputs(py, v, (&self.shape, &self.shape), &self.kind)
    }

    /// `(linear, angular) = prefactor div M`.
    #[pyo3(signature = (prefactor = 1.0))]
    #[allow(non_snake_case)]
    fn divM<'py>(&self, py: Python<'py>, prefactor: f64) -> PyResult<Output<'py>> {
        let batches = self.batches()?;
        let m = self.moments();
        let d = py.detach(|| batches.divergence(m)).map_err(input_error)?;
        self.outputs(
            py,
            d.into_iter().map(|v| v * prefactor).collect(),
            (&self.shape, &self.shape),
            &self.kind,
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
    ) -> PyResult<Output<'py>> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(input_error(format!(
                "dt = {dt}: the time step must be a positive finite number"
            )));
        }
        if !(kbt >= 0.0 && kbt.is_finite()) {
            return Err(input_error(format!(
                "kbt = {kbt}: the thermal energy must be a finite number >= 0"
            )));
        }
        let Product {
            mut v,
            forces,
            torques,
            kind,
        } = self.m_dot(py, forces, torques)?;
        if kbt != 0.0 {
            let noise = self.sqrt_m_w(py, (2.0 * kbt / dt).sqrt())?;
            let batches = self.batches()?;
            let m = self.moments();
            let div = py.detach(|| batches.divergence(m)).map_err(input_error)?;
            for ((v, w), d) in v.iter_mut().zip(noise).zip(div) {
                *v += w + kbt * d;
            }
        }
        // libMobility: each output shaped like its own input, else like the positions
        let lin = forces.unwrap_or_else(|| self.shape.clone());
        let ang = torques.unwrap_or_else(|| self.shape.clone());
        let kind = kind.unwrap_or_else(|| self.kind.clone_ref(py));
        self.outputs(py, v, (&lin, &ang), &kind)
    }

    /// Forget the positions (and parameters): `initialize` and `setPositions` again
    /// before the next product.
    fn clean(&mut self) {
        self.batches = None;
        self.viscosity = None;
        self.radius = None;
    }
}

/// The library's error for particle `offset + index` of a batch, in the words
/// libMobility's users match on for a centre below the wall ("fallen below the wall").
/// A periodic box's error of the batch of particles from `offset` on, naming the
/// particles by their indices among all particles.
fn periodic_words(e: stokesian::PeriodicError, offset: usize) -> String {
    use stokesian::PeriodicError::*;
    match e {
        OwnImage {
            index,
            a,
            axis,
            length,
        } => OwnImage {
            index: offset + index,
            a,
            axis,
            length,
        },
        Overlap {
            first,
            second,
            distance,
            sum,
        } => Overlap {
            first: offset + first,
            second: offset + second,
            distance,
            sum,
        },
        CutsWall { index, a, distance } => CutsWall {
            index: offset + index,
            a,
            distance,
        },
        other => other,
    }
    .to_string()
}

fn wall_words(e: stokesian::InputError, offset: usize) -> String {
    use stokesian::InputError::*;
    match e {
        OutsideFluid {
            index,
            distance,
            boundary,
        } => {
            let side = if boundary.normal[2] < 0.0 {
                "risen above the upper wall"
            } else {
                "fallen below the wall"
            };
            format!(
                "particle {}: the centre has {side}: signed distance {distance} from the \
                 boundary, {boundary}",
                offset + index
            )
        }
        e if offset == 0 => e.to_string(),
        e => format!("batch of particles {offset}..: {e}"),
    }
}
