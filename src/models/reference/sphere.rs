//! Bounding-sphere test in world space (paper Eq. 4) with the entry distance used as sort key.
//!
//! With l = c − o and unit d: the ray's line misses iff l·l − (l·d)² > r². Otherwise
//! t_enter = l·d − √(r² − (l·l − (l·d)²)); when the origin is inside or on the sphere
//! (l·l ≤ r²) t_enter is 0; when the whole sphere is behind the origin (t_exit < 0) the
//! instance is culled too, which Eq. 4 alone would not do.

use glam::DVec3;

/// Entry distance of the ray into the sphere, or `None` if it cannot reach it.
///
/// ```
/// use glam::DVec3;
/// use svo_sim::models::reference::sphere::sphere_entry;
/// let (o, d) = (DVec3::ZERO, DVec3::X);
/// assert_eq!(sphere_entry(o, d, DVec3::new(5.0, 0.0, 0.0), 1.0), Some(4.0));
/// assert_eq!(sphere_entry(o, d, DVec3::new(-5.0, 0.0, 0.0), 1.0), None); // behind
/// assert_eq!(sphere_entry(o, d, DVec3::new(0.5, 0.0, 0.0), 1.0), Some(0.0)); // inside
/// assert_eq!(sphere_entry(o, d, DVec3::new(5.0, 2.0, 0.0), 1.0), None); // beside
/// ```
#[inline]
pub fn sphere_entry(origin: DVec3, dir: DVec3, centre: DVec3, radius: f64) -> Option<f64> {
    let l = centre - origin;
    let tca = l.dot(dir);
    let l2 = l.dot(l);
    let r2 = radius * radius;
    let d2 = l2 - tca * tca;
    if d2 > r2 {
        return None;
    }
    if l2 <= r2 {
        return Some(0.0);
    }
    let thc = (r2 - d2).sqrt();
    let t_enter = tca - thc;
    if t_enter < 0.0 {
        // Outside the sphere, so entry and exit have the same sign: both behind.
        return None;
    }
    Some(t_enter)
}
