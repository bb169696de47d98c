//! Section b, physics: the resistance functions of one sphere near a wall and of two
//! equal spheres in unbounded fluid, from the solver at the truncation levels F, FT and
//! FTS, far field only (the inverse of `stokesian::System::mobility`) and with
//! lubrication (`stokesian::System::resistance` with `stokesian::Lubrication::default()`),
//! against exact results: the bispherical series of `stokesian::resistance::exact` (Brenner,
//! O'Neill, Dean & O'Neill / Goldman-Cox-Brenner, Jeffery; Stimson & Jeffery for the
//! pair along the line of centres) and the two-sphere twin-multipole series of
//! `stokesian::resistance::two_sphere` (across the line of centres); and the run time per particle.

use super::table::{self, Table};
use super::timing::ns_per_eval;
use super::{plot, Ctx, Section};
use anyhow::{anyhow, Context, Result};
use integration_tests::configurations::{
    equal_pair, free_surface_functions_of, pair_functions_of, sphere_above_free_surface,
    sphere_above_wall, wall_functions_of,
};
use nalgebra::DMatrix;
use std::fmt::Write as _;
use std::hint::black_box;
use stokesian::resistance::exact::{
    brenner_xa_free_surface, brenner_xa_wall, jeffery_xc_free_surface, jeffery_xc_wall,
    oneill_parallel, rotation_parallel, two_sphere_xa, two_sphere_xc,
};
use stokesian::{Lubrication, Moments, System};

/// A truncation level, with or without lubrication.
#[derive(Clone, Copy, Debug)]
struct Method {
    level: Moments,
    lubrication: bool,
}

const METHODS: [Method; 5] = [
    Method {
        level: Moments::F,
        lubrication: false,
    },
    Method {
        level: Moments::FT,
        lubrication: false,
    },
    Method {
        level: Moments::FT,
        lubrication: true,
    },
    Method {
        level: Moments::FTS,
        lubrication: false,
    },
    Method {
        level: Moments::FTS,
        lubrication: true,
    },
];

impl Method {
    fn name(self) -> String {
        let l = match self.level {
            Moments::F => "F",
            Moments::FT => "FT",
            Moments::FTS => "FTS",
        };
        if self.lubrication {
            format!("{l} + lubrication")
        } else {
            format!("{l} far field")
        }
    }

    /// The force-torque resistance of `sys` in the FT layout (all F then all L rows;
    /// all U then all Omega columns; F level: the 3N x 3N block): the inverse of the
    /// mobility (FTS: its force-torque block, rigid spheres in a quiescent fluid), or
    /// Eq. 19 with lubrication.
    fn resistance(self, sys: &System) -> Result<DMatrix<f64>> {
        let n = sys.len();
        let r = if self.lubrication {
            sys.resistance(self.level, &Lubrication::default())?
        } else {
            sys.mobility(self.level)
                .cholesky()
                .ok_or_else(|| anyhow!("mobility not positive definite"))?
                .inverse()
        };
        let k = match self.level {
            Moments::F => 3 * n,
            _ => 6 * n,
        };
        Ok(r.view((0, 0), (k, k)).into_owned())
    }
}

fn geometric(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if n == 1 {
        return vec![lo];
    }
    (0..n)
        .map(|k| lo * (hi / lo).powf(k as f64 / (n - 1) as f64))
        .collect()
}

/// One case: configurations, the functions it compares, and how to read them.
struct Case {
    name: &'static str,
    /// Names of the functions.
    functions: Vec<&'static str>,
    /// Number of spheres.
    n: usize,
    /// Systems over the sweep, with the sweep parameter.
    systems: Vec<(f64, System)>,
    /// Exact values at a sweep parameter.
    exact: fn(f64) -> Result<Vec<f64>>,
    /// The functions from a resistance (FT layout), `None` where the level lacks them.
    read: fn(&DMatrix<f64>) -> Vec<Option<f64>>,
    /// Whether a sweep parameter lies inside the default lubrication cutoff.
    inside: fn(f64) -> bool,
}

fn sphere_wall(sweep: usize) -> Result<Case> {
    let systems = geometric(1e-3, 9.0, sweep)
        .into_iter()
        .map(|eps| (1.0 + eps, sphere_above_wall(1.0 + eps)))
        .collect();
    Ok(Case {
        name: "one sphere and a wall",
        functions: vec!["X^A_w", "Y^A_w", "F^r", "Y^C_w", "X^C_w"],
        n: 1,
        systems,
        exact: |h| {
            let (ya, _) = oneill_parallel(h);
            let (fr, yc) = rotation_parallel(h);
            Ok(vec![brenner_xa_wall(h), ya, fr, yc, jeffery_xc_wall(h)])
        },
        inside: |h| {
            h - 1.0
                < Lubrication::default()
                    .wall_cutoff
                    .min(stokesian::resistance::wall_tables::EPS_MAX)
        },
        read: |r| wall_functions_of(r).to_vec(),
    })
}

