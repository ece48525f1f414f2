//! The fronts of `sim explore`: fps against one resource, one panel per scene; every point a
//! dot (filled when it fits the part, hollow when not), the Pareto front as a staircase, the
//! budget (70 % of LUTs or FFs, 90 % of a hard block) as a dashed line, the default in red and
//! the best fitting point in green, each labelled.
//!
//! Pipeline position: the figures of `sim explore` ([`super::output`]). Drawn with `plotters`
//! into an RGB buffer with the embedded font (`output::figure`), so the picture is the same on
//! every machine and thread count.

use super::run::{ExploreResult, ExploreRow, BLOCK_BUDGET, LUT_BUDGET, RESOURCES};
use crate::studies::sweep::plot::staircase;
use plotters::prelude::*;

/// Width of the picture and height of one scene's panel, pixels.
pub const PANEL: (u32, u32) = (900, 440);

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    rows: &[&ExploreRow],
    k: usize,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("plot: {e}");
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.usage.used[k] as f64, r.fps))
        .collect();
    let share = if k < 2 { LUT_BUDGET } else { BLOCK_BUDGET };
    let limit = rows
        .first()
        .map_or(0.0, |r| share * r.usage.available[k] as f64);
    let (mut x0, mut x1) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    if !x0.is_finite() {
        (x0, x1) = (0.0, 1.0);
    }
    if limit > 0.0 {
        x1 = x1.max(limit);
        x0 = x0.min(limit);
    }
    let pad = ((x1 - x0) * 0.06).max(x1.abs() * 0.02).max(1.0);
    let y1 = pts.iter().map(|p| p.1).fold(0.0, f64::max).max(1.0) * 1.12;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 17))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((x0 - pad).max(0.0)..(x1 + pad), 0.0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(format!("{} (estimate, whole design)", RESOURCES[k]))
        .y_desc("fps (cycle model)")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0}"))
        .label_style(("sans-serif", 13))
        .light_line_style(WHITE)
        .draw()
        .map_err(err)?;
    let grey = RGBColor(150, 150, 150);
    let blue = RGBColor(31, 90, 200);
    let orange = RGBColor(230, 120, 20);
    let red = RGBColor(210, 30, 30);
    let green = RGBColor(20, 150, 60);
    if limit > 0.0 {
        let dashes = (0..40).map(|s| {
            let (a, b) = (y1 * f64::from(s) / 40.0, y1 * (f64::from(s) + 0.5) / 40.0);
            PathElement::new(vec![(limit, a), (limit, b)], BLACK.stroke_width(1))
        });
        chart
            .draw_series(dashes)
            .map_err(err)?
            .label(format!("budget ({:.0} % of the part)", 100.0 * share))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(1)));
    }
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .zip(&pts)
        .filter(|(r, _)| r.front[k])
        .map(|(_, p)| *p)
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    chart
        .draw_series(LineSeries::new(
            staircase(&front, x1 + pad),
            orange.stroke_width(2),
        ))
        .map_err(err)?
        .label("Pareto front")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], orange.stroke_width(2)));
    let fit: Vec<(f64, f64)> = rows
        .iter()
        .zip(&pts)
        .filter(|(r, _)| r.usage.fits)
        .map(|(_, p)| *p)
        .collect();
    let over: Vec<(f64, f64)> = rows
        .iter()
        .zip(&pts)
        .filter(|(r, _)| !r.usage.fits)
        .map(|(_, p)| *p)
        .collect();
    chart
        .draw_series(
            over.iter()
                .map(|&p| Circle::new(p, 3, grey.stroke_width(1))),
        )
        .map_err(err)?
        .label("does not fit")
        .legend(move |(x, y)| Circle::new((x + 9, y), 3, grey.stroke_width(1)));
    chart
        .draw_series(fit.iter().map(|&p| Circle::new(p, 3, blue.filled())))
        .map_err(err)?
        .label("fits the part")
        .legend(move |(x, y)| Circle::new((x + 9, y), 3, blue.filled()));
    for (r, &p) in rows.iter().zip(&pts) {
        let mark = |colour: RGBColor, text: String, dy: i32| {
            EmptyElement::at(p)
                + Circle::new((0, 0), 7, colour.stroke_width(2))
                + Text::new(text, (9, dy), ("sans-serif", 14).into_font().color(&colour))
        };
        if r.default {
            chart
                .draw_series(std::iter::once(mark(red, "default".into(), 4)))
                .map_err(err)?;
        }
        if r.best {
            let text = format!("best fitting (point {})", r.point);
            chart
                .draw_series(std::iter::once(mark(green, text, -18)))
                .map_err(err)?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .label_font(("sans-serif", 12))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// Renders the front of resource `k` (the order of [`RESOURCES`]) as RGB pixels: one panel
/// per scene, stacked.
pub fn render(result: &ExploreResult, k: usize) -> Result<image::RgbImage, String> {
    crate::output::figure::register_font()?;
    let n = result.scenes.len().max(1) as u32;
    let (w, h) = (PANEL.0, PANEL.1 * n);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| format!("plot: {e}"))?;
        let areas = root.split_evenly((n as usize, 1));
        for (scene, area) in result.scenes.iter().zip(&areas) {
            let rows: Vec<&ExploreRow> = result
                .rows
                .iter()
                .filter(|r| r.scene == scene.name)
                .collect();
            let s = &scene.spec;
            let title = format!(
                "{}: fps against {}, {}×{}, {} frames{}{}, {} points",
                scene.name,
                RESOURCES[k],
                s.width,
                s.height,
                s.frames,
                s.depth.map_or_else(String::new, |d| format!(", depth {d}")),
                result
                    .sample
                    .map_or_else(String::new, |x| format!(", sampled 1/{:.0}", 1.0 / x.rate)),
                rows.len()
            );
            panel(area, &title, &rows, k)?;
        }
        root.present().map_err(|e| format!("plot: {e}"))?;
    }
    image::RgbImage::from_raw(w, h, buf).ok_or_else(|| "plot: buffer size".to_string())
}
