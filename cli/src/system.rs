//! The system arguments every subcommand shares (confinement, truncation or scene file,
//! particles, viscosity, the confinement's parameters, overlaps), their validation and
//! the mapping of the library's [`InputError`] to files, lines and options; and the
//! cause named when a result is not finite. The confinements and their parameters are
//! those the kernels declare (`kernels::DECLARATIONS`): `--confinement NAME` and
//! `--param NAME=VALUE`, with the aliases [`ALIASES`].

use crate::error::CliError;
use crate::options::{num, parse_components, positive};
use crate::table::{self, Columns, Table};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use kernels::{Declaration, ParamError};
use std::fs;
use std::path::PathBuf;
use stokesian::{BoxLengths, Confinement, InputError, Moments, Overlap, Particle, System};

/// The system: confinement, truncation, particles, viscosity.
#[derive(Args, Debug)]
pub struct SystemArgs {
    /// The Green's function: one of the registry's confinements (a hyphen may stand for
    /// each underscore); `stokesian confinements` lists them with their parameters.
    #[arg(
        long,
        value_name = "NAME",
        value_parser = confinement_parser(),
        required_unless_present = "scene"
    )]
    pub confinement: Option<&'static Declaration>,
    /// A parameter of the confinement, NAME=VALUE (repeatable); those not given take
    /// their defaults (`stokesian confinements` lists them).
    #[arg(long = "param", value_name = "NAME=VALUE", value_parser = parse_param)]
    pub params: Vec<(String, f64)>,
    /// Truncation of the multipole expansion: F, FT or FTS.
    #[arg(
        long,
        value_enum,
        ignore_case = true,
        required_unless_present = "scene"
    )]
    pub moments: Option<MomentsArg>,
    /// A scene file (scenes/*.toml) giving the confinement and the truncation instead of
    /// --confinement and --moments (its other keys concern the generated kernels).
    #[arg(long, value_name = "scene.toml", conflicts_with_all = ["confinement", "moments"])]
    pub scene: Option<PathBuf>,
    /// The spheres: CSV with columns x,y,z,radius (any order, other columns ignored) or
    /// .npy of shape (N, 4); with --radius, x,y,z or (N, 3).
    #[arg(long, value_name = "particles.csv|particles.npy")]
    pub particles: PathBuf,
    /// The radius of every sphere, for a particles file of centres only (x,y,z).
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub radius: Option<f64>,
    /// Viscosity of the fluid that holds the spheres.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub viscosity: f64,
    /// --param height=H: the height of the boundary plane x3 = H, for the confinements
    /// that have a `height` [default: 0].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    pub boundary_height: Option<f64>,
    /// --param lambda=L: the interface's viscosity ratio (liquid below / liquid holding
    /// the spheres), >= 0.
    #[arg(long, value_name = "L", allow_negative_numbers = true)]
    pub lambda: Option<f64>,
    /// --param gap=G: the slit's distance from the lower wall to the upper wall (> 0).
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    pub gap: Option<f64>,
    /// Spheres that overlap each other or cut a boundary: refuse them (an error), take
    /// the far forms anyway (not positive definite), or the Rotne-Prager-Yamakawa
    /// overlap forms and the damping near boundaries (F and FT; docs/overlap.md).
    #[arg(long, value_enum, value_name = "HOW", default_value = "refuse")]
    pub overlap: OverlapArg,
    /// The same as --overlap far.
    #[arg(long, conflicts_with = "overlap")]
    pub allow_overlap: bool,
    /// A periodic box, every periodic image summed by Ewald summation (F and FT;
    /// docs/periodic.md): LX,LY,LZ, triply periodic unbounded fluid (--confinement free),
    /// or LX,LY, periodic along the wall (--confinement wall) or the walls of a slit
    /// (--confinement slit: its exact Green's function, not the superposed images).
    #[arg(long = "box", value_name = "LX,LY[,LZ]", allow_hyphen_values = true)]
    pub periodic_box: Option<String>,
    /// Relative truncation error of the periodic sums (with --box).
    #[arg(long, value_name = "TOL", requires = "periodic_box", default_value_t = stokesian::PeriodicBox::TOLERANCE)]
    pub periodic_tolerance: f64,
}

/// `--overlap`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OverlapArg {
    /// An error (the default).
    Refuse,
    /// The far forms, evaluated anyway.
    Far,
    /// The RPY overlap forms; spheres cutting a boundary damped.
    Rpy,
}

