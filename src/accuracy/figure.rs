//! The figure of a sweep: relative error against wall seconds, log–log, one colour per case;
//! every setting a marker (circle: one thread, triangle: more), the Pareto points filled and
//! joined by the case's line.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{Case, Row};
use crate::error::Result;
use crate::output::figure;

const SIZE: (u32, u32) = (1000, 600);
/// The width of the chart; the legend takes the rest.
const CHART_WIDTH: u32 = 760;

/// Distinct colours, one per case.
const COLOURS: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
];

/// One point: wall seconds, error, threads, Pareto.
type Point = (f64, f64, usize, bool);

/// A case's points.
#[derive(Debug, PartialEq)]
pub struct Curve {
    pub label: String,
    pub points: Vec<Point>,
}

/// The curves of `rows`, one per case that has an error anywhere. Reference runs are left out
/// (their error is 0 by definition).
pub fn curves(cases: &[&Case], rows: &[Row]) -> Vec<Curve> {
    cases
        .iter()
        .map(|c| Curve {
            label: c.name.to_string(),
            points: rows
                .iter()
                .filter(|r| r.case == c.name && !r.is_reference)
                .filter_map(|r| r.error.map(|e| (r.wall_seconds, e, r.threads, r.pareto)))
                .collect(),
        })
        .filter(|c| !c.points.is_empty())
        .collect()
}

/// The curves of an accuracy_cost.csv ([`super::csv`]'s columns), cases in the order of their
/// first row: what [`curves`] gives for the rows it was written from. A row that does not
/// read is named by its line.
pub fn curves_from_csv(text: &str) -> std::result::Result<Vec<Curve>, String> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| format!("has no `{name}` column in its header"))
    };
    let [case, role, threads, error, wall, pareto] =
        ["case", "role", "threads", "error", "wall_seconds", "pareto"].map(column);
    let (case, role, threads, error, wall, pareto) =
        (case?, role?, threads?, error?, wall?, pareto?);
    let mut curves: Vec<Curve> = Vec::new();
    for (k, line) in lines.enumerate() {
        let ln = k + 2;
        // The note, last and quoted, may hold commas; the columns before it do not.
        let fields: Vec<&str> = line.splitn(header.len(), ',').collect();
        if fields.len() < header.len() - 1 {
            return Err(format!(
                "line {ln}: {} columns, the header has {}",
                fields.len(),
                header.len()
            ));
        }
        if fields[role] == "reference" || fields[error].is_empty() {
            continue;
        }
        let number = |c: usize| {
            fields[c]
                .parse::<f64>()
                .map_err(|_| format!("line {ln}: `{}` is not a number ({})", fields[c], header[c]))
        };
        let point = (
            number(wall)?,
            number(error)?,
            number(threads)? as usize,
            fields[pareto] == "true",
        );
        match curves.iter_mut().find(|c| c.label == fields[case]) {
            Some(c) => c.points.push(point),
            None => curves.push(Curve {
                label: fields[case].to_string(),
                points: vec![point],
            }),
        }
    }
    Ok(curves)
}

fn range(values: impl Iterator<Item = f64>, floor: f64) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > floor)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo.is_finite() {
        (lo / 2.0, hi * 2.0)
    } else {
        (floor.max(1e-6), 1.0)
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    curves: &[Curve],
) -> std::result::Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (plot, side) = root.split_horizontally(CHART_WIDTH);
    let all = || curves.iter().flat_map(|c| c.points.iter());
    let (x0, x1) = range(all().map(|p| p.0), 0.0);
    // Errors of exactly 0 (a setting that repeats its reference bit for bit) sit on the axis.
    let (y0, y1) = range(all().map(|p| p.1), 0.0);
    let at = |e: f64| e.max(y0);
    let mut chart = ChartBuilder::on(&plot)
        .caption(title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("wall seconds per setting (all its runs)")
        .y_desc("relative error against the reference")
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    for (k, c) in curves.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let mut front: Vec<(f64, f64)> = c
            .points
            .iter()
            .filter(|p| p.3)
            .map(|p| (p.0, at(p.1)))
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart.draw_series(LineSeries::new(front, colour.stroke_width(2)))?;
        let y = 60 + 24 * k as i32;
        side.draw(&PathElement::new(
            vec![(8, y), (34, y)],
            colour.stroke_width(2),
        ))?;
        side.draw(&Circle::new((21, y), 4, colour.filled()))?;
        side.draw(&Text::new(c.label.clone(), (42, y - 8), ("sans-serif", 15)))?;
        for p in &c.points {
            let style = if p.3 {
                colour.filled()
            } else {
                colour.stroke_width(1)
            };
            let size = if p.3 { 5 } else { 4 };
            let at = (p.0, at(p.1));
            if p.2 == 1 {
                chart.draw_series(std::iter::once(Circle::new(at, size, style)))?;
            } else {
                chart.draw_series(std::iter::once(TriangleMarker::new(at, size + 1, style)))?;
            }
        }
    }
    let y = 60 + 24 * curves.len() as i32 + 16;
    for (k, line) in [
        "filled: Pareto points, joined",
        "open: dominated settings",
        "circle: 1 thread",
        "triangle: 2 threads",
    ]
    .iter()
    .enumerate()
    {
        side.draw(&Text::new(
            *line,
            (8, y + 20 * k as i32),
            ("sans-serif", 13),
        ))?;
    }
    Ok(())
}

/// The figure as SVG text.
pub fn svg(title: &str, curves: &[Curve]) -> Result<String> {
    figure::svg(SIZE, &|root| draw(root, title, curves))
}

/// The figure as PNG bytes.
pub fn png(title: &str, curves: &[Curve]) -> Result<Vec<u8>> {
    figure::png(SIZE, &|root| draw(root, title, curves))
}
