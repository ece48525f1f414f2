//! Scene facts for elaboration: what the animation actually does over its frames.
//!
//! Pipeline position: before anything is built or rendered; the facts come from the validated
//! scene alone (keyframes interpolated frame by frame, exactly as the renderers will), so the
//! decisions in [`super::plan`] rest on the frames that will run, not on the keyframes'
//! appearance (a key pair 0° → 360° rotates even though both keys look alike).

use crate::error::AssetError;
use crate::world::assets::effective_depths;
use crate::world::scene::{Camera, Scene};
use glam::{DMat3, DVec3};
use rtl_model::datapath::{overflow_table, signals, DatapathConfig};
use rtl_model::fixed::{from_f64, to_f64};

pub use crate::models::cycle::elaboration::{InstanceFacts, SceneFacts};

fn camera_bits(c: &Camera) -> [u64; 13] {
    let v = |x: DVec3| x.to_array().map(f64::to_bits);
    let [a, b, c2, d] = [v(c.position), v(c.forward), v(c.right), v(c.up)];
    [
        a[0],
        a[1],
        a[2],
        b[0],
        b[1],
        b[2],
        c2[0],
        c2[1],
        c2[2],
        d[0],
        d[1],
        d[2],
        c.tan_half_vfov.to_bits(),
    ]
}

/// Whether the rotation's entries, quantised into `raygen.mat` as the host writes them, are
/// exactly the identity's codes (1.0 must itself be representable).
fn quantised_identity(r: DMat3, dp: &DatapathConfig) -> bool {
    let mut ov = overflow_table();
    let fmt = dp.raygen.mat;
    let one = from_f64(1.0, fmt, &mut ov, signals::RAYGEN_MAT);
    if to_f64(one, fmt) != 1.0 {
        return false;
    }
    let cols = [r.x_axis, r.y_axis, r.z_axis];
    cols.iter().enumerate().all(|(k, c)| {
        c.to_array().iter().enumerate().all(|(j, &x)| {
            let want = if j == k { one } else { 0 };
            from_f64(x, fmt, &mut ov, signals::RAYGEN_MAT) == want
        })
    })
}

/// The facts of `scene` as it will run (its frames and resolution already overridden), with
/// the `--depth` option and the datapath whose matrix format decides "rotates".
pub fn analyse(
    scene: &Scene,
    depth: Option<u8>,
    dp: &DatapathConfig,
) -> Result<SceneFacts, AssetError> {
    let frames = scene.file.frames;
    let depths = effective_depths(scene, depth)?;
    let deepest_asset = depths.iter().copied().max().unwrap_or(1);
    let mut range = 0.0f64;
    let mut cameras = Vec::with_capacity(frames as usize);
    for f in 0..frames {
        // Validation already checked every frame's camera; a failure here cannot happen, and
        // would only make the camera count as moving (the conservative side).
        let cam = scene.camera_at(f).ok();
        if let Some(c) = &cam {
            range = range.max(c.position.abs().max_element());
        }
        cameras.push(cam.as_ref().map(camera_bits));
    }
    let camera_moves_every_frame = cameras.windows(2).all(|w| w[0].is_none() || w[0] != w[1]);
    // poses_at's half_extent is scale × asset half size: a half size of 1 gives the scale.
    let ones = vec![1.0; scene.file.assets.len()];
    let first = scene.poses_at(0, &ones);
    let mut flags = vec![(false, false, false); first.len()];
    for f in 0..frames {
        for ((p, p0), fl) in scene.poses_at(f, &ones).iter().zip(&first).zip(&mut flags) {
            range = range.max(p.centre.abs().max_element());
            fl.0 |= p != p0;
            fl.1 |= !quantised_identity(p.world_from_local, dp);
            fl.2 |= p.half_extent != DVec3::ONE;
        }
    }
    let instances = scene
        .file
        .instances
        .iter()
        .zip(flags)
        .map(|(spec, (moves, rotates, scaled))| InstanceFacts {
            name: spec.name.clone(),
            moves,
            rotates,
            scaled,
        })
        .collect();
    Ok(SceneFacts {
        frames,
        instances,
        camera_moves_every_frame,
        deepest_asset,
        coordinate_range_m: range,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::sdf::rotation_xyz_deg;

    #[test]
    fn zero_angles_are_the_identity_codes_and_a_quarter_turn_is_not() {
        let dp = DatapathConfig::default();
        assert!(quantised_identity(rotation_xyz_deg([0.0; 3]), &dp));
        assert!(!quantised_identity(rotation_xyz_deg([0.0, 90.0, 0.0]), &dp));
        // A full turn is the identity up to f64 error far below the matrix format's LSB.
        assert!(quantised_identity(rotation_xyz_deg([0.0, 360.0, 0.0]), &dp));
    }
}
