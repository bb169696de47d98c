//! The adaptive binary tree of the fast product and its interaction lists.
//!
//! A box splits in halves across its longest side until a cell holds at most `leaf`
//! particles, and empty halves are dropped: a monolayer's boxes split in the plane
//! only until they are as wide as the layer is thick (a quadtree in a layer, an octree
//! in the bulk, one axis per level), and the leaves of a uniform suspension hold
//! between `leaf/2` and `leaf` (a split into four or eight at once leaves them a
//! quarter or an eighth full where the count falls just past a level). The particles
//! are reordered so that every cell's are contiguous. A cell's expansions are about its
//! box's centre, its radius the largest distance of one of its particles from it (an
//! image cell's: the same about the mirrored centre), except where a cell lies so close
//! to a mirror that its particles and their images fit within [`MERGE`] times its
//! radius of the centre's projection on the mirror: there the two share one expansion
//! about that projection ([`Merged`]; a layer of spheres near a wall, whose images
//! would otherwise take a second multipole-to-local translation per cell pair from a
//! centre only the layer's thickness away). A dual traversal from the root pair lists,
//! for every target cell, the source cells whose multipoles reach it (the multipole
//! acceptance criterion `r_t + r_s < theta |c_t - c_s|`, for the source cell and for
//! each of its images, or for their shared expansion), and for every leaf the leaves
//! whose particles it meets through the exact pair kernels. Everything is fixed by the
//! positions alone.

use kernels::expansion::Mirror;

/// A cell's particles and their images in a mirror share one expansion when they lie
/// within this many times the cell's radius of the centre's projection on the mirror
/// ([`Merged`]): one multipole-to-local translation instead of two, for a slightly
/// larger radius.
const MERGE: f64 = 1.1;

/// A cell whose sources and their images in one mirror share one expansion: about the
/// centre's projection on the mirror, where the particles and their images lie within
/// the same distance.
#[derive(Clone, Copy, Debug)]
pub(super) struct Merged {
    /// The mirror's index.
    pub mirror: usize,
    pub centre: [f64; 3],
    /// The largest distance of a particle (and so of its image) from `centre`.
    pub radius: f64,
    /// The largest distance of a particle from the mirror.
    pub height: f64,
}

impl Merged {
    /// Whether the particles lie within half the shared radius of the mirror, where the
    /// image's rows `h^h_power d^(2 + h_power + 2 a2)` need no more orders than the
    /// Stokeslet's (`(h/R)^h_power` counts as orders of `rho/R`).
    pub fn low(&self) -> bool {
        2.0 * self.height <= self.radius
    }
}

/// A cell of the tree.
#[derive(Clone, Debug)]
pub(super) struct Cell {
    pub centre: [f64; 3],
    pub radius: f64,
    /// Its particles' and their images' shared expansion, if it has one.
    pub merged: Option<Merged>,
    /// Its particles: `order[start..end]`.
    pub start: usize,
    pub end: usize,
    pub children: Vec<usize>,
    pub level: usize,
}

impl Cell {
    pub fn is_leaf(&self) -> bool {
        self.children.is_empty()
    }
}

/// The tree, its particle order and its lists.
pub(super) struct Tree {
    pub cells: Vec<Cell>,
    /// Tree order -> input index.
    pub order: Vec<usize>,
    /// Per cell, the source cells whose multipoles it takes.
    pub far: Vec<Vec<usize>>,
    /// Per leaf (cell index), the leaves met through the pair kernels (itself included).
    pub near: Vec<Vec<usize>>,
    /// The cells of each level.
    pub levels: Vec<Vec<usize>>,
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

impl Tree {
    /// The tree of `points` with at most `leaf` per leaf, and its lists for the
    /// acceptance parameter `theta` and the mirrors `mirrors`.
    pub fn new(points: &[[f64; 3]], leaf: usize, theta: f64, mirrors: &[Mirror]) -> Tree {
        let n = points.len();
        let mut lo = points[0];
        let mut hi = points[0];
        for p in points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let half: [f64; 3] =
            std::array::from_fn(|k| (hi[k] - lo[k]) / 2.0 * (1.0 + 1e-12) + f64::MIN_POSITIVE);
        let centre = std::array::from_fn(|k| (lo[k] + hi[k]) / 2.0);
        let mut tree = Tree {
            cells: Vec::new(),
            order: (0..n).collect(),
            far: Vec::new(),
            near: Vec::new(),
            levels: Vec::new(),
        };
        tree.build(points, mirrors, centre, half, 0, n, 0, leaf);
        for (c, cell) in tree.cells.iter().enumerate() {
            if tree.levels.len() <= cell.level {
                tree.levels.resize(cell.level + 1, Vec::new());
            }
            tree.levels[cell.level].push(c);
        }
        tree.far = vec![Vec::new(); tree.cells.len()];
        tree.near = vec![Vec::new(); tree.cells.len()];
        tree.traverse(0, 0, theta, mirrors);
        tree
    }