/// The options that stand for `--param NAME=`, kept from before `--param`: (option,
/// parameter).
pub const ALIASES: [(&str, &str); 3] = [
    ("--boundary-height", "height"),
    ("--lambda", "lambda"),
    ("--gap", "gap"),
];

/// The declaration called `name`, a hyphen standing for each underscore
/// (`free-surface` for `free_surface`), in any case.
fn confinement_named(name: &str) -> Result<&'static Declaration, ParamError> {
    kernels::declaration(&name.to_ascii_lowercase().replace('-', "_"))
}

/// `--confinement`: the registry's names, each with its title as help and its hyphenated
/// spelling as an alias.
fn confinement_parser() -> impl clap::builder::TypedValueParser<Value = &'static Declaration> {
    let values = kernels::DECLARATIONS.iter().map(|d| {
        PossibleValue::new(d.name)
            .help(d.title)
            .alias(d.name.replace('_', "-"))
    });
    PossibleValuesParser::new(values).map(|name| {
        confinement_named(&name).expect("a possible value of --confinement names a declaration")
    })
}

/// `--param NAME=VALUE`.
fn parse_param(text: &str) -> Result<(String, f64), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or("expected NAME=VALUE, such as gap=12")?;
    let name = name.trim();
    if name.is_empty() {
        return Err("the parameter's name is empty (expected NAME=VALUE)".to_string());
    }
    let value: f64 = value
        .trim()
        .parse()
        .map_err(|_| format!("{:?} is not a number", value.trim()))?;
    Ok((name.to_string(), value))
}

/// `its parameters: a, b` or `it has no parameters`, for messages.
fn parameters_phrase(d: &Declaration) -> String {
    if d.params.is_empty() {
        "it has no parameters".to_string()
    } else {
        let names: Vec<&str> = d.params.iter().map(|p| p.name).collect();
        format!("its parameters: {}", names.join(", "))
    }
}

/// `--moments`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MomentsArg {
    /// Forces only.
    #[value(name = "F")]
    F,
    /// Forces and torques.
    #[value(name = "FT")]
    Ft,
    /// Forces, torques and stresslets.
    #[value(name = "FTS")]
    Fts,
}

impl MomentsArg {
    /// The library's truncation.
    pub fn moments(self) -> Moments {
        match self {
            MomentsArg::F => Moments::F,
            MomentsArg::Ft => Moments::FT,
            MomentsArg::Fts => Moments::FTS,
        }
    }

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            MomentsArg::F => "F",
            MomentsArg::Ft => "FT",
            MomentsArg::Fts => "FTS",
        }
    }
}

/// `--moments` made optional with the default F (`velocity`, `brownian`), with the
/// subcommand's own `help`; applied by `#[command(mut_arg("moments", ...))]`.
pub fn moments_default_f(arg: clap::Arg, help: &'static str) -> clap::Arg {
    arg.required(false)
        .required_unless_present(clap::builder::Resettable::Reset)
        .default_value("F")
        .help(help)
}

/// The particles file's columns, with and without `--radius`.
const PARTICLES: Columns = Columns {
    what: "particles",
    required: &["x", "y", "z", "radius"],
    refused: &[],
    refused_why: "",
    hint: " (one sphere per row: centre x,y,z and radius; --radius A for centres only)",
};
const CENTRES: Columns = Columns {
    what: "particles",
    required: &["x", "y", "z"],
    refused: &["radius"],
    refused_why: "conflicts with --radius (give the radii in the file or by --radius, not both)",
    hint: " (one sphere centre per row; the radius is --radius)",
};

