//! The sweep plots: error score (log scale) against a cost — cycles per frame or DSP48E2
//! slices — one panel per scene, every configuration a dot, the Pareto front as filled dots
//! joined by its staircase (the boundary of the region it dominates), front points and the
//! default labelled by name, the default in red.
//!
//! Pipeline position: the figures of `sim sweep` (`sweep_cycles.png`, `sweep_dsp.png`). Drawn
//! with `plotters` into an RGB buffer and encoded by the `image` crate, with DejaVu Sans
//! compiled into the binary (as the drift plot), so the picture is the same on every machine.

use super::configs::DEFAULT_NAME;
use super::run::{SweepResult, SweepRow};
use plotters::prelude::*;

/// Width of the picture and height of one scene's panel, pixels.
pub const PANEL: (u32, u32) = (900, 420);

/// Error scores at or below this are drawn at it (log scale; 0 has no logarithm).
const FLOOR: f64 = 1e-12;

/// The cost on the x axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Mean cycles per frame of the cycle model.
    Cycles,
    /// DSP48E2 slices of the pipeline.
    Dsp,
}

impl Axis {
    fn cost(self, r: &SweepRow) -> f64 {
        match self {
            Axis::Cycles => r.cycles_per_frame,
            Axis::Dsp => r.cost.dsp48e2 as f64,
        }
    }

    fn on_front(self, r: &SweepRow) -> bool {
        match self {
            Axis::Cycles => r.cycles_front.on_front,
            Axis::Dsp => r.dsp_front.on_front,
        }
    }