fn sphere_free_surface(sweep: usize) -> Result<Case> {
    let systems = geometric(1e-3, 9.0, sweep)
        .into_iter()
        .map(|eps| (1.0 + eps, sphere_above_free_surface(1.0 + eps)))
        .collect();
    Ok(Case {
        name: "one sphere and a free surface",
        functions: vec!["X^A_fs", "X^C_fs"],
        n: 1,
        systems,
        exact: |h| Ok(vec![brenner_xa_free_surface(h), jeffery_xc_free_surface(h)]),
        // sphere and image are two equal spheres at s' = 2h/a
        inside: |h| 2.0 * h < Lubrication::default().pair_window(Moments::FTS).0,
        read: |r| free_surface_functions_of(r).to_vec(),
    })
}

fn two_spheres(sweep: usize) -> Result<Case> {
    let systems = geometric(1e-3, 3.0, sweep)
        .into_iter()
        .map(|xi| (xi, equal_pair(xi)))
        .collect();
    Ok(Case {
        name: "two equal spheres",
        functions: vec![
            "X11A", "X12A", "X11C", "X12C", "Y11A", "Y12A", "Y11B", "Y12B", "Y11C", "Y12C",
        ],
        n: 2,
        systems,
        exact: |xi| {
            let (xa11, xa12) = two_sphere_xa(xi);
            let (xc11, xc12) = two_sphere_xc(xi);
            let s = stokesian::resistance::two_sphere::resistance_scalars(2.0 + xi, 1.0)
                .with_context(|| format!("two-sphere series at xi = {xi}"))?;
            Ok(vec![
                xa11, xa12, xc11, xc12, s.y11a, s.y12a, s.y11b, s.y12b, s.y11c, s.y12c,
            ])
        },
        // FTS has the narrower window of the two levels
        inside: |xi| 2.0 + xi < Lubrication::default().pair_window(Moments::FTS).0,
        read: |r| pair_functions_of(r).to_vec(),
    })
}

/// Per method: per function the largest relative error over the sweep, all errors, and
/// the time per particle.
struct Measured {
    method: Method,
    per_function: Vec<Option<f64>>,
    all: Vec<f64>,
    /// All errors where the lubrication correction is kept in full.
    inside: Vec<f64>,
    ns_per_particle: f64,
}

fn measure(ctx: &Ctx, case: &Case) -> Result<Vec<Measured>> {
    let exact: Vec<Vec<f64>> = case
        .systems
        .iter()
        .map(|(p, _)| (case.exact)(*p))
        .collect::<Result<_>>()?;
    let mut out = Vec::new();
    for m in METHODS {
        ctx.progress
            .set_message(format!("physics: {}, {}", case.name, m.name()));
        let mut per_function: Vec<Option<f64>> = vec![None; case.functions.len()];
        let mut all = Vec::new();
        let mut inside = Vec::new();
        for ((p, sys), want) in case.systems.iter().zip(&exact) {
            let r = m.resistance(sys)?;
            for (k, got) in (case.read)(&r).into_iter().enumerate() {
                if let Some(got) = got {
                    let e = (got / want[k] - 1.0).abs();
                    per_function[k] = Some(per_function[k].map_or(e, |w: f64| w.max(e)));
                    all.push(e);
                    if (case.inside)(*p) {
                        inside.push(e);
                    }
                }
            }
        }
        let ns = ns_per_eval(ctx.cfg.min_time, case.systems.len(), || {
            for (_, sys) in &case.systems {
                black_box(m.resistance(black_box(sys)).ok());
            }
        });
        out.push(Measured {
            method: m,
            per_function,
            all,
            inside,
            ns_per_particle: ns / case.n as f64,
        });
        ctx.progress.inc(1);
    }
    Ok(out)
}

