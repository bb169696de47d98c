//! What a Green's function's declaration must satisfy before kernels are generated from
//! it: unit normals (mirrors, boundaries, the directions of positions), parameter names
//! that are distinct Rust identifiers, image terms that refer to declared mirrors and
//! weights, and registered names that are distinct. A declaration that breaks one of
//! these would otherwise give wrong kernels (a reflection across a non-unit normal is no
//! reflection) or generated code that does not compile, far from its cause.

use super::{examples, Green, Visitor};

/// How far from 1 the length of a declared normal may be. The frames, reflections and
/// distances built from a normal are exact only for a unit vector; 1e-12 admits a normal
/// whose components are rounded to double precision (`1/sqrt(2)` to 17 digits is off by
/// 1e-16) and catches any that was not normalised.
pub const UNIT_TOLERANCE: f64 = 1e-12;

/// A declaration kernels cannot be generated from.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DeclarationError {
    /// A normal or direction is not a unit vector.
    #[error(
        "`{green}`: {what} has the normal {normal:?} of length {length}, not 1: normals must \
         be unit vectors (to {UNIT_TOLERANCE:e}); divide by the length"
    )]
    NotUnit {
        /// The Green's function.
        green: &'static str,
        /// Which plane or parameter.
        what: String,
        /// The normal as declared (at the parameters' example values).
        normal: [f64; 3],
        /// Its length.
        length: f64,
    },
    /// A parameter's name cannot be a kernel argument.
    #[error(
        "`{green}`: parameter {name:?} is not a Rust identifier (lower-case letters, digits, `_`)"
    )]
    BadParamName {
        /// The Green's function.
        green: &'static str,
        /// The name.
        name: &'static str,
    },
    /// Two parameters share a name.
    #[error("`{green}`: parameter `{name}` is declared twice")]
    RepeatedParam {
        /// The Green's function.
        green: &'static str,
        /// The name.
        name: &'static str,
    },
    /// A parameter's default or example is not a finite number.
    #[error("`{green}`: parameter `{name}` has a default or example that is not finite")]
    NonFiniteParam {
        /// The Green's function.
        green: &'static str,
        /// The name.
        name: &'static str,
    },
    /// An image term refers to a mirror or weight that is not declared, or to a tensor
    /// component outside `0..3`.
    #[error("`{green}`: image term {index} {why}")]
    BadImageTerm {
        /// The Green's function.
        green: &'static str,
        /// Its index in `Green::image_terms`.
        index: usize,
        /// What it refers to.
        why: String,
    },
    /// A radial potential ([`Green::radial`]) with a cancelling image: the exactly
    /// evaluated `phi(R) - phi(r)` is built for the Stokeslet's homogeneous potentials only.
    #[error(
        "`{0}`: declares a radial potential and a cancelling image; the exact difference of \
         the Stokeslet and its image exists for the Stokeslet's `r` only (drop `cancelling_image`)"
    )]
    RadialCancellingImage(&'static str),
    /// The Green's function's name cannot name generated items.
    #[error("a Green's function is named {0:?}, which is not a Rust identifier (lower-case letters, digits, `_`)")]
    BadName(&'static str),
    /// Two registered Green's functions share a name.
    #[error("two registered Green's functions are named `{0}`: each needs its own `name()`")]
    RepeatedName(&'static str),
    /// A scene names a confinement that is another one turned (a twin, kernel_gen
    /// `catalog::twin`): its kernels are the other's, and so are its scenes.
    #[error(
        "scene `{scene}`: `{green}` is `{of}` in its planes' frame and is served by `{of}`'s \
         kernels; write the scene for `{of}` (its F and FT scenes serve `{green}` too)"
    )]
    SceneOfTwin {
        /// The scene's name.
        scene: String,
        /// The twin.
        green: &'static str,
        /// The confinement that serves it.
        of: &'static str,
    },
}

/// Whether `s` is a lower-case Rust identifier (a letter, then letters, digits and `_`):
/// what names a Green's function, its module and its parameters.
pub fn is_identifier(s: &str) -> bool {
    let mut c = s.chars();
    c.next().is_some_and(|f| f.is_ascii_lowercase())
        && c.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

fn unit(green: &'static str, what: String, normal: [f64; 3]) -> Result<(), DeclarationError> {
    let length = normal.iter().map(|v| v * v).sum::<f64>().sqrt();
    if (length - 1.0).abs() <= UNIT_TOLERANCE {
        Ok(())
    } else {
        Err(DeclarationError::NotUnit {
            green,
            what,
            normal,
            length,
        })
    }
}

/// Check one declaration, its planes evaluated at the parameters' example values.
pub fn check<G: Green>(g: &G) -> Result<(), DeclarationError> {
    let green = g.name();
    if !is_identifier(green) {
        return Err(DeclarationError::BadName(green));
    }
    for (k, p) in g.params().iter().enumerate() {
        if !is_identifier(p.name) {
            return Err(DeclarationError::BadParamName {
                green,
                name: p.name,
            });
        }
        if g.params()[..k].iter().any(|q| q.name == p.name) {
            return Err(DeclarationError::RepeatedParam {
                green,
                name: p.name,
            });
        }
        if !p.example.is_finite() || p.default.is_some_and(|d| !d.is_finite()) {
            return Err(DeclarationError::NonFiniteParam {
                green,
                name: p.name,
            });
        }
        if let super::Dimension::Position(d) = p.dimension {
            unit(green, format!("the direction of parameter `{}`", p.name), d)?;
        }
    }
    let p = examples(g);
    if g.cancelling_image().is_some() && super::is_radial(g) {
        return Err(DeclarationError::RadialCancellingImage(green));
    }
    let mirrors = g.mirrors(&p);
    for (k, m) in mirrors.iter().enumerate() {
        unit(green, format!("mirror {k}"), m.normal)?;
    }
    for (k, b) in g.boundaries(&p).iter().enumerate() {
        unit(green, format!("boundary {k}"), b.plane.normal)?;
    }
    let weights = g.weights(&p).len();
    for (index, t) in g.image_terms().unwrap_or_default().iter().enumerate() {
        let bad = |why: String| DeclarationError::BadImageTerm { green, index, why };
        if t.plane >= mirrors.len() {
            return Err(bad(format!(
                "reflects across mirror {}, but `mirrors` declares {}",
                t.plane,
                mirrors.len()
            )));
        }
        if t.weight >= weights {
            return Err(bad(format!(
                "has weight {}, but `weights` declares {weights}",
                t.weight
            )));
        }
        if [t.out.0, t.out.1, t.j.0, t.j.1].iter().any(|&i| i > 2) {
            return Err(bad(format!(
                "has components out = {:?}, j = {:?} outside 0..3",
                t.out, t.j
            )));
        }
    }
    Ok(())
}

/// Check every registered declaration, confinements and building blocks ([`check`]), and
/// that their names are distinct.
pub fn check_registry() -> Result<(), DeclarationError> {
    struct All(Vec<&'static str>, Result<(), DeclarationError>);
    impl Visitor for All {
        fn visit<G: Green>(&mut self, g: &G) {
            if self.1.is_err() {
                return;
            }
            self.1 = check(g).and_then(|()| {
                if self.0.contains(&g.name()) {
                    Err(DeclarationError::RepeatedName(g.name()))
                } else {
                    Ok(())
                }
            });
            self.0.push(g.name());
        }
    }
    let mut all = All(Vec::new(), Ok(()));
    super::for_each(&mut all);
    super::for_each_building_block(&mut all);
    all.1
}