    fn label(self) -> &'static str {
        match self {
            Axis::Cycles => "cycles per frame (cycle model, mean over the frames)",
            Axis::Dsp => "DSP48E2 slices (whole pipeline)",
        }
    }
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    rows: &[&SweepRow],
    axis: Axis,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("plot: {e}");
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (axis.cost(r), r.error.error_score.max(FLOOR)))
        .collect();
    let (mut x0, mut x1) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    if !x0.is_finite() {
        (x0, x1) = (0.0, 1.0);
    }
    let pad = ((x1 - x0) * 0.08).max(x1.abs() * 0.02).max(1.0);
    let (y0, y1) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let (y0, y1) = if y0.is_finite() {
        // A decade and a half of headroom above the worst point keeps the legend clear.
        (y0 / 3.0, y1 * 30.0)
    } else {
        (FLOOR, 1.0)
    };
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((x0 - pad)..(x1 + pad), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(axis.label())
        .y_desc("error score")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 13))
        .light_line_style(WHITE)
        .draw()
        .map_err(err)?;
    let grey = RGBColor(150, 150, 150);
    let blue = RGBColor(31, 90, 200);
    let red = RGBColor(210, 30, 30);
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .zip(&pts)
        .filter(|(r, _)| axis.on_front(r))
        .map(|(_, p)| *p)
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    chart
        .draw_series(LineSeries::new(
            staircase(&front, x1 + pad),
            blue.stroke_width(2),
        ))
        .map_err(err)?
        .label("Pareto front")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], blue.stroke_width(2)));
    chart
        .draw_series(pts.iter().map(|&p| Circle::new(p, 4, grey.stroke_width(1))))
        .map_err(err)?
        .label("configuration")
        .legend(move |(x, y)| Circle::new((x + 9, y), 4, grey.stroke_width(1)));
    chart
        .draw_series(front.iter().map(|&p| Circle::new(p, 5, blue.filled())))
        .map_err(err)?
        .label("on the front")
        .legend(move |(x, y)| Circle::new((x + 9, y), 5, blue.filled()));
    // Labels: the default first, then the front by cost; each takes the first of a few places
    // around its dot where it overlaps no label placed before it and no dot.
    let mut order: Vec<usize> = (0..rows.len())
        .filter(|&k| rows[k].config == DEFAULT_NAME || axis.on_front(rows[k]))
        .collect();
    order.sort_by(|&a, &b| {
        let key = |k: usize| rows[k].config != DEFAULT_NAME;
        key(a).cmp(&key(b)).then(pts[a].0.total_cmp(&pts[b].0))
    });
    let dots: Vec<(i32, i32)> = pts.iter().map(|p| chart.backend_coord(p)).collect();
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let inside: Rect = (xr.start, yr.start, xr.end, yr.end);
    let mut taken: Vec<Rect> = Vec::new();
    for k in order {
        let r = rows[k];
        let is_default = r.config == DEFAULT_NAME;
        let (colour, size) = if is_default { (red, 15) } else { (BLACK, 12) };
        let (dx, dy) = place_label(&r.config, size, dots[k], &dots, &taken, inside);
        taken.push(label_rect(&r.config, size, dots[k], (dx, dy)));
        let text = Text::new(
            r.config.clone(),
            (dx, dy),
            ("sans-serif", size).into_font().color(&colour),
        );
        chart
            .draw_series(std::iter::once(EmptyElement::at(pts[k]) + text))
            .map_err(err)?;
        if is_default {
            chart
                .draw_series(std::iter::once(Circle::new(pts[k], 6, red.stroke_width(2))))
                .map_err(err)?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(("sans-serif", 12))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// A label's box in pixels: (left, top, right, bottom).
type Rect = (i32, i32, i32, i32);

/// The box of `text` at `size` pixels drawn at offset `d` from the dot at `at` (the width is
/// estimated at 0.6 em per character, enough to keep labels apart).
/// A Pareto front drawn as a staircase: from each point (sorted by cost, x) right to the next
/// point's cost, then to it; the last point's value runs on to `x_end`. The sweep's and the
/// explorer's fronts both draw with it.
pub fn staircase(front: &[(f64, f64)], x_end: f64) -> Vec<(f64, f64)> {
    let mut stairs = Vec::with_capacity(2 * front.len() + 1);
    for (k, p) in front.iter().enumerate() {
        if k > 0 {
            stairs.push((p.0, front[k - 1].1));
        }
        stairs.push(*p);
    }
    if let Some(&(_, y)) = front.last() {
        stairs.push((x_end, y));
    }
    stairs
}

fn label_rect(text: &str, size: i32, at: (i32, i32), d: (i32, i32)) -> Rect {
    let w = (text.chars().count() as f64 * 0.6 * f64::from(size)).ceil() as i32;
    let (x, y) = (at.0 + d.0, at.1 + d.1);
    (x, y, x + w, y + size)
}

fn overlaps(a: Rect, b: Rect) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// The first offset, of right-above, right-below, left-above, left-below and the same further
/// out, whose box lies inside the plotting area and hits no earlier label and no dot; the
/// first when none does.
fn place_label(
    text: &str,
    size: i32,
    at: (i32, i32),
    dots: &[(i32, i32)],
    taken: &[Rect],
    inside: Rect,
) -> (i32, i32) {
    let w = (text.chars().count() as f64 * 0.6 * f64::from(size)).ceil() as i32;
    let candidates = [
        (8, -size - 4),
        (8, 5),
        (-w - 8, -size - 4),
        (-w - 8, 5),
        (8, -2 * size - 6),
        (8, size + 8),
        (-w - 8, -2 * size - 6),
        (-w - 8, size + 8),
    ];
    let free = |d: (i32, i32)| {
        let b = label_rect(text, size, at, d);
        let within = b.0 >= inside.0 && b.1 >= inside.1 && b.2 <= inside.2 && b.3 <= inside.3;
        within
            && !taken.iter().any(|&t| overlaps(b, t))
            && !dots
                .iter()
                .any(|&(x, y)| overlaps(b, (x - 5, y - 5, x + 5, y + 5)))
    };
    candidates
        .iter()
        .copied()
        .find(|&d| free(d))
        .unwrap_or(candidates[0])
}

/// Renders the plot of `axis` as RGB pixels: one panel per scene, stacked.
pub fn render(result: &SweepResult, axis: Axis) -> Result<image::RgbImage, String> {
    crate::output::figure::register_font()?;
    let n = result.scenes.len().max(1) as u32;
    let (w, h) = (PANEL.0, PANEL.1 * n);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| format!("plot: {e}"))?;
        let areas = root.split_evenly((n as usize, 1));
        let o = &result.options;
        for (scene, area) in result.scenes.iter().zip(&areas) {
            let rows: Vec<&SweepRow> = result
                .rows
                .iter()
                .filter(|r| r.scene == scene.name)
                .collect();
            let title = format!(
                "{}: error score against {}, {}×{}, {} frames{}",
                scene.name,
                match axis {
                    Axis::Cycles => "cycles per frame",
                    Axis::Dsp => "DSP48E2",
                },
                o.width,
                o.height,
                o.frames,
                o.depth.map_or_else(String::new, |d| format!(", depth {d}"))
            );
            panel(area, &title, &rows, axis)?;
        }
        root.present().map_err(|e| format!("plot: {e}"))?;
    }
    image::RgbImage::from_raw(w, h, buf).ok_or_else(|| "plot: buffer size".to_string())
}