/// Section b.
pub fn section(ctx: &Ctx) -> Result<Section> {
    ctx.progress.inc_length(3 * METHODS.len() as u64);
    let cases = [
        sphere_wall(ctx.cfg.sweep)?,
        two_spheres(ctx.cfg.sweep)?,
        sphere_free_surface(ctx.cfg.sweep)?,
    ];
    let mut body = String::new();
    let heights: Vec<f64> = cases[0].systems.iter().map(|(h, _)| *h).collect();
    let gaps: Vec<f64> = cases[1].systems.iter().map(|(x, _)| *x).collect();
    let fmt = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    writeln!(
        body,
        "Resistance functions from the solver against exact results, at the truncation levels F, FT and FTS, \
         far field only (the inverse of `System::mobility`; at FTS its force-torque block, i.e. rigid spheres in a \
         quiescent fluid, stresslets eliminated; at F, `(M_UF)^-1`) and with lubrication (`System::resistance` with \
         `Lubrication::default()`: every pair whose correction may exceed 1e-3 of the drag, switched off smoothly \
         beyond (`Lubrication::pair_window`: s' = 2r/(a1 + a2) < 9.31 at FT, < 5.57 at FTS), every sphere closer than \
         1000 radii to a wall, from the generated sphere-wall tables, and a sphere near a free surface with its mirror \
         image as a pair; F has no lubrication level). Error: `|computed / exact - 1|`, the largest over the sweep per \
         function, the median over all functions and the sweep, and the largest over all functions where the \
         correction is kept in full (wall: every height of the sweep; pair and free surface: s' below the FTS window).\n\n\
         - One sphere of radius a above a no-slip wall, {} heights h/a = {} (geometric in the gap): X^A_w normal translation \
         (Brenner 1961), Y^A_w parallel translation (O'Neill 1964), F^r the translation-rotation coupling and Y^C_w rotation \
         parallel to the wall (Dean & O'Neill 1963 as corrected by Goldman, Cox & Brenner 1967), X^C_w rotation about the \
         normal (Jeffery 1915), all from `stokesian::resistance::exact` (bispherical series to convergence).\n\
         - Two equal spheres in unbounded fluid, {} gaps xi = r/a - 2 = {}: along and about the line of centres X11A, X12A \
         (Stimson & Jeffery 1926 with Brenner's series, `stokesian::resistance::exact::two_sphere_xa`) and X11C, X12C (Jeffery 1915, \
         `two_sphere_xc`); across it Y11A ... Y12C from the twin-multipole series `stokesian::resistance::two_sphere::resistance_scalars` \
         (Jeffrey & Onishi 1984, corrected by Townsend 2023). Eq. 19 for an isolated pair uses that same series, so with \
         lubrication the Y errors check the assembly, not the series.\n\
         - One sphere of radius a above a flat free surface, the same heights: X^A_fs normal translation (Brenner 1961, \
         `stokesian::resistance::exact::brenner_xa_free_surface`) and X^C_fs rotation about the normal (Jeffery's image sum, \
         `jeffery_xc_free_surface`), both independent of the two-sphere series that Eq. 19 uses here.\n\n\
         Time per particle: forming the resistance (assembly of the mobility, Cholesky inverse, lubrication where used) for \
         every configuration of the sweep, divided by the number of configurations and of spheres (the two-sphere \
         series of a size ratio, formed once per process in 60-95 us, are formed during the warm-up and not timed).\n",
        heights.len(),
        fmt(&heights),
        gaps.len(),
        fmt(&gaps)
    )?;
    let mut points = Vec::new();
    for (g, case) in cases.iter().enumerate() {
        let measured = measure(ctx, case)?;
        let mut header: Vec<String> = vec!["method".into()];
        header.extend(case.functions.iter().map(|f| f.to_string()));
        header.extend([
            "median of all".into(),
            "largest where kept in full".into(),
            "time per particle".into(),
        ]);
        let mut t = Table::new(&header);
        for m in &measured {
            let mut cells = vec![m.method.name()];
            cells.extend(m.per_function.iter().map(|e| table::err(*e)));
            cells.push(table::err(table::median(&m.all)));
            cells.push(table::err(table::max(&m.inside)));
            cells.push(table::time_ns(m.ns_per_particle));
            t.row(cells);
            let series = METHODS
                .iter()
                .position(|q| q.name() == m.method.name())
                .unwrap_or(0);
            for (y, filled) in [(table::max(&m.all), true), (table::median(&m.all), false)] {
                if let Some(y) = y {
                    points.push(plot::Point {
                        x: m.ns_per_particle,
                        y,
                        series,
                        group: g,
                        filled,
                    });
                }
            }
        }
        writeln!(
            body,
            "\n**{}** (largest relative error over the sweep; n/a: not computed at that level)\n",
            case.name
        )?;
        body.push_str(&t.markdown());
    }
    let floor = 1e-16;
    let scatter = plot::Scatter {
        title: "Resistance functions: error against run time per particle".into(),
        x_label: "time per particle [ns]".into(),
        y_label: "relative error over the functions and the sweep".into(),
        series: METHODS.iter().map(|m| m.name()).collect(),
        groups: cases.iter().map(|c| c.name.to_string()).collect(),
        fill_legend: Some(("largest error".into(), "median error".into())),
        y_floor: floor,
        points,
    };
    plot::write(&ctx.cfg.out, "physics", &scatter)?;
    writeln!(
        body,
        "\n![error against time per particle](physics.png)\n\n[physics.svg](physics.svg): one point per method (colour) and case (shape) for the largest (filled) and the median (hollow) error over all functions and the sweep; errors below {floor:.0e} (exact agreement) are drawn at {floor:.0e}."
    )?;
    Ok(Section {
        title: "b. Physics".into(),
        body,
    })
}
