//! `stokesian doublet`: the CSV or `.npy`, the contour plots and the maximum rate.

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
        let p = stokesian::studies::doublet::doublet(row[0], row[1], &lub).expect("doublet");
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

/// `.npy`: a float64 array of shape (points, 6), the CSV's columns and numbers bit for
/// bit, the plots beside it; another extension is refused before any work.
#[test]
fn doublet_npy_has_the_csv_columns_bit_for_bit() {
    let dir = Dir::new("doublet-npy");
    let grid = [
        "--r-points",
        "3",
        "--h-points",
        "2",
        "--r-max",
        "3",
        "--h-max",
        "2",
    ];
    let doublet = |out: &str| {
        let mut args = vec!["doublet", "--out", out];
        args.extend(grid);
        run(&args)
    };
    let (csv, npy) = (dir.path("d.csv"), dir.path("e.npy"));
    assert_ok(&doublet(s(&csv)));
    assert_ok(&doublet(s(&npy)));
    let want = read_csv(
        &csv,
        "r,h,rate_resistance,rate_farfield,tension_resistance,tension_farfield",
    );
    let got = read_npy(&npy);
    assert_eq!(got.shape(), (6, 6));
    for (i, row) in want.iter().enumerate() {
        for (j, w) in row.iter().enumerate() {
            assert_eq!(got[(i, j)].to_bits(), w.to_bits(), "({i}, {j})");
        }
    }
    let written = ["d.csv", "d.png", "d.svg", "e.npy", "e.png", "e.svg"];
    assert_eq!(dir.listing(), written);
    let bad = dir.path("f.txt");
    assert_fails(
        &doublet(s(&bad)),
        &["f.txt: the file name must end in .csv or .npy"],
        &dir,
        &written,
    );
}
