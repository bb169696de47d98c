//! Reciprocals of a lane kernel that share one division (Montgomery's trick).

use crate::graph::{Graph, Id, Op};
use proc_macro2::TokenStream;

/// Groups of reciprocals `1/x` among the nodes `want` (not yet named) that share one
/// division (Montgomery's trick): `p_i = x_1 ... x_i`, `q = 1/p_k`, then
/// `1/x_i = q_i p_(i-1)`, `q_(i-1) = q_i x_i`. A reciprocal joins the first group none of
/// whose members its argument depends on. A division costs the latency and the
/// throughput of about 16 multiplications in the vector units; the trick trades
/// `k - 1` of them for `3 (k - 1)` multiplications, at the price of about two ulps.
pub(super) fn reciprocal_groups(
    g: &Graph,
    want: &[bool],
    name: &[Option<TokenStream>],
) -> Vec<Vec<Id>> {
    let recips: Vec<Id> = (0..g.len() as Id)
        .filter(|&id| want[id as usize] && name[id as usize].is_none())
        .filter(|&id| matches!(g.op(id), Op::Div(a, _) if g.as_const(a) == Some(1.0)))
        .collect();
    if recips.len() < 2 || recips.len() > 128 {
        return Vec::new();
    }
    // dep[n]: which reciprocals node n depends on (bit k for recips[k])
    let mut dep = vec![0u128; g.len()];
    for id in 0..g.len() {
        let mut m = g
            .op(id as Id)
            .operands()
            .iter()
            .fold(0u128, |m, &a| m | dep[a as usize]);
        if let Some(k) = recips.iter().position(|&r| r == id as Id) {
            m |= 1 << k;
        }
        dep[id] = m;
    }
    let mut groups: Vec<(u128, Vec<Id>)> = Vec::new();
    for (k, &r) in recips.iter().enumerate() {
        let Op::Div(_, x) = g.op(r) else {
            unreachable!("reciprocals are divisions")
        };
        match groups
            .iter_mut()
            .find(|(mask, _)| dep[x as usize] & mask == 0)
        {
            Some((mask, members)) => {
                *mask |= 1 << k;
                members.push(r);
            }
            None => groups.push((1 << k, vec![r])),
        }
    }
    groups
        .into_iter()
        .map(|(_, m)| m)
        .filter(|m| m.len() > 1)
        .collect()
}
