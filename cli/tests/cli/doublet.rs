//! `stokesian doublet`: the CSV, the contour plots and the maximum rate.

use crate::common::*;
use std::fs;

/// `stokesian doublet` writes the CSV with the header (one row per grid point,
/// each row equal to the library's `doublet` at that point), the contour plot as PNG and
/// SVG beside it, and prints the maximum; bad grids fail without output.
#[test]
fn doublet_writes_csv_and_plots_and_rejects_bad_grids() {
    let dir = Dir::new("doublet");
    let out = dir.path("d.csv");
    let args = [
        "doublet",
        "--out",
        s(&out),
        "--r-points",
        "4",
        "--h-points",
        "3",
        "--r-max",
        "3",
        "--h-max",
        "2",
    ];
    let o = run(&args);
    assert_ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("maximum rate with lubrication"), "{stdout}");
    let text = fs::read_to_string(&out).expect("csv");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("r,h,rate_resistance,rate_farfield,tension_resistance,tension_farfield")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 12);
    let lub = stokesian::Lubrication::default();
    for row in &rows {
        let p = stokesian::doublet::doublet(row[0], row[1], &lub).expect("doublet");
        let want = [
            p.r,
            p.h,
            p.rate_resistance,
            p.rate_farfield,
            p.tension_resistance,
            p.tension_farfield,
        ];
        for (g, w) in row.iter().zip(want) {
            assert_eq!(g.to_bits(), w.to_bits(), "{row:?}");
        }
    }
    assert_eq!(rows[0][0], 2.0001);
    assert_eq!(rows[11][0], 3.0);
    let png = fs::read(dir.path("d.png")).expect("png");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let svg = fs::read_to_string(dir.path("d.svg")).expect("svg");
    assert!(svg.contains("<svg"));
    assert_eq!(dir.listing(), ["d.csv", "d.png", "d.svg"]);

    let bad = dir.path("bad.csv");
    for (option, value, needle) in [
        ("--r-min", "2", "must be above 2"),
        ("--h-min", "0.5", "must be above 1"),
        ("--r-points", "1", "at least 2"),
        ("--h-max", "1.00001", "above the minimum"),
    ] {
        let o = run(&["doublet", "--out", s(&bad), option, value]);
        assert_fails(&o, &[option, needle], &dir, &["d.csv", "d.png", "d.svg"]);
    }
}
