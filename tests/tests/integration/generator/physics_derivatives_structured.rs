use kernel_gen::number::dd::Dd;
use kernel_gen::physics::derivatives::{Collection, Differences, Form, Structured};
use kernel_gen::physics::green::wall::Wall;
use kernel_gen::physics::operators::Derivatives;

/// The wall's UF block with both Faxen Laplacians, at a lateral distance where the
/// Stokeslet and its image cancel to 4e-4 of either, in every form the generator
/// traces (three collections, the exact difference for every term or for the
/// leading ones only) against the plain direct sum in double-double: 1e-14 of the
/// block's largest entry covers the f64 rounding of every form (the plain sum in
/// f64 would lose about `eps rho^2/(h_a h_b)` = 1e-12 here).
#[test]
fn every_form_of_a_faxen_block_agrees() {
    use kernel_gen::physics::operators::{block, max_order, Basis, Moment, Response};
    let (x, y, p) = ([0.3, -0.7, 1.9], [60.1, 32.4, 1.4], [0.25]);
    let (aa2, ab2) = (0.64, 1.21);
    let order = max_order(Response::U, Moment::F);
    let terms = block(Response::U, Moment::F, Basis::Cartesian);
    let dd = |v: [f64; 3]| v.map(Dd::new);
    let mut reference =
        Structured::new(&Wall, &dd(x), &dd(y), &[Dd::new(p[0])], order, true, true).direct_sum();
    let want: Vec<f64> = terms
        .iter()
        .flatten()
        .map(|t| reference.combine(t, &Dd::new(aa2), &Dd::new(ab2)).to_f64())
        .collect();
    let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for collect in [
        Collection::Atoms,
        Collection::Centres,
        Collection::Entries,
        Collection::EntriesOnSphere,
    ] {
        for differences in [Differences::All, Differences::Leading] {
            let form = Form {
                collect,
                differences,
            };
            let mut s = Structured::new(&Wall, &x, &y, &p, order, true, true).in_form(form);
            for (t, w) in terms.iter().flatten().zip(&want) {
                let got = s.combine(t, &aa2, &ab2);
                assert!((got - w).abs() <= 1e-14 * scale, "{form:?}: {got:e} {w:e}");
            }
        }
    }
}