impl SystemArgs {
    /// With `--scene`, read the confinement and the truncation from the scene file (clap
    /// has already made `--scene` exclusive with `--confinement` and `--moments`, and
    /// required one or the other). A TOML syntax error names its line and column.
    pub fn resolve_scene(&mut self) -> Result<(), CliError> {
        let Some(path) = &self.scene else {
            return Ok(());
        };
        let shown = path.display().to_string();
        let text = fs::read_to_string(path).map_err(|source| CliError::Read {
            what: "scene",
            path: shown.clone(),
            source,
        })?;
        let bad = |reason: String| CliError::Scene {
            path: shown.clone(),
            reason,
        };
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| bad(e.to_string().trim_end().to_string()))?;
        const KEYS: [&str; 6] = [
            "name",
            "confinement",
            "moments",
            "radii",
            "outputs",
            "description",
        ];
        if let Some(key) = table.keys().find(|k| !KEYS.contains(&k.as_str())) {
            return Err(bad(format!(
                "unknown key `{key}` (a scene has {})",
                KEYS.join(", ")
            )));
        }
        let string = |key: &str| match table.get(key) {
            Some(toml::Value::String(v)) => Ok(v.clone()),
            Some(_) => Err(bad(format!("`{key}` must be a string"))),
            None => Err(bad(format!("`{key}` is missing"))),
        };
        let c = string("confinement")?;
        self.confinement = Some(confinement_named(&c).map_err(|e| bad(e.to_string()))?);
        let m = string("moments")?;
        self.moments = Some(
            MomentsArg::from_str(&m, true)
                .map_err(|_| bad(format!("unknown moments `{m}` (F, FT or FTS)")))?,
        );
        Ok(())
    }

    /// The confinement's declaration (given, or read by [`SystemArgs::resolve_scene`]).
    pub fn declaration(&self) -> &'static Declaration {
        self.confinement
            .expect("clap requires --confinement or --scene, and resolve_scene reads the scene")
    }

    /// The truncation (given, or read by [`SystemArgs::resolve_scene`]).
    pub fn truncation(&self) -> MomentsArg {
        self.moments
            .expect("clap requires --moments or --scene, and resolve_scene reads the scene")
    }

    /// The parameters given, each with how: the aliases first, then `--param` in order.
    fn given(&self) -> Vec<Given<'_>> {
        let aliases = [self.boundary_height, self.lambda, self.gap];
        let by_alias = ALIASES
            .iter()
            .zip(aliases)
            .filter_map(|(&(option, name), value)| {
                value.map(|value| Given {
                    name,
                    value,
                    option,
                })
            });
        let by_param = self.params.iter().map(|(name, value)| Given {
            name,
            value: *value,
            option: "--param",
        });
        by_alias.chain(by_param).collect()
    }

    /// The confinement from the command line by its declaration
    /// ([`Declaration::with`]): an alias that does not apply, an unknown, missing,
    /// repeated or non-finite parameter is an error that says which (the values'
    /// ranges are the library's to check).
    pub fn confinement(&self) -> Result<Confinement, CliError> {
        let decl = self.declaration();
        let given = self.given();
        for g in &given {
            if g.option != "--param" && !decl.params.iter().any(|p| p.name == g.name) {
                return Err(CliError::Inapplicable {
                    option: g.option,
                    context: format!("--confinement {} ({})", decl.name, parameters_phrase(decl)),
                });
            }
        }
        let values: Vec<(&str, f64)> = given.iter().map(|g| (g.name, g.value)).collect();
        decl.with(&values).map_err(|source| {
            let shown = |name: &str| -> Vec<String> {
                given
                    .iter()
                    .filter(|g| g.name == name)
                    .map(Given::shown)
                    .collect()
            };
            let (place, hint) = match &source {
                ParamError::Unknown { param, .. } => (shown(param).join(", "), String::new()),
                ParamError::Missing { param, .. } => {
                    let alias = ALIASES
                        .iter()
                        .find(|(_, name)| name == param)
                        .map(|(option, _)| format!(" or {option} VALUE"))
                        .unwrap_or_default();
                    (
                        String::new(),
                        format!(" (give --param {param}=VALUE{alias})"),
                    )
                }
                ParamError::Repeated(param) => (
                    String::new(),
                    format!(" ({}; give it once)", shown(param).join(" and ")),
                ),
                ParamError::NotFinite { param, .. } => (shown(param).join(", "), String::new()),
                ParamError::UnknownConfinement(_) => (String::new(), String::new()),
            };
            let place = if place.is_empty() {
                place
            } else {
                format!("{place}: ")
            };
            CliError::Param {
                place,
                source,
                hint,
            }
        })
    }

    /// Read and validate the particles (the library validates the physics).
    pub fn setup(&self) -> Result<Setup, CliError> {
        let conf = self.confinement()?;
        if let Some(a) = self.radius {
            positive("--radius", a, "the radius")?;
        }
        let columns = if self.radius.is_some() {
            &CENTRES
        } else {
            &PARTICLES
        };
        let table = table::read(&self.particles, columns)?;
        if table.rows.is_empty() {
            return Err(CliError::NoParticles { path: table.path });
        }
        let particles: Vec<Particle> = table
            .rows
            .iter()
            .map(|r| Particle {
                x: [r[0], r[1], r[2]],
                a: self.radius.unwrap_or_else(|| r[3]),
            })
            .collect();
        let overlap = match (self.allow_overlap, self.overlap) {
            (true, _) | (_, OverlapArg::Far) => Overlap::Far,
            (_, OverlapArg::Refuse) => Overlap::Refuse,
            (_, OverlapArg::Rpy) => Overlap::Rpy,
        };
        let system = System::new(conf, self.viscosity, particles, overlap)
            .map_err(|e| input_error(e, &table, &self.given()))?;
        let system = match &self.periodic_box {
            Some(text) => {
                let lengths = match parse_components("--box", text)?.as_slice() {
                    &[lx, ly, lz] => BoxLengths::Triply([lx, ly, lz]),
                    &[lx, ly] => BoxLengths::Lateral([lx, ly]),
                    v => {
                        return Err(CliError::BadOption {
                            option: "--box",
                            value: text.clone(),
                            reason: format!(
                                "needs 3 lengths lx,ly,lz (a triply periodic box) or 2 lengths lx,ly (periodic along a wall or a slit's walls), found {}",
                                v.len()
                            ),
                        })
                    }
                };
                system.periodic(stokesian::PeriodicBox {
                    lengths,
                    tolerance: self.periodic_tolerance,
                })?
            }
            None => system,
        };
        Ok(Setup {
            system,
            table,
            moments: self.truncation(),
            allow_overlap: overlap == Overlap::Far,
        })
    }
}

