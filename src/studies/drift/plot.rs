//! The drift plot: four stacked panels over the frame number, log scale — the matrix's
//! orthonormality error, its error against the exact pose, the image's largest t error, and
//! that error over the per-pixel bound a pose rebuilt from the keys guarantees —
//! one line per pose path (the largest value over each run of frames), the bounds dashed.
//!
//! Pipeline position: the last output of `sim drift`. Drawn with `plotters` into an RGB
//! buffer (bitmap backend only) and encoded by the project's PNG writer. Text uses DejaVu Sans
//! compiled into the binary (the `dejavu` crate) through plotters' `ab_glyph` feature, so no
//! system font is looked up and the picture is the same on every machine.

use super::run::{DriftResult, FrameDrift, Mode};
use plotters::prelude::*;

/// Picture size in pixels.
pub const SIZE: (u32, u32) = (800, 1080);

/// Points drawn per line at most: each is the largest value of a run of frames (the envelope
/// that a bound is about), which keeps the PNG small and its lines legible.
const MAX_POINTS: usize = 500;

/// Values at or below this are drawn at it (log scale; an exact 0 has no logarithm).
const FLOOR: f64 = 1e-12;

fn colour(m: Mode) -> RGBColor {
    match m {
        Mode::Keyframe => RGBColor(31, 90, 200),
        Mode::Incremental => RGBColor(20, 150, 60),
        Mode::IncrementalNoReorth => RGBColor(210, 40, 40),
    }
}

fn label(m: Mode) -> &'static str {
    match m {
        Mode::Keyframe => "(a) keyframes, fixed point",
        Mode::Incremental => "(b) incremental + re-orthonormalisation",
        Mode::IncrementalNoReorth => "(b) incremental, no correction",
    }
}

/// A dashed bound line: (label, colour, points).
type Bound = (String, RGBColor, Vec<(f64, f64)>);

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    frames: f64,
    series: &[(Mode, Vec<(f64, f64)>)],
    bounds: &[Bound],
    lo: f64,
    legend: SeriesLabelPosition,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("plot: {e}");
    let top = series
        .iter()
        .flat_map(|(_, p)| p.iter())
        .chain(bounds.iter().flat_map(|(_, _, p)| p.iter()))
        .map(|&(_, v)| v)
        .fold(lo * 10.0, f64::max);
    let hi = 10f64.powf(top.log10().ceil() + 0.3);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(32)
        .y_label_area_size(64)
        .build_cartesian_2d(0f64..frames, (lo..hi).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("frame")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 13))
        .light_line_style(WHITE)
        .draw()
        .map_err(err)?;
    for (m, pts) in series {
        let c = colour(*m);
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(1)))
            .map_err(err)?
            .label(label(*m))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
    }
    for (name, c, pts) in bounds {
        let c = *c;
        chart
            .draw_series(DashedLineSeries::new(
                pts.iter().copied(),
                6,
                4,
                c.stroke_width(2),
            ))
            .map_err(err)?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 8, y)], c.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(legend)
        .label_font(("sans-serif", 12))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// The largest value of `f` over runs of consecutive frames, at most [`MAX_POINTS`] points,
/// each at its run's first frame (and the last frame's own point, so lines reach the end).
fn envelope(rows: &[&FrameDrift], f: fn(&FrameDrift) -> f64) -> Vec<(f64, f64)> {
    let run = rows.len().div_ceil(MAX_POINTS).max(1);
    let mut pts: Vec<(f64, f64)> = rows
        .chunks(run)
        .map(|c| {
            let y = c.iter().map(|r| f(r)).fold(FLOOR, f64::max);
            (f64::from(c[0].frame), y)
        })
        .collect();
    if let Some(last) = rows.last() {
        pts.push((f64::from(last.frame), f(last).max(FLOOR)));
    }
    pts
}

/// Renders the plot as RGB pixels (`SIZE`).
pub fn render(result: &DriftResult) -> Result<image::RgbImage, String> {
    crate::output::figure::register_font()?;
    let (w, h) = SIZE;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| format!("plot: {e}"))?;
        let areas = root.split_evenly((4, 1));
        let frames = f64::from(result.frames.max(2) - 1);
        let pick = |f: fn(&FrameDrift) -> f64| -> Vec<(Mode, Vec<(f64, f64)>)> {
            Mode::ALL
                .iter()
                .map(|&m| {
                    let mine: Vec<&FrameDrift> =
                        result.rows.iter().filter(|r| r.mode == m).collect();
                    (m, envelope(&mine, f))
                })
                .collect()
        };
        let b = &result.bounds;
        let flat = |v: f64| vec![(0.0, v.max(FLOOR)), (frames, v.max(FLOOR))];
        let inc: Vec<&FrameDrift> = result
            .rows
            .iter()
            .filter(|r| r.mode == Mode::Incremental)
            .collect();
        let inc_growth = envelope(&inc, |r| r.matrix_bound);
        panel(
            &areas[0],
            "orthonormality error max |RᵀR − I|",
            frames,
            &pick(|r| r.orthonormality),
            &[
                (
                    "bound (a), dashed".into(),
                    colour(Mode::Keyframe),
                    flat(b.keyframe_orthonormality),
                ),
                (
                    "bound (b) with correction, dashed".into(),
                    colour(Mode::Incremental),
                    flat(b.incremental_orthonormality),
                ),
            ],
            FLOOR,
            SeriesLabelPosition::UpperLeft,
        )?;
        panel(
            &areas[1],
            "matrix error max |R − R_exact|",
            frames,
            &pick(|r| r.matrix_error),
            &[
                (
                    "bound (a), dashed".into(),
                    colour(Mode::Keyframe),
                    flat(b.keyframe_matrix),
                ),
                (
                    "bound (b), linear in frames, dashed".into(),
                    colour(Mode::Incremental),
                    inc_growth,
                ),
            ],
            FLOOR,
            SeriesLabelPosition::UpperLeft,
        )?;
        panel(
            &areas[2],
            "largest t error against f64 (m), same-leaf pixels",
            frames,
            &pick(|r| r.t_err_max),
            &[],
            1e-9,
            SeriesLabelPosition::UpperLeft,
        )?;
        panel(
            &areas[3],
            "largest t error ÷ its per-pixel bound with (a)'s matrix bound",
            frames,
            &pick(|r| r.t_err_over_keyframe_bound),
            &[("1: the bound".into(), RGBColor(0, 0, 0), flat(1.0))],
            1e-2,
            SeriesLabelPosition::LowerRight,
        )?;
        root.present().map_err(|e| format!("plot: {e}"))?;
    }
    image::RgbImage::from_raw(w, h, buf).ok_or_else(|| "plot: buffer size".to_string())
}
