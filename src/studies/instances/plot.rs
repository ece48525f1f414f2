//! The study's figure: modelled frames per second against instances (both axes logarithmic),
//! one line per scheme and camera, simulated points filled, bound-only points hollow, and the
//! 60 fps goal dashed.
//!
//! Pipeline position: `instances.png` of `sim instances`, drawn with `plotters` into an RGB
//! buffer with the embedded DejaVu Sans (as the other studies), so it is the same everywhere.

use super::measure::FpsPoint;
use plotters::prelude::*;

/// Renders the plot.
pub fn render(points: &[FpsPoint], clock_mhz: u32) -> Result<image::RgbImage, String> {
    crate::output::figure::register_font()?;
    let (w, h) = (900u32, 560u32);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| format!("plot: {e}"))?;
        let n_max = points.iter().map(|p| p.n).max().unwrap_or(10).max(10);
        let (f0, f1) = points.iter().fold((f64::INFINITY, 0f64), |(a, b), p| {
            (a.min(p.fps), b.max(p.fps))
        });
        let (f0, f1) = if f0.is_finite() {
            ((f0 / 2.0).min(30.0), f1 * 2.0)
        } else {
            (0.1, 1000.0)
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("modelled fps at 1280×768 against instances ({clock_mhz} MHz, XCVU9P)"),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(
                (0.8f64..f64::from(n_max) * 1.5).log_scale(),
                (f0..f1).log_scale(),
            )
            .map_err(|e| format!("plot: {e}"))?;
        chart
            .configure_mesh()
            .x_desc("instances")
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| format!("{y}"))
            .y_desc("frames per second (frame 1)")
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| format!("plot: {e}"))?;
        let goal = DashedLineSeries::new(
            vec![(0.8, 60.0), (f64::from(n_max) * 1.5, 60.0)],
            6,
            4,
            BLACK.stroke_width(1),
        );
        chart
            .draw_series(goal)
            .map_err(|e| format!("plot: {e}"))?
            .label("60 fps goal")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK));
        let lines = [
            ("flat", "still", RGBColor(200, 60, 40)),
            ("flat", "moving", RGBColor(240, 150, 60)),
            ("two-level", "still", RGBColor(30, 90, 200)),
            ("two-level", "moving", RGBColor(60, 170, 90)),
        ];
        for (scheme, camera, colour) in lines {
            let pts: Vec<&FpsPoint> = points
                .iter()
                .filter(|p| p.scheme == scheme && p.camera == camera)
                .collect();
            let xy: Vec<(f64, f64)> = pts.iter().map(|p| (f64::from(p.n), p.fps)).collect();
            // The moving camera dashed: the two cameras' lines nearly coincide.
            let series = if camera == "moving" {
                chart.draw_series(DashedLineSeries::new(xy, 10, 6, colour.stroke_width(2)))
            } else {
                chart.draw_series(LineSeries::new(xy, colour.stroke_width(2)))
            };
            series
                .map_err(|e| format!("plot: {e}"))?
                .label(format!("{scheme}, {camera} camera"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                });
            chart
                .draw_series(pts.iter().map(|p| {
                    let style = if p.simulated {
                        colour.filled()
                    } else {
                        colour.stroke_width(2)
                    };
                    Circle::new((f64::from(p.n), p.fps), 5, style)
                }))
                .map_err(|e| format!("plot: {e}"))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .position(SeriesLabelPosition::LowerLeft)
            .draw()
            .map_err(|e| format!("plot: {e}"))?;
        root.present().map_err(|e| format!("plot: {e}"))?;
    }
    image::RgbImage::from_raw(w, h, buf).ok_or_else(|| "plot: buffer size".to_string())
}
