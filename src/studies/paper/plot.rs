//! The chart of `sim paper`, laid out like the paper's Fig. 7: render time per frame and
//! frame rate, one bar per case in each group, a group per resolution; the top row the
//! reference's wall time, the bottom row the cycle model at the hardware clock.
//!
//! Pipeline position: `paper.png`, drawn with `plotters` into an RGB buffer with the embedded
//! DejaVu Sans (`output::figure`), so it is the same on every machine.

use super::measure::Row;
use plotters::prelude::*;

/// Bar colours of the cases, as the paper's: static blue, animated red, optimised yellow;
/// (a') a lighter blue.
const COLOURS: [(&str, RGBColor); 4] = [
    ("a", RGBColor(40, 90, 200)),
    ("a'", RGBColor(120, 170, 240)),
    ("b", RGBColor(210, 50, 40)),
    ("c", RGBColor(235, 180, 30)),
];

type Panel<'a> = (&'a str, &'a str, fn(&Row) -> Option<f64>);

/// Renders the chart.
pub fn render(rows: &[Row], clock_mhz: u32) -> Result<image::RgbImage, String> {
    crate::output::figure::register_font()?;
    let (w, h) = (1100u32, 760u32);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    let mut res: Vec<(u32, u32)> = Vec::new();
    for r in rows {
        if !res.contains(&(r.width, r.height)) {
            res.push((r.width, r.height));
        }
    }
    let cases: Vec<(String, String)> = {
        let mut v: Vec<(String, String)> = Vec::new();
        for r in rows {
            if !v.iter().any(|(c, _)| *c == r.case) {
                v.push((r.case.clone(), r.label.clone()));
            }
        }
        v
    };
    let panels: [Panel<'_>; 4] = [
        ("reference: render time", "ms per frame", |r| {
            r.reference_best_s
                .map(|s| 1e3 * s / f64::from(r.frames.max(1)))
        }),
        ("reference: frame rate", "frames per second", |r| {
            r.reference_fps
        }),
        ("cycle model: render time", "ms per frame", |r| {
            r.cycle_fps.map(|f| 1e3 / f.max(1e-12))
        }),
        ("cycle model: frame rate", "frames per second", |r| {
            r.cycle_fps
        }),
    ];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| format!("plot: {e}"))?;
        let root = root
            .titled(
                &format!("Espe et al. Fig. 7 on this model (cycle model at {clock_mhz} MHz)"),
                ("sans-serif", 20),
            )
            .map_err(|e| format!("plot: {e}"))?;
        let areas = root.split_evenly((2, 2));
        let n_cases = cases.len().max(1);
        for (area, (title, ylabel, value)) in areas.iter().zip(panels) {
            let vmax = rows.iter().filter_map(value).fold(0f64, f64::max);
            // Head room for the legend in the upper right.
            let vmax = if vmax > 0.0 { vmax * 1.6 } else { 1.0 };
            let groups = res.len().max(1);
            let mut chart = ChartBuilder::on(area)
                .caption(title, ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(30)
                .y_label_area_size(60)
                .build_cartesian_2d(0f64..groups as f64, 0f64..vmax)
                .map_err(|e| format!("plot: {e}"))?;
            let labels: Vec<String> = res.iter().map(|(w, h)| format!("{w}×{h}")).collect();
            chart
                .configure_mesh()
                .disable_x_mesh()
                .x_labels(groups * 2 + 1)
                .x_label_formatter(&|x| {
                    let g = (x - 0.5).round();
                    if (x - 0.5 - g).abs() < 1e-6 && g >= 0.0 {
                        labels.get(g as usize).cloned().unwrap_or_default()
                    } else {
                        String::new()
                    }
                })
                .y_desc(ylabel)
                .label_style(("sans-serif", 13))
                .draw()
                .map_err(|e| format!("plot: {e}"))?;
            let bar_w = 0.8 / n_cases as f64;
            for (ci, (case, label)) in cases.iter().enumerate() {
                let colour = COLOURS
                    .iter()
                    .find(|(c, _)| c == case)
                    .map_or(BLACK, |(_, c)| *c);
                let bars: Vec<Rectangle<(f64, f64)>> = rows
                    .iter()
                    .filter(|r| r.case == *case)
                    .filter_map(|r| {
                        let g = res.iter().position(|&x| x == (r.width, r.height))?;
                        let v = value(r)?;
                        let x0 = g as f64 + 0.1 + ci as f64 * bar_w;
                        Some(Rectangle::new(
                            [(x0, 0.0), (x0 + bar_w * 0.9, v)],
                            colour.filled(),
                        ))
                    })
                    .collect();
                chart
                    .draw_series(bars)
                    .map_err(|e| format!("plot: {e}"))?
                    .label(format!("({case}) {label}"))
                    .legend(move |(x, y)| {
                        Rectangle::new([(x, y - 5), (x + 12, y + 5)], colour.filled())
                    });
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.9))
                .border_style(BLACK)
                .label_font(("sans-serif", 12))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| format!("plot: {e}"))?;
        }
        root.present().map_err(|e| format!("plot: {e}"))?;
    }
    image::RgbImage::from_raw(w, h, buf).ok_or_else(|| "plot: buffer size".to_string())
}
