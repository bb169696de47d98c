//! `doublet`: the co-rotating doublet above a wall (Swan & Brady Sec. III B, Figs. 2-3)
//! on a grid of separations and heights, its maximum rotation rate, and the contour
//! plot.

use crate::error::CliError;
use crate::options::finite;
use crate::output::{self, check_out, temporary, write_atomically, Format};
use crate::plot;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget};
use std::fs;
use std::path::PathBuf;

pub const ABOUT: &str = "\
The co-rotating doublet of Swan & Brady (Sec. III B, Figs. 2-3): two equal spheres
(radius a) at height h above a no-slip wall, centres r apart, with equal and opposite
torques T along their line of centres and otherwise force- and torque-free (FTS, no
imposed flow). Near the wall they translate in opposite directions and the doublet turns
about its centre. On a grid of r in [--r-min, --r-max] and h in [--h-min, --h-max]
(geometric in the gaps r/a - 2 and h/a - 1), for the resistance with lubrication
(Eq. 19) and for the far-field mobility alone, it computes the rotation rate
8 pi eta a^3 Omega / T and the tension tau a / T a wire joining the spheres must carry
to keep r fixed (positive: pulling them together).

Writes --out (CSV: r,h,rate_resistance,rate_farfield,tension_resistance,
tension_farfield, r and h over a; or .npy, a float64 array of shape (points, 6) with the
same columns) and, beside it with the same stem, a filled contour plot of the rate with
lubrication (.png and .svg); prints the maximum rate and where it is (the grid maximum
refined by a pattern search).";

/// `doublet`: the grid and the output.
#[derive(Args, Debug)]
pub struct DoubletArgs {
    /// Output file, its format by the extension: .csv or .npy (shape (points, 6)); the
    /// contour plot is written beside it as .png and .svg.
    #[arg(long, value_name = "doublet.csv|doublet.npy")]
    out: PathBuf,
    /// Smallest separation r/a (> 2).
    #[arg(long, default_value_t = 2.0001)]
    r_min: f64,
    /// Largest separation r/a.
    #[arg(long, default_value_t = 6.0)]
    r_max: f64,
    /// Smallest height h/a (> 1).
    #[arg(long, default_value_t = 1.0001)]
    h_min: f64,
    /// Largest height h/a.
    #[arg(long, default_value_t = 4.0)]
    h_max: f64,
    /// Grid points in r (>= 2).
    #[arg(long, default_value_t = 61)]
    r_points: usize,
    /// Grid points in h (>= 2).
    #[arg(long, default_value_t = 61)]
    h_points: usize,
}

/// Geometric grid from `lo` to `hi` (both > 0), `n >= 2` points.
fn geometric(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| lo * (hi / lo).powf(k as f64 / (n - 1) as f64))
        .collect()
}

