//! Fused multiply-adds of the lane kernels.

use crate::graph::{Graph, Id, Op};

/// Fused multiply-adds of the lane kernels: for each `+` or `-` node, an operand that
/// is a product used only by sums (fused into `mul_add`, `mul_sub` or `neg_mul_add`),
/// as `(node, operand)`; and for each fused product, whether it is fused (so it is not
/// emitted on its own). A product is fused only if every one of its uses takes it
/// fused: used by `k` sums, it then costs `k` multiply-adds instead of a product and `k`
/// sums (each sum rounds the exact product once, as a single fused use always did).
pub struct Fusion {
    /// `fused_into[n] = Some(m)`: node `n` (`+`/`-`) takes the product `m` fused.
    pub fused_into: Vec<Option<Id>>,
    /// `fused[m]`: product `m` is emitted only inside its users (or a sum, only inside
    /// its negation).
    pub fused: Vec<bool>,
    /// `negated[n]`: node `n` is `-(x y + c)` of a sum used only there with its product
    /// fused, emitted as one `neg_mul_sub` (the sum is `fused`).
    pub negated: Vec<bool>,
}

impl Fusion {
    /// The fusions among the nodes `live`, of which `named` (outputs, conditions) are
    /// used by name.
    pub fn of(g: &Graph, live: &[bool], named: &[Id]) -> Fusion {
        // uses of each node, and uses as an operand of a sum
        let (mut uses, mut in_sums) = (vec![0u32; g.len()], vec![0u32; g.len()]);
        for id in 0..g.len() {
            if !live[id] {
                continue;
            }
            let op = g.op(id as Id);
            let sum = matches!(op, Op::Add(..) | Op::Sub(..));
            for a in op.operands() {
                uses[a as usize] += 1;
                in_sums[a as usize] += u32::from(sum);
            }
        }
        for &n in named {
            uses[n as usize] += 1;
        }
        let candidate =
            |x: Id| matches!(g.op(x), Op::Mul(..)) && uses[x as usize] == in_sums[x as usize];
        let mut fused_into = vec![None; g.len()];
        let mut taken = vec![0u32; g.len()];
        for id in 0..g.len() {
            if !live[id] {
                continue;
            }
            if let Op::Add(a, b) | Op::Sub(a, b) = g.op(id as Id) {
                // a product used once first: it is fused whatever the others do
                let pick = [a, b]
                    .into_iter()
                    .filter(|&x| candidate(x))
                    .min_by_key(|&x| uses[x as usize] != 1);
                if let Some(m) = pick {
                    fused_into[id] = Some(m);
                    taken[m as usize] += 1;
                }
            }
        }
        // a product some use does not take fused (`x + x`, or a sum fusing its other
        // operand) is emitted on its own, and every sum then uses its value; such a
        // sum may fuse its other operand if that is a product used once
        let mut fused: Vec<bool> = (0..g.len())
            .map(|m| taken[m] > 0 && taken[m] == uses[m])
            .collect();
        for id in 0..g.len() {
            let Some(m) = fused_into[id] else { continue };
            if fused[m as usize] {
                continue;
            }
            fused_into[id] = None;
            if let Op::Add(a, b) | Op::Sub(a, b) = g.op(id as Id) {
                let other = if m == a { b } else { a };
                if matches!(g.op(other), Op::Mul(..))
                    && uses[other as usize] == 1
                    && !fused[other as usize]
                {
                    fused_into[id] = Some(other);
                    fused[other as usize] = true;
                }
            }
        }
        // a negated multiply-add, `-(x y + c)`, is one instruction too
        let mut negated = vec![false; g.len()];
        for id in 0..g.len() {
            if !live[id] {
                continue;
            }
            if let Op::Neg(s) = g.op(id as Id) {
                let s = s as usize;
                if matches!(g.op(s as Id), Op::Add(..)) && fused_into[s].is_some() && uses[s] == 1 {
                    negated[id] = true;
                    fused[s] = true;
                }
            }
        }
        Fusion {
            fused_into,
            fused,
            negated,
        }
    }

    /// How many products are fused among the nodes `want` (each saves one operation).
    pub fn count(&self, want: &[bool]) -> usize {
        self.fused
            .iter()
            .zip(want)
            .filter(|(f, w)| **f && **w)
            .count()
    }
}
