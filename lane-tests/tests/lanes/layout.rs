//! The flat layouts of the lane kernels' outputs (`kernels::blocks`): the fields of the
//! returned blocks flattened in their order are the grand matrix, and the lane product
//! over them is the blocks' product.

use kernels::blocks::{
    grand_lanes_product, truncate_lanes, BlocksF, BlocksFT, Grand, FT_FLAT, F_FLAT, GRAND_FLAT,
};
use nalgebra::SMatrix;

/// `GRAND_FLAT` reads `Grand::matrix` back from the fields flattened in their
/// order (and `FT_FLAT`, `F_FLAT` their truncations, `truncate_lanes`), and
/// `grand_lanes_product` (on `f64` lanes) is `Grand::product`: the
/// same products summed in the same order, fused (exact small integers here, so
/// equal bit for bit).
#[test]
fn flattened_fields_are_the_grand_matrix() {
    let m = SMatrix::<f64, 11, 11>::from_fn(|i, j| (i * 11 + j) as f64);
    let g = Grand::from_matrix(&m);
    let flat: Vec<f64> = [
        g.uf.concat(),
        g.ul.concat(),
        g.us.concat(),
        g.of.concat(),
        g.ol.concat(),
        g.os.concat(),
        g.ef.concat(),
        g.el.concat(),
        g.es.concat(),
    ]
    .concat();
    assert_eq!(flat.len(), 121);
    for i in 0..11 {
        for j in 0..11 {
            assert_eq!(flat[GRAND_FLAT[i][j]], m[(i, j)], "entry ({i}, {j})");
        }
    }
    let lanes: [f64; 121] = std::array::from_fn(|k| flat[k]);
    let va: [f64; 11] = std::array::from_fn(|k| k as f64 - 5.0);
    let vb: [f64; 11] = std::array::from_fn(|k| 2.0 * k as f64 + 1.0);
    let (a, b) = grand_lanes_product(&lanes, va, vb);
    let want = g.product(va, vb);
    assert_eq!((a, b), (want.a, want.b));
    // the F and FT truncations: their fields flattened, placed by F_FLAT and FT_FLAT
    let ft = BlocksFT::from(&g);
    let ft_flat = [
        ft.uf.concat(),
        ft.ul.concat(),
        ft.of.concat(),
        ft.ol.concat(),
    ]
    .concat();
    let ftm = ft.matrix();
    for i in 0..6 {
        for j in 0..6 {
            assert_eq!(ft_flat[FT_FLAT[i][j]], ftm[i][j], "FT entry ({i}, {j})");
        }
    }
    let got: [f64; 36] = truncate_lanes(lanes, &FT_FLAT);
    assert_eq!(got.to_vec(), ft_flat);
    let f = BlocksF::from(&g);
    let got: [f64; 9] = truncate_lanes(lanes, &F_FLAT);
    assert_eq!(got.to_vec(), f.uf.concat());
    assert_eq!(F_FLAT, [[0, 1, 2], [3, 4, 5], [6, 7, 8]]);
}