pub fn run(args: &DoubletArgs) -> Result<(), CliError> {
    use rayon::prelude::*;
    use stokesian::studies::doublet::{doublet, DoubletPoint};
    let format = check_out(&args.out, &[Format::Csv, Format::Npy])?;
    for (option, value, floor) in [
        ("--r-min", args.r_min, 2.0),
        ("--r-max", args.r_max, 2.0),
        ("--h-min", args.h_min, 1.0),
        ("--h-max", args.h_max, 1.0),
    ] {
        finite(option, value)?;
        if value <= floor {
            return Err(CliError::BadOption {
                option,
                value: format!("{value}"),
                reason: format!(
                    "must be above {floor} (touching {})",
                    if floor == 2.0 { "spheres" } else { "the wall" }
                ),
            });
        }
    }
    for (option, lo, hi) in [
        ("--r-max", args.r_min, args.r_max),
        ("--h-max", args.h_min, args.h_max),
    ] {
        if hi <= lo {
            return Err(CliError::BadOption {
                option,
                value: format!("{hi}"),
                reason: format!("must be above the minimum {lo}"),
            });
        }
    }
    for (option, n) in [("--r-points", args.r_points), ("--h-points", args.h_points)] {
        if n < 2 {
            return Err(CliError::BadOption {
                option,
                value: n.to_string(),
                reason: "needs at least 2 points".to_string(),
            });
        }
    }
    let gaps_r = geometric(args.r_min - 2.0, args.r_max - 2.0, args.r_points);
    let gaps_h = geometric(args.h_min - 1.0, args.h_max - 1.0, args.h_points);
    let lub = stokesian::Lubrication::default();
    let pb = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    output::bar(
        &pb,
        (gaps_r.len() * gaps_h.len()) as u64,
        "points",
        true,
        "doublet".to_string(),
    );
    let points: Vec<DoubletPoint> = gaps_r
        .par_iter()
        .flat_map_iter(|&gr| gaps_h.iter().map(move |&gh| (gr, gh)))
        .map(|(gr, gh)| {
            let p = doublet(2.0 + gr, 1.0 + gh, &lub);
            pb.inc(1);
            p
        })
        .collect::<Result<_, _>>()
        .inspect_err(|_| pb.finish_and_clear())?;
    pb.finish_and_clear();
    // the maximum rate with lubrication: grid maximum, refined by a pattern search in
    // (ln(r - 2), ln(h - 1)) with steps halved down to 1e-6 of the grid spacing
    let best = points
        .iter()
        .max_by(|p, q| p.rate_resistance.total_cmp(&q.rate_resistance))
        .copied()
        .ok_or_else(|| CliError::Numerical("empty grid".to_string()))?;
    let rate = |u: f64, v: f64| -> Result<f64, CliError> {
        let (r, h) = (2.0 + u.exp(), 1.0 + v.exp());
        if r > args.r_max || h > args.h_max || r < args.r_min || h < args.h_min {
            return Ok(f64::NEG_INFINITY);
        }
        Ok(doublet(r, h, &lub)?.rate_resistance)
    };
    let (mut u, mut v, mut top) = (
        (best.r - 2.0).ln(),
        (best.h - 1.0).ln(),
        best.rate_resistance,
    );
    let (mut du, mut dv) = ((gaps_r[1] / gaps_r[0]).ln(), (gaps_h[1] / gaps_h[0]).ln());
    let stop = 1e-6 * du.min(dv);
    while du.max(dv) > stop {
        let mut moved = false;
        for (su, sv) in [(du, 0.0), (-du, 0.0), (0.0, dv), (0.0, -dv)] {
            let value = rate(u + su, v + sv)?;
            if value > top {
                (u, v, top, moved) = (u + su, v + sv, value, true);
            }
        }
        if !moved {
            du *= 0.5;
            dv *= 0.5;
        }
    }
    let (r_top, h_top) = (2.0 + u.exp(), 1.0 + v.exp());
    write_atomically(&args.out, |w| {
        let columns = [
            "r",
            "h",
            "rate_resistance",
            "rate_farfield",
            "tension_resistance",
            "tension_farfield",
        ];
        let rows = points.iter().map(|p| {
            [
                p.r,
                p.h,
                p.rate_resistance,
                p.rate_farfield,
                p.tension_resistance,
                p.tension_farfield,
            ]
        });
        output::write_table(w, format, &columns, points.len(), rows)
    })?;
    let rates: Vec<Vec<f64>> = points
        .chunks(gaps_h.len())
        .map(|c| c.iter().map(|p| p.rate_resistance).collect())
        .collect();
    let field = plot::Field {
        x: &gaps_r,
        y: &gaps_h,
        z: &rates,
        x_label: "r/a - 2",
        y_label: "h/a - 1",
        title: "doublet rotation rate 8 pi eta a^3 Omega / T (Eq. 19)",
        mark: (r_top - 2.0, h_top - 1.0),
    };
    let mut written = vec![args.out.display().to_string()];
    for ext in ["png", "svg"] {
        let path = args.out.with_extension(ext);
        let shown = path.display().to_string();
        let tmp = temporary(&path, &format!(".{ext}"));
        plot::filled_contours(&tmp, &field, 16)
            .and_then(|()| fs::rename(&tmp, &path).map_err(|e| e.to_string()))
            .map_err(|reason| {
                let _ = fs::remove_file(&tmp);
                CliError::Plot {
                    path: shown.clone(),
                    reason,
                }
            })?;
        written.push(shown);
    }
    let (worst_t_res, worst_t_far) = points.iter().fold((0.0f64, 0.0f64), |(a, b), p| {
        (
            a.max(p.tension_resistance.abs()),
            b.max(p.tension_farfield.abs()),
        )
    });
    println!(
        "maximum rate with lubrication 8 pi eta a^3 Omega / T = {top:.6} at r = {r_top:.6} a, \
         h = {h_top:.6} a (grid maximum {:.6} at r = {:.6} a, h = {:.6} a)",
        best.rate_resistance, best.r, best.h
    );
    println!(
        "largest |tension| a / T: {worst_t_res:.3e} with lubrication, {worst_t_far:.3e} far field"
    );
    println!("wrote {}", written.join(", "));
    Ok(())
}
