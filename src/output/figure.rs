//! What every plotted figure shares: the embedded font and the PNG encoding.
//!
//! Pipeline position: the last step of `sim drift`, `sim sweep` and `sim bench --model cycle
//! --scaling`, which draw with `plotters` into an RGB buffer (bitmap backend only). Text uses
//! DejaVu Sans compiled into the binary (the `dejavu` crate) through plotters' `ab_glyph`
//! feature, so no system font is looked up and a figure is the same on every machine; figures
//! are encoded with the strongest PNG compression because some are committed under `docs/`.

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::ImageEncoder;
use plotters::style::FontStyle;
use std::sync::OnceLock;

/// Registers the embedded font under the family name the figures use (`sans-serif`), once per
/// process.
pub fn register_font() -> Result<(), String> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| "the embedded DejaVu Sans font cannot be parsed".to_string())
    })
    .clone()
}

/// Encodes a figure as PNG with the strongest compression; `what` names it in an error.
pub fn encode_png_best(img: &image::RgbImage, what: &str) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    PngEncoder::new_with_quality(&mut bytes, CompressionType::Best, FilterType::Adaptive)
        .write_image(
            img.as_raw(),
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| format!("{what}: {e}"))?;
    Ok(bytes)
}