    /// Cell of `order[start..end]` (preorder: a parent before its children).
    #[allow(clippy::too_many_arguments)]
    fn build(
        &mut self,
        points: &[[f64; 3]],
        mirrors: &[Mirror],
        centre: [f64; 3],
        half: [f64; 3],
        start: usize,
        end: usize,
        level: usize,
        leaf: usize,
    ) -> usize {
        let radius = self.order[start..end]
            .iter()
            .map(|&i| distance(points[i], centre))
            .fold(0.0, f64::max);
        let members = &self.order[start..end];
        let merged = mirrors
            .iter()
            .enumerate()
            .map(|(mirror, m)| {
                let h = m.distance(centre);
                let centre: [f64; 3] = std::array::from_fn(|k| centre[k] - h * m.normal[k]);
                let radius = members
                    .iter()
                    .map(|&i| distance(points[i], centre))
                    .fold(0.0, f64::max);
                let height = members
                    .iter()
                    .map(|&i| m.distance(points[i]).abs())
                    .fold(0.0, f64::max);
                Merged {
                    mirror,
                    centre,
                    radius,
                    height,
                }
            })
            .filter(|m| m.radius <= MERGE * radius)
            .min_by(|a, b| a.radius.total_cmp(&b.radius));
        let me = self.cells.len();
        self.cells.push(Cell {
            centre,
            radius,
            merged,
            start,
            end,
            children: Vec::new(),
            level,
        });
        // cells of coincident points would split forever: a depth of 144 halves each
        // side of the root 48 times, to 4e-15 of itself
        if end - start <= leaf || level >= 144 {
            return me;
        }
        let longest = half.iter().copied().fold(0.0, f64::max);
        let axis = (0..3).find(|&k| half[k] == longest).unwrap_or(0);
        let child_half: [f64; 3] =
            std::array::from_fn(|k| if k == axis { half[k] / 2.0 } else { half[k] });
        // stable partition of this cell's particles by half
        let mut by: Vec<Vec<usize>> = vec![Vec::new(); 2];
        for &i in &self.order[start..end] {
            by[usize::from(points[i][axis] >= centre[axis])].push(i);
        }
        let mut at = start;
        let mut children = Vec::new();
        for (o, members) in by.into_iter().enumerate() {
            if members.is_empty() {
                continue;
            }
            let len = members.len();
            self.order[at..at + len].copy_from_slice(&members);
            let c: [f64; 3] = std::array::from_fn(|k| match (k == axis, o == 1) {
                (false, _) => centre[k],
                (true, true) => centre[k] + half[k] / 2.0,
                (true, false) => centre[k] - half[k] / 2.0,
            });
            children.push(self.build(
                points,
                mirrors,
                c,
                child_half,
                at,
                at + len,
                level + 1,
                leaf,
            ));
            at += len;
        }
        self.cells[me].children = children;
        me
    }

    /// Whether the multipoles of `s` (and of each of its images, or their shared
    /// expansion) reach `t`.
    fn accepts(&self, t: usize, s: usize, theta: f64, mirrors: &[Mirror]) -> bool {
        let (ct, cs) = (&self.cells[t], &self.cells[s]);
        let reaches = |centre: [f64; 3], radius: f64| {
            ct.radius + radius < theta * distance(ct.centre, centre)
        };
        let shared = cs.merged.map(|m| m.mirror);
        cs.merged.map_or(reaches(cs.centre, cs.radius), |m| {
            reaches(m.centre, m.radius)
        }) && mirrors
            .iter()
            .enumerate()
            .filter(|&(k, _)| Some(k) != shared)
            .all(|(_, m)| reaches(m.image(cs.centre), cs.radius))
    }

    fn traverse(&mut self, t: usize, s: usize, theta: f64, mirrors: &[Mirror]) {
        if t != s && self.accepts(t, s, theta, mirrors) {
            self.far[t].push(s);
            return;
        }
        let (lt, ls) = (self.cells[t].is_leaf(), self.cells[s].is_leaf());
        if lt && ls {
            self.near[t].push(s);
            return;
        }
        let split_source = !ls && (lt || self.cells[s].radius >= self.cells[t].radius);
        if split_source {
            for c in self.cells[s].children.clone() {
                self.traverse(t, c, theta, mirrors);
            }
        } else {
            for c in self.cells[t].children.clone() {
                self.traverse(c, s, theta, mirrors);
            }
        }
    }
}
