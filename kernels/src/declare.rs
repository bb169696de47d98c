//! What each Green's function declares about itself, as the generated
//! [`crate::Confinement`] reports it: its named parameters ([`Param`]) and the planes
//! that confine the fluid ([`Boundary`]). The solver, the command line and Python read
//! these instead of knowing any confinement by name.

/// How a parameter changes when lengths are measured in another unit from another
/// origin ([`crate::Confinement::in_units`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Dimension {
    /// A position along the unit direction `d` (a plane's offset `d . x`):
    /// `(p - d . origin) / unit`.
    Position([f64; 3]),
    /// A distance: `p / unit`.
    Length,
    /// A pure number (a viscosity ratio): unchanged.
    Number,
}

/// A named run-time parameter of a confinement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    /// Name: the field of the [`crate::Confinement`] variant, `--param NAME=VALUE` on
    /// the command line, `params={NAME: VALUE}` in Python.
    pub name: &'static str,
    /// What it is, one line.
    pub doc: &'static str,
    /// How it scales with the unit of length.
    pub dimension: Dimension,
    /// The value a user gets without giving it; `None` if it must be given.
    pub default: Option<f64>,
    /// A typical value away from the default (the checks use it).
    pub example: f64,
}

/// What a boundary imposes on the flow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Condition {
    /// No slip: spheres near it take the sphere-wall lubrication along its normal.
    NoSlip,
    /// A flat free surface: no penetration, no tangential stress.
    FreeSurface,
    /// A flat interface with a second liquid: no penetration.
    Interface,
}

impl Condition {
    /// A name for messages and listings.
    pub fn describe(&self) -> &'static str {
        match self {
            Condition::NoSlip => "no slip",
            Condition::FreeSurface => "free surface",
            Condition::Interface => "liquid-liquid interface",
        }
    }
}

/// A plane `normal . x = offset` that confines the fluid to `normal . x > offset`
/// (the normal points into the fluid).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Boundary {
    /// Unit normal, into the fluid.
    pub normal: [f64; 3],
    /// `normal . x` on the plane.
    pub offset: f64,
    /// What it imposes.
    pub condition: Condition,
    /// Whether the Green's function satisfies the condition exactly (the slit's
    /// superposed images satisfy neither wall's no slip exactly).
    pub exact: bool,
}

impl Boundary {
    /// The distance `normal . x - offset` of `x` from the plane: positive in the fluid.
    pub fn distance(&self, x: [f64; 3]) -> f64 {
        along(self.normal, x) - self.offset
    }

    /// Whether the normal is `e3` or `-e3` (a plane `x3 = const`).
    pub fn is_horizontal(&self) -> bool {
        self.normal[0] == 0.0 && self.normal[1] == 0.0
    }

    /// One line: `no slip at x3 = 0 (fluid where x3 > 0)`.
    pub fn describe(&self) -> String {
        let n = self.normal;
        let axis = (0..3).find(|&k| n[k].abs() == 1.0);
        let (lhs, off) = match axis {
            Some(k) => (format!("x{}", k + 1), readable(self.offset * n[k])),
            None => (
                format!("({:.6}, {:.6}, {:.6}) . x", n[0], n[1], n[2]),
                readable(self.offset),
            ),
        };
        let side = match axis {
            Some(k) if n[k] < 0.0 => "<",
            _ => ">",
        };
        let exact = if self.exact { "" } else { ", approximately" };
        format!(
            "{} at {lhs} = {off} (fluid where {lhs} {side} {off}{exact})",
            self.condition.describe()
        )
    }
}

impl std::fmt::Display for Boundary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.describe())
    }
}

/// A number as people read it: plain between 1e-5 and 1e16 in magnitude (and zero),
/// in exponent form outside (a plane at `1e308` is not 309 digits).
pub fn readable(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-5..1e16).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// `n . x`, skipping the zero components of `n` and multiplying by none of `+-1`
/// (so `e3 . x` is `x3` exactly), as the generated kernels compute it.
pub fn along(n: [f64; 3], x: [f64; 3]) -> f64 {
    let mut acc: Option<f64> = None;
    for k in 0..3 {
        let t = if n[k] == 0.0 {
            continue;
        } else if n[k] == 1.0 {
            x[k]
        } else if n[k] == -1.0 {
            -x[k]
        } else {
            n[k] * x[k]
        };
        acc = Some(acc.map_or(t, |a| a + t));
    }
    acc.unwrap_or(0.0)
}

