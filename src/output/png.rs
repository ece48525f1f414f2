//! Simple shading of hit records to an 8-bit RGB image (for people, not for comparison:
//! tools compare the records, see [`super::dump`]).
//!
//! colour = leaf colour × (ambient + (1 − ambient)·max(0, n·(−L))), n the leaf's normal in
//! world space, L the light's unit direction; misses get the background.

use crate::models::reference::HitRecord;
use glam::DVec3;
use image::RgbImage;

/// Shades records into an image.
pub fn shade(
    records: &[HitRecord],
    width: u32,
    height: u32,
    light_dir: [f64; 3],
    ambient: f64,
    background: [u8; 3],
) -> RgbImage {
    let to_light = -DVec3::from_array(light_dir).normalize();
    let mut img = RgbImage::new(width, height);
    for (p, rec) in img.pixels_mut().zip(records) {
        p.0 = if rec.hit {
            let n = DVec3::from_array(rec.shade_normal.map(f64::from));
            let k = ambient + (1.0 - ambient) * n.dot(to_light).max(0.0);
            let c = rec.colour;
            [0, 1, 2].map(|i| (f64::from(c[i]) * k).round().clamp(0.0, 255.0) as u8)
        } else {
            background
        };
    }
    img
}

/// Encodes an image as PNG bytes.
pub fn encode_png(img: &RgbImage) -> Result<Vec<u8>, image::ImageError> {
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )?;
    Ok(bytes)
}