/// A parameter as the command line gave it.
struct Given<'a> {
    /// The declared name it stands for.
    name: &'a str,
    /// Its value.
    value: f64,
    /// `--param` or the alias that gave it.
    option: &'static str,
}

impl Given<'_> {
    /// As typed: `--gap 12` or `--param gap=12`.
    fn shown(&self) -> String {
        if self.option == "--param" {
            format!("--param {}={}", self.name, num(self.value))
        } else {
            format!("{} {}", self.option, num(self.value))
        }
    }
}

/// The validated system and where its particles came from.
pub struct Setup {
    /// The spheres in their confinement.
    pub system: System,
    /// The particles file.
    pub table: Table,
    /// The truncation.
    pub moments: MomentsArg,
    /// Whether overlaps were accepted with the far forms (`--overlap far`).
    pub allow_overlap: bool,
}

impl Setup {
    /// The error for a result (`what`) with entries that are not finite numbers.
    pub fn non_finite(&self, what: &str) -> CliError {
        CliError::Numerical(format!(
            "the {what} has entries that are not finite numbers: {}; nothing written",
            self.suspects()
        ))
    }

    /// Check that `values` (the `what`) are finite.
    pub fn check_finite(&self, values: &[f64], what: &str) -> Result<(), CliError> {
        if values.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(self.non_finite(what))
        }
    }

    /// The overlaps `--overlap far` accepted, if it accepted any.
    fn accepted_overlap(&self) -> Option<String> {
        let s = &self.system;
        if !self.allow_overlap {
            return None;
        }
        let strict = stokesian::validate(s.confinement(), s.viscosity(), s.particles(), false);
        strict.err().map(|e| {
            format!(
                "spheres accepted with --overlap far overlap ({}), where the kernels are \
                 not meaningful",
                // the confinement's parameters passed this validation already
                input_error(e, &self.table, &[])
            )
        })
    }

    /// Why the stresslet block is not positive definite: accepted overlaps, boundaries
    /// that hold only approximately (the slit's superposed images, not positive definite
    /// near a wall of a narrow slit), or neither (unexpected).
    pub fn indefinite(&self) -> String {
        let conf = self.system.confinement();
        if let Some(overlap) = self.accepted_overlap() {
            overlap
        } else if let Some(b) = conf.boundaries().iter().find(|b| !b.exact) {
            format!(
                "--confinement {} satisfies its boundary conditions only approximately \
                 ({b}), and is not positive definite near such a boundary when the fluid \
                 between its boundaries is narrow: widen it ({})",
                conf.name(),
                parameters_phrase(conf.declaration())
            )
        } else {
            "unexpected for spheres clear of each other and of the boundaries; please \
             report it with the input"
                .to_string()
        }
    }

    /// Why results are not finite: accepted overlaps, or else the length scales.
    fn suspects(&self) -> String {
        if let Some(overlap) = self.accepted_overlap() {
            return overlap;
        }
        let s = &self.system;
        // the smallest and largest lengths: radii, the extent of the centres, and the
        // distances to the boundary planes
        let ps = s.particles();
        let radii = ps.iter().map(|p| p.a);
        let lo = radii.clone().fold(f64::INFINITY, f64::min);
        let mut hi = radii.fold(0.0, f64::max);
        for k in 0..3 {
            let (min, max) = ps
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                    (l.min(p.x[k]), h.max(p.x[k]))
                });
            hi = hi.max(max - min);
            for b in s.confinement().boundaries() {
                for p in ps {
                    hi = hi.max(b.distance(p.x).abs());
                }
            }
        }
        format!(
            "the lengths (from {lo:.3e}, the smallest radius, to {hi:.3e}, the largest radius, \
             extent of the centres or distance to a boundary) and the viscosity {:.3e} are at \
             scales where the kernels' powers of lengths (a^-3 / viscosity and beyond) leave \
             the range of double precision; express lengths and viscosity in other units \
             (for spheres of a micrometre, lengths in micrometres) so that radii, distances \
             and viscosity are nearer 1",
            s.viscosity()
        )
    }
}

