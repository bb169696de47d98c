//! Plots of the command line (plotters): the doublet study's contour plot, written as
//! PNG and SVG. Text uses the embedded DejaVu Sans (assets/, Bitstream Vera licence),
//! so no system font is needed.

use crate::output::has_extension;
use plotters::coord::combinators::IntoLogRange;
use plotters::prelude::*;
use std::path::Path;

/// Embedded font for the bitmap backend.
const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// A scalar field on a tensor grid `x[i]`, `y[j]`, `z[i][j]`.
pub struct Field<'a> {
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub z: &'a [Vec<f64>],
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub title: &'a str,
    /// Marked point (e.g. the maximum).
    pub mark: (f64, f64),
}

/// Filled contour plot (the field in `levels` bands, colour-mapped) on logarithmic axes
/// (all coordinates must be positive), with a labelled colour bar; written to `path`
/// as PNG or SVG by its extension.
pub fn filled_contours(path: &Path, f: &Field, levels: usize) -> Result<(), String> {
    let is_svg = has_extension(path, "svg");
    let size = (900, 700);
    if is_svg {
        draw(SVGBackend::new(path, size).into_drawing_area(), f, levels)
    } else {
        // idempotent; a failure only means the font is unusable
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .map_err(|_| "the embedded font cannot be read".to_string())?;
        draw(
            BitMapBackend::new(path, size).into_drawing_area(),
            f,
            levels,
        )
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    f: &Field,
    levels: usize,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let (main, bar) = root.split_horizontally(780);
    let (lo, hi) =
        f.z.iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
    let band = |v: f64| (((v - lo) / (hi - lo) * levels as f64) as usize).min(levels - 1);
    let colour = |k: usize| {
        plotters::style::colors::colormaps::ViridisRGB::get_color_normalized(
            k as f64,
            0.0,
            (levels - 1) as f64,
        )
    };
    // cell edges: geometric midpoints between grid points, the outer points as edges
    let edges = |v: &[f64]| -> Vec<f64> {
        let mut e = vec![v[0]];
        e.extend(v.windows(2).map(|w| (w[0] * w[1]).sqrt()));
        e.push(v[v.len() - 1]);
        e
    };
    let (ex, ey) = (edges(f.x), edges(f.y));
    let mut chart = ChartBuilder::on(&main)
        .caption(f.title, ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (ex[0]..ex[ex.len() - 1]).log_scale(),
            (ey[0]..ey[ey.len() - 1]).log_scale(),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(f.x_label)
        .y_desc(f.y_label)
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .disable_mesh()
        .draw()
        .map_err(err)?;
    chart
        .draw_series((0..f.x.len()).flat_map(|i| {
            let (ex, ey) = (&ex, &ey);
            (0..f.y.len()).map(move |j| {
                Rectangle::new(
                    [(ex[i], ey[j]), (ex[i + 1], ey[j + 1])],
                    colour(band(f.z[i][j])).filled(),
                )
            })
        }))
        .map_err(err)?;
    chart
        .draw_series(std::iter::once(Cross::new(
            f.mark,
            8,
            WHITE.stroke_width(3),
        )))
        .map_err(err)?;
    // colour bar
    let mut bar_chart = ChartBuilder::on(&bar)
        .margin_top(50)
        .margin_bottom(65)
        .margin_right(10)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(err)?;
    bar_chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let step = (hi - lo) / levels as f64;
    bar_chart
        .draw_series((0..levels).map(|k| {
            let v0 = lo + k as f64 * step;
            Rectangle::new([(0.0, v0), (1.0, v0 + step)], colour(k).filled())
        }))
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}
