//! Section c, stiff and extreme cases: the norm-wise relative error per block of every
//! generated kernel of every confinement against a double-double evaluation of the
//! plain direct sum (`kernel_gen::kernel::evaluate_direct`), for lateral separations up to 1e8 heights, gaps down to 1e-12 a, radius
//! ratios up to 1e3, heights up to 1e8 a and nanometre and unit scales. The measurement
//! is `integration_tests::stiff::stiff_cases`, the same function whose rows
//! `tests/tests/integration/generated/stiff_cases.rs` asserts; this section prints the worst of each case and
//! confinement, and where it is.

use super::table::{err, Table};
use super::{Ctx, Section};
use anyhow::Result;
use integration_tests::stiff::{stiff_cases_of, StiffRow, TOL};
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// Section c.
pub fn section(ctx: &Ctx) -> Result<Section> {
    ctx.progress.inc_length(1);
    ctx.progress
        .set_message("stiff and extreme cases (double-double references)");
    let only = ctx.cfg.stiff_only;
    let rows = stiff_cases_of(&|name| only.is_none() || only == Some(name));
    ctx.progress.inc(1);
    // the worst row per (case, confinement)
    // the worst row per (case, confinement), and the plain direct sum's worst there
    let mut worst: BTreeMap<(&str, String), (&StiffRow, f64)> = BTreeMap::new();
    for r in &rows {
        let e = worst
            .entry((r.case, r.confinement.clone()))
            .or_insert((r, 0.0));
        if r.error > e.0.error {
            e.0 = r;
        }
        e.1 = e.1.max(r.direct_sum);
    }
    let mut t = Table::new(&[
        "case",
        "confinement",
        "worst error",
        "kernel and configuration",
        "block",
        "parameter",
        "plain direct sum (worst)",
    ]);
    for ((case, conf), (r, direct)) in &worst {
        t.row(vec![
            case.to_string(),
            conf.clone(),
            err(Some(r.error)),
            format!("`{}`", r.kernel),
            r.block.clone(),
            // three significant digits, shortest form (6.85e2, 1e-3)
            format!(
                "{:e}",
                format!("{:.2e}", r.parameter)
                    .parse::<f64>()
                    .unwrap_or(r.parameter)
            ),
            err(Some(*direct)),
        ]);
    }
    let above: Vec<&StiffRow> = rows.iter().filter(|r| r.error > TOL).collect();
    let mut body = String::new();
    writeln!(
        body,
        "Every generated kernel of every confinement (self, pair, equal-radius pair, fused \
         products; F, FT and FTS) against the same kernel's plain direct sum evaluated straight \
         in double-double with exact rational weights (`kernel_gen::kernel::evaluate_direct`), \
         error norm-wise per block (`||B - B_ref|| / ||B_ref||`), over the \
         configurations of `integration_tests::stiff::stiff_cases` ({} block measurements): \
         lateral separation over height rho/h from 1e2 to 1e8 (the Stokeslet and its image \
         cancel to `h_a h_b / rho^3`), gaps to the wall and between spheres down to 1e-12 a, \
         radius ratios up to 1e3, heights up to 1e8 a, and a = 1e-9 m with eta = 1e-3 Pa s \
         next to a = 1 with eta = 1. The worst block of each case and confinement, and \
         beside it the worst of the same configurations for the plain direct sum of the \
         Stokeslet and its image traced and evaluated in f64 (what the kernels would lose \
         without the generator's stable forms, i.e. before them):\n",
        rows.len()
    )?;
    body.push_str(&t.markdown());
    writeln!(body)?;
    if above.is_empty() {
        writeln!(body, "No block loses more than {TOL:e} relative accuracy.")?;
    } else {
        let largest = above.iter().map(|r| r.error).fold(0.0, f64::max);
        writeln!(
            body,
            "{} block measurements lose more than {TOL:e} (largest {}).",
            above.len(),
            err(Some(largest))
        )?;
    }
    writeln!(
        body,
        "\nThe stable forms: the exactly evaluated difference of the Stokeslet and its wall \
         image (`|R|^2 - |r|^2 = 4 h_a h_b` carried through the jets, \
         `kernel_gen::physics::derivatives`), the exchange of roles that makes the lower particle the \
         source (`kernel_gen::kernel::Swap`), the lateral far-field expansion \
         (`kernel_gen::physics::farfield`), the closed-form reflected self term \
         (`kernel_gen::physics::self_image`), and exact operator coefficients \
         (`kernel_gen::physics::operators::exact_block`)."
    )?;
    Ok(Section {
        title: "c. Stiff and extreme cases".to_string(),
        body,
    })
}
