//! Twins: a confinement that, seen from its planes' own frame ([`turned`]), is another
//! registered confinement, and whose kernels are therefore that confinement's.
//!
//! A Green's function `g` whose planes share a normal other than `e3` is traced in the
//! frame `Q` of its planes ([`turned::turn`]). Where that trace, with the names of an
//! earlier family `w` (its name, title and parameters in order), emits `w`'s family file
//! to the byte, `g` is `w` turned: `G_g(x, y; p) = Q^T G_w(Q x, Q y; p) Q`. The
//! catalogue then emits no kernels for `g`: its entry points rotate the points and
//! moments into the frame, call `w`'s kernels (the same call, so the solver compiles
//! them once) and rotate the responses and blocks back (`kernels::turn`). The side wall
//! is the wall so (`Q` a permutation of the axes); a wall of any normal for which the
//! rotation folds to the same graph would be too, and one for which it does not keeps
//! kernels of its own, as before.

use super::family::family_file;
use super::Family;
use crate::kernel::trace_in_frame;
use crate::physics::frame::strains;
use crate::physics::green::turned;
use crate::physics::green::{clean, Dimension, Green, Mat3};

/// The family whose kernels serve a twin, and the twin's frame.
#[derive(Clone, Debug)]
pub(super) struct Twin {
    /// The serving family's name.
    pub of: &'static str,
    /// Its parameters' names, in order: the twin's parameters are passed in their
    /// places.
    pub of_params: Vec<&'static str>,
    /// `Q`, rows `t1, t2, n`.
    pub q: Mat3<f64>,
    /// `Q_5`, the same rotation on the orthonormal strain basis.
    pub q5: [[f64; 5]; 5],
}

/// The earlier family of `families` that `g` is, turned, if any (module docs).
pub(super) fn find<G: Green>(g: &G, families: &[Family]) -> Option<Twin> {
    let q = turned::turn(g)?;
    families.iter().find_map(|w| {
        let file = w.file.as_ref()?;
        let same_params = w.params.len() == g.params().len()
            && w.params
                .iter()
                .zip(g.params())
                .all(|(a, b)| match (a.dimension, b.dimension) {
                    (Dimension::Position(da), Dimension::Position(db)) => {
                        let turned: [f64; 3] =
                            std::array::from_fn(|i| clean((0..3).map(|k| q[i][k] * db[k]).sum()));
                        turned == da
                    }
                    (da, db) => da == db,
                });
        if !same_params {
            return None;
        }
        // the kernels traced in the frame, under `w`'s names (no generic code of `G`
        // beyond the trace, which `trace` instantiates already)
        let traced = |spec: &_| trace_in_frame(g, &q, spec).renamed(g.params(), w.params);
        let (mine, _) = family_file(w.name, w.title, &traced);
        (mine.contents == file.contents).then(|| {
            let q5 = strains(&q);
            Twin {
                of: w.name,
                of_params: w.params.iter().map(|p| p.name).collect(),
                q,
                q5: std::array::from_fn(|i| std::array::from_fn(|j| clean(q5[i][j]))),
            }
        })
    })
}
