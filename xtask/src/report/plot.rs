//! Log-log scatter plots of the report (plotters), each written as PNG and SVG. Colour
//! names a series (e.g. a kernel variant), marker shape a group (e.g. a family), and a
//! filled or hollow marker a two-way split (e.g. self or pair). PNG text uses the
//! embedded DejaVu Sans of `cli/assets/` (Bitstream Vera licence), so no system
//! font is needed.

use anyhow::{anyhow, Result};
use plotters::coord::combinators::IntoLogRange;
use plotters::prelude::*;
use std::path::Path;

/// Embedded font for the bitmap backend.
const FONT: &[u8] = include_bytes!("../../../cli/assets/DejaVuSans.ttf");

/// One point.
#[derive(Clone, Debug)]
pub struct Point {
    /// Abscissa (positive).
    pub x: f64,
    /// Ordinate (positive; smaller values are drawn at the floor of the axis).
    pub y: f64,
    /// Index into [`Scatter::series`] (colour).
    pub series: usize,
    /// Index into [`Scatter::groups`] (marker shape).
    pub group: usize,
    /// Filled (true) or hollow marker.
    pub filled: bool,
}

/// A scatter plot.
pub struct Scatter {
    /// Title.
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// Series names (colours).
    pub series: Vec<String>,
    /// Group names (marker shapes).
    pub groups: Vec<String>,
    /// Legend text for filled and hollow markers, if both occur.
    pub fill_legend: Option<(String, String)>,
    /// Smallest y drawn (points below are drawn on it).
    pub y_floor: f64,
    /// The points.
    pub points: Vec<Point>,
}

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Write `dir/stem.png` and `dir/stem.svg`.
pub fn write(dir: &Path, stem: &str, s: &Scatter) -> Result<()> {
    let size = (1000, 720);
    // idempotent; a failure means the embedded font is unusable (both backends lay out
    // text with it)
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| anyhow!("the embedded font cannot be read"))?;
    let svg = dir.join(format!("{stem}.svg"));
    draw(SVGBackend::new(&svg, size).into_drawing_area(), s)?;
    let png = dir.join(format!("{stem}.png"));
    draw(BitMapBackend::new(&png, size).into_drawing_area(), s)?;
    Ok(())
}

/// The marker of group `g` at `c` in `colour`, filled or not.
fn marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    c: (i32, i32),
    g: usize,
    colour: RGBColor,
    filled: bool,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let style = if filled {
        colour.filled()
    } else {
        colour.stroke_width(2)
    };
    let r = 7;
    let (x, y) = c;
    match g % 5 {
        0 => area.draw(&Circle::new(c, r, style)),
        1 => {
            let pts = vec![(x, y - r), (x - r, y + r), (x + r, y + r)];
            if filled {
                area.draw(&Polygon::new(pts, style))
            } else {
                let mut p = pts.clone();
                p.push(pts[0]);
                area.draw(&PathElement::new(p, style))
            }
        }
        2 => area.draw(&Rectangle::new(
            [(x - r + 1, y - r + 1), (x + r - 1, y + r - 1)],
            style,
        )),
        3 => {
            let pts = vec![
                (x, y - r - 1),
                (x + r + 1, y),
                (x, y + r + 1),
                (x - r - 1, y),
            ];
            if filled {
                area.draw(&Polygon::new(pts, style))
            } else {
                let mut p = pts.clone();
                p.push(pts[0]);
                area.draw(&PathElement::new(p, style))
            }
        }
        _ => {
            let st = colour.stroke_width(if filled { 3 } else { 2 });
            area.draw(&PathElement::new(vec![(x - r, y - r), (x + r, y + r)], st))?;
            area.draw(&PathElement::new(vec![(x - r, y + r), (x + r, y - r)], st))
        }
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    s: &Scatter,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plot: {e}");
    root.fill(&WHITE).map_err(e)?;
    let (main, legend) = root.split_horizontally(760);
    let ys: Vec<f64> = s.points.iter().map(|p| p.y.max(s.y_floor)).collect();
    let xs: Vec<f64> = s.points.iter().map(|p| p.x).collect();
    let range = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (lo, hi) = if lo.is_finite() && hi.is_finite() {
            (lo, hi)
        } else {
            (1.0, 10.0)
        };
        // a decade of room above a point that sits on a power of ten
        let top = (hi.log10() + 0.05).ceil().max(lo.log10().floor() + 1.0);
        (10f64.powf(lo.log10().floor()), 10f64.powf(top))
    };
    let (x0, x1) = range(&xs);
    let (y0, y1) = range(&ys);
    let mut chart = ChartBuilder::on(&main)
        .caption(&s.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(&s.x_label)
        .y_desc(&s.y_label)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()
        .map_err(e)?;
    let plot_area = chart.plotting_area().strip_coord_spec();
    let to_px = |x: f64, y: f64| chart.backend_coord(&(x, y));
    let (ox, oy) = plot_area.get_base_pixel();
    for (p, &y) in s.points.iter().zip(&ys) {
        let (px, py) = to_px(p.x, y);
        marker(
            &plot_area,
            (px - ox, py - oy),
            p.group,
            PALETTE[p.series % PALETTE.len()],
            p.filled,
        )
        .map_err(e)?;
    }
    // legend: colours, then shapes, then fill
    let text = ("sans-serif", 15).into_font();
    let mut y = 40;
    legend
        .draw(&Text::new("colour", (10, y), text.clone()))
        .map_err(e)?;
    y += 24;
    for (k, name) in s.series.iter().enumerate() {
        marker(&legend, (20, y + 7), 0, PALETTE[k % PALETTE.len()], true).map_err(e)?;
        legend
            .draw(&Text::new(name.as_str(), (36, y), text.clone()))
            .map_err(e)?;
        y += 24;
    }
    y += 16;
    legend
        .draw(&Text::new("shape", (10, y), text.clone()))
        .map_err(e)?;
    y += 24;
    for (k, name) in s.groups.iter().enumerate() {
        marker(&legend, (20, y + 7), k, BLACK, true).map_err(e)?;
        legend
            .draw(&Text::new(name.as_str(), (36, y), text.clone()))
            .map_err(e)?;
        y += 24;
    }
    if let Some((filled, hollow)) = &s.fill_legend {
        y += 16;
        marker(&legend, (20, y + 7), 0, BLACK, true).map_err(e)?;
        legend
            .draw(&Text::new(filled.as_str(), (36, y), text.clone()))
            .map_err(e)?;
        y += 24;
        marker(&legend, (20, y + 7), 0, BLACK, false).map_err(e)?;
        legend
            .draw(&Text::new(hollow.as_str(), (36, y), text.clone()))
            .map_err(e)?;
    }
    root.present().map_err(e)?;
    Ok(())
}