/// `CliError::Particle` for row `index` of `table`.
pub fn particle_error(table: &Table, index: usize, reason: String) -> CliError {
    CliError::Particle {
        path: table.path.clone(),
        place: table.place(index),
        index,
        reason,
    }
}

/// Map the library's 0-based particle errors to file lines (or rows), and a
/// parameter's to the option that gave it (`given`; `--param` for a default).
fn input_error(e: InputError, table: &Table, given: &[Given]) -> CliError {
    let pair = |a: usize, b: usize, reason: String| CliError::Pair {
        path: table.path.clone(),
        places: table.places(a, b),
        a,
        b,
        reason,
    };
    match e {
        InputError::Empty => CliError::NoParticles {
            path: table.path.clone(),
        },
        InputError::NonFinitePosition { index, axis, value } => particle_error(
            table,
            index,
            format!("coordinate {axis} is {value}, not a finite number"),
        ),
        InputError::BadRadius { index, value } => particle_error(
            table,
            index,
            format!("radius {} must be a positive finite number", num(value)),
        ),
        InputError::BadViscosity(value) => CliError::BadOption {
            option: "--viscosity",
            value: num(value),
            reason: "must be a positive finite number".to_string(),
        },
        InputError::BadParameter { name, value, why } => {
            let (option, value) = match given.iter().find(|g| g.name == name) {
                Some(g) if g.option != "--param" => (g.option, num(value)),
                _ => ("--param", format!("{name}={}", num(value))),
            };
            CliError::BadOption {
                option,
                value,
                reason: why.to_string(),
            }
        }
        InputError::Unrepresentable { index, a, eta } => particle_error(
            table,
            index,
            format!(
                "radius {} with viscosity {}: 1/(viscosity a^3), the scale of the \
                 rotation and strain mobilities, is outside the range of double precision; \
                 express lengths and viscosity in other units (for spheres of a \
                 micrometre, lengths in micrometres) so that radii and viscosity are \
                 nearer 1",
                num(a),
                num(eta)
            ),
        ),
        InputError::OutsideFluid {
            index,
            distance,
            boundary,
        } => particle_error(
            table,
            index,
            format!(
                "centre is not inside the fluid: signed distance {} from the boundary, {}",
                num(distance),
                boundary
            ),
        ),
        InputError::OverlapsBoundary {
            index,
            a,
            distance,
            boundary,
        } => particle_error(
            table,
            index,
            format!(
                "sphere of radius {} overlaps the boundary, {}: centre-to-boundary \
                 distance {} < radius (--overlap rpy or far accepts this)",
                num(a),
                boundary,
                num(distance)
            ),
        ),
        InputError::Overlap {
            first,
            second,
            distance,
            sum,
        } => pair(
            first,
            second,
            format!(
                "spheres overlap: centre distance {} < sum of radii {} \
                 (--overlap rpy or far accepts this)",
                num(distance),
                num(sum)
            ),
        ),
        InputError::SameCentre { first, second } => pair(
            first,
            second,
            "the two spheres have the same centre; the mobility is undefined even with \
             --overlap"
                .to_string(),
        ),
    }
}