/// A registered confinement's declaration: its name, one line on what it is, and its
/// parameters in order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Declaration {
    /// The name of [`crate::Confinement::name`].
    pub name: &'static str,
    /// One line.
    pub title: &'static str,
    /// Its parameters, in the order of [`crate::Confinement::from_name`].
    pub params: &'static [Param],
}

impl Declaration {
    /// The confinement with the named `values` (each a declared parameter, given at
    /// most once) and the defaults of the others.
    pub fn with(&self, values: &[(&str, f64)]) -> Result<crate::Confinement, ParamError> {
        for (k, (name, _)) in values.iter().enumerate() {
            if !self.params.iter().any(|p| p.name == *name) {
                return Err(ParamError::Unknown {
                    confinement: self.name,
                    param: name.to_string(),
                    known: self.params.iter().map(|p| p.name).collect(),
                });
            }
            if values[..k].iter().any(|(n, _)| n == name) {
                return Err(ParamError::Repeated(name.to_string()));
            }
        }
        let mut ordered = Vec::new();
        for p in self.params {
            match values.iter().find(|(n, _)| *n == p.name) {
                Some(&(_, v)) if v.is_finite() => ordered.push(v),
                Some(&(_, v)) => {
                    return Err(ParamError::NotFinite {
                        param: p.name,
                        value: v,
                    })
                }
                None => match p.default {
                    Some(v) => ordered.push(v),
                    None => {
                        return Err(ParamError::Missing {
                            confinement: self.name,
                            param: p.name,
                            doc: p.doc,
                        })
                    }
                },
            }
        }
        Ok(crate::Confinement::from_name(self.name, &ordered)
            .expect("a declaration builds its own confinement"))
    }
}

/// A confinement's parameters given wrongly by name ([`Declaration::with`]).
#[derive(Clone, Debug, PartialEq)]
pub enum ParamError {
    /// No confinement of that name.
    UnknownConfinement(String),
    /// A parameter the confinement does not declare.
    Unknown {
        /// The confinement.
        confinement: &'static str,
        /// The parameter given.
        param: String,
        /// Those it declares.
        known: Vec<&'static str>,
    },
    /// A parameter without a default that was not given.
    Missing {
        /// The confinement.
        confinement: &'static str,
        /// The parameter.
        param: &'static str,
        /// What it is.
        doc: &'static str,
    },
    /// A parameter given twice.
    Repeated(String),
    /// A NaN or infinite value.
    NotFinite {
        /// The parameter.
        param: &'static str,
        /// Its value.
        value: f64,
    },
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamError::UnknownConfinement(name) => write!(
                f,
                "unknown confinement `{name}` (known: {})",
                crate::Confinement::NAMES.join(", ")
            ),
            ParamError::Unknown {
                confinement,
                param,
                known,
            } => {
                if known.is_empty() {
                    write!(f, "`{confinement}` has no parameters (got `{param}`)")
                } else {
                    write!(
                        f,
                        "`{confinement}` has no parameter `{param}` (its parameters: {})",
                        known.join(", ")
                    )
                }
            }
            ParamError::Missing {
                confinement,
                param,
                doc,
            } => write!(f, "`{confinement}` needs the parameter `{param}`: {doc}"),
            ParamError::Repeated(p) => write!(f, "the parameter `{p}` is given twice"),
            ParamError::NotFinite { param, value } => {
                write!(f, "the parameter `{param}` must be finite (got {value})")
            }
        }
    }
}

impl std::error::Error for ParamError {}

/// The declaration of the confinement called `name`.
pub fn declaration(name: &str) -> Result<&'static Declaration, ParamError> {
    crate::generated::DECLARATIONS
        .iter()
        .find(|d| d.name == name)
        .ok_or_else(|| ParamError::UnknownConfinement(name.to_string()))
}
