//! What a simulation needs, read from a TOML file in `scenes/`: the confinement, the
//! truncation of the multipole expansion, equal or unequal radii, and which kernels
//! (block kernels for dense matrices, fused pair products).

use crate::physics::operators::{self, Moment, Response};

/// Truncation of the multipole expansion a scene needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Moments {
    /// Forces and velocities only.
    F,
    /// Forces and torques; velocities and angular velocities.
    FT,
    /// Forces, torques and stresslets; velocities, angular velocities and strains.
    FTS,
}

impl Moments {
    /// The blocks, in output order.
    pub fn blocks(self) -> Vec<(Response, Moment)> {
        use Moment::*;
        use Response::*;
        match self {
            Moments::F => vec![(U, F)],
            Moments::FT => vec![(U, F), (U, L), (Omega, F), (Omega, L)],
            Moments::FTS => operators::BLOCKS.to_vec(),
        }
    }

    /// Components per particle (3, 6 or 11).
    pub fn per_particle(self) -> usize {
        match self {
            Moments::F => 3,
            Moments::FT => 6,
            Moments::FTS => 11,
        }
    }

    /// Lower-case name (`f`, `ft`, `fts`).
    pub fn lower(self) -> &'static str {
        match self {
            Moments::F => "f",
            Moments::FT => "ft",
            Moments::FTS => "fts",
        }
    }
}

/// Whether a scene's particles all share one radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Radii {
    /// One radius: only equal-radius kernels are generated.
    Equal,
    /// Any radii: unequal-radius kernels, plus the equal-radius ones as a fast path.
    Unequal,
}

/// What a simulation needs, read from a TOML file in `scenes/`:
///
/// ```toml
/// name = "wall_f"            # identifier: functions are wall_f_self, wall_f_pair, ...
/// confinement = "wall"       # a registered Green's function
/// moments = "F"              # F, FT or FTS
/// radii = "unequal"          # equal or unequal
/// outputs = ["dense", "product"]   # block kernels, fused pair-product kernels,
///                            # "drift": a sphere's drift from itself and its own images
/// description = "..."        # optional
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Identifier, prefix of the generated functions.
    pub name: String,
    /// Name of a registered Green's function.
    pub confinement: String,
    /// Truncation.
    pub moments: Moments,
    /// Radii.
    pub radii: Radii,
    /// Generate block kernels (for dense matrices).
    pub dense: bool,
    /// Generate fused pair-product kernels (`u_a += M^{ab} x_b`, `u_b += M^{ba} x_a`).
    pub product: bool,
    /// Generate the kernels of a sphere's drift in a periodic box: the derivative of the
    /// self kernel along a direction `v` of its column along `v` (`self_along`) and the
    /// same of the pair kernel with both points moving together (`pair_together`, for
    /// the sphere's own images); one radius.
    pub drift: bool,
    /// Free text for the generated documentation.
    pub description: String,
}

/// Why a scene file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Not valid TOML or not the scene schema.
    #[error("{file}: {message}")]
    Parse {
        /// File name.
        file: String,
        /// What the parser said.
        message: String,
    },
    /// A field has a value outside its set.
    #[error("{file}: {field} = {value:?}: {why}")]
    Value {
        /// File name.
        file: String,
        /// Field.
        field: &'static str,
        /// Value found.
        value: String,
        /// What is allowed.
        why: String,
    },
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneToml {
    name: String,
    confinement: String,
    moments: String,
    radii: String,
    outputs: Vec<String>,
    #[serde(default)]
    description: String,
}

impl Scene {
    /// Parse a scene description; `file` names it in errors. `registered` lists the
    /// Green's functions the confinement may name.
    pub fn parse(file: &str, text: &str, registered: &[&str]) -> Result<Scene, SceneError> {
        let t: SceneToml = toml::from_str(text).map_err(|e| SceneError::Parse {
            file: file.into(),
            message: e.to_string(),
        })?;
        let bad = |field: &'static str, value: &str, why: &str| SceneError::Value {
            file: file.into(),
            field,
            value: value.into(),
            why: why.into(),
        };
        let ident_ok = !t.name.is_empty()
            && t.name
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_lowercase())
            && t.name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        if !ident_ok {
            return Err(bad(
                "name",
                &t.name,
                "must be a lower-case identifier (a-z, 0-9, _)",
            ));
        }
        if !registered.contains(&t.confinement.as_str()) {
            return Err(bad(
                "confinement",
                &t.confinement,
                &format!("must be one of {registered:?}"),
            ));
        }
        let moments = match t.moments.as_str() {
            "F" => Moments::F,
            "FT" => Moments::FT,
            "FTS" => Moments::FTS,
            other => return Err(bad("moments", other, "must be F, FT or FTS")),
        };
        let radii = match t.radii.as_str() {
            "equal" => Radii::Equal,
            "unequal" => Radii::Unequal,
            other => return Err(bad("radii", other, "must be equal or unequal")),
        };
        let (mut dense, mut product, mut drift) = (false, false, false);
        for o in &t.outputs {
            match o.as_str() {
                "dense" => dense = true,
                "product" => product = true,
                "drift" => drift = true,
                other => {
                    return Err(bad(
                        "outputs",
                        other,
                        "entries must be dense, product or drift",
                    ))
                }
            }
        }
        if !dense && !product && !drift {
            return Err(bad(
                "outputs",
                "[]",
                "ask for dense, product, drift or several",
            ));
        }
        Ok(Scene {
            name: t.name,
            confinement: t.confinement,
            moments,
            radii,
            dense,
            product,
            drift,
            description: t.description,
        })
    }
}
