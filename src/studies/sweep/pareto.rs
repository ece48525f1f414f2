//! Pareto fronts of (error, cost) points, both to be minimised, and each point's relative
//! distance to its front.
//!
//! Pipeline position: after every configuration of `sim sweep` ran on a scene; once for error
//! against cycles per frame and once for error against DSP48E2 slices.
//!
//! Definitions (`docs/accuracy.md`): q dominates p when q.e ≤ p.e and q.c ≤ p.c with one of
//! them strict; the front is the set of points no other point dominates (equal points are both
//! on it). The distance of p is the multiplicative ε-indicator: the smallest δ ≥ 0 such that p
//! improved by the factor (1 − δ) in both error and cost, ((1 − δ)·p.e, (1 − δ)·p.c), would be
//! dominated by no point, i.e. δ(p) = max(0, max_q min(1 − q.e/p.e, 1 − q.c/p.c)). It is 0 on
//! the front, and "within 5 %" means δ ≤ 0.05: 5 % less error and 5 % less cost would put p on
//! it. A point that ties another's cost (or error) and loses on the other axis has δ = 0 and
//! is still off the front; `on_front` tells the two apart.

use std::cmp::Ordering;

/// A point: error and cost, both ≥ 0 and finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Error (lower is better).
    pub error: f64,
    /// Cost (lower is better).
    pub cost: f64,
}

/// Which points are on the front, by a sort and one sweep: after sorting by error (then cost),
/// a point is on the front iff its cost is below every cost of a strictly smaller error and is
/// the lowest among the points of its own error.
pub fn on_front(points: &[Point]) -> Vec<bool> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        let (p, q) = (points[a], points[b]);
        p.error.total_cmp(&q.error).then(p.cost.total_cmp(&q.cost))
    });
    let mut front = vec![false; points.len()];
    let mut best_before = f64::INFINITY;
    let mut i = 0;
    while i < order.len() {
        let e = points[order[i]].error;
        let mut j = i;
        while j < order.len() && points[order[j]].error.total_cmp(&e) == Ordering::Equal {
            j += 1;
        }
        // Sorted by cost within the group: its first cost is the group's lowest.
        let group_min = points[order[i]].cost;
        for &k in &order[i..j] {
            front[k] = points[k].cost == group_min && group_min < best_before;
        }
        best_before = best_before.min(group_min);
        i = j;
    }
    front
}

/// 1 − a/b: how far p's coordinate b must shrink (as a fraction) before it drops below q's
/// coordinate a. For b = 0 it cannot shrink: q is escaped on this axis already when a > 0
/// (−∞) and never when a = 0 (+∞, so the other axis decides).
fn gain(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        1.0 - a / b
    } else if a > 0.0 {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    }
}

/// Each point's distance δ to the front (a fraction: 0.05 is 5 %). Only front points need be
/// tried as q: every point is weakly dominated by one of them, whose terms are no smaller. A q
/// equal to p in both coordinates is skipped: equal points never dominate each other.
pub fn distance(points: &[Point]) -> Vec<f64> {
    let front = on_front(points);
    let fp: Vec<Point> = points
        .iter()
        .zip(&front)
        .filter(|(_, &f)| f)
        .map(|(p, _)| *p)
        .collect();
    points
        .iter()
        .map(|p| {
            fp.iter()
                .filter(|q| *q != p)
                .map(|q| gain(q.error, p.error).min(gain(q.cost, p.cost)))
                .fold(0.0, f64::max)
        })
        .collect()
}

/// Each point's error excess at its cost: 1 − e_min/p.e, where e_min is the lowest error of a
/// point costing no more than p (p included), i.e. the share of p's error that a configuration
/// of no greater cost avoids. 0 on the front and at a tie that wins on error; the vertical gap
/// to the staircase, which the ε distance misses when p ties another point's cost.
pub fn error_excess(points: &[Point]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a].cost.total_cmp(&points[b].cost));
    let mut e_min = vec![f64::INFINITY; points.len()];
    let mut best = f64::INFINITY;
    let mut i = 0;
    while i < order.len() {
        let c = points[order[i]].cost;
        let mut j = i;
        while j < order.len() && points[order[j]].cost.total_cmp(&c) == Ordering::Equal {
            best = best.min(points[order[j]].error);
            j += 1;
        }
        for &k in &order[i..j] {
            e_min[k] = best;
        }
        i = j;
    }
    points
        .iter()
        .zip(e_min)
        .map(|(p, m)| {
            if p.error > 0.0 {
                1.0 - m / p.error
            } else {
                0.0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_case_by_hand() {
        let p = |error, cost| Point { error, cost };
        let pts = [
            p(1.0, 10.0),
            p(2.0, 5.0),
            p(2.0, 6.0),
            p(3.0, 10.0),
            p(1.0, 10.0),
        ];
        assert_eq!(on_front(&pts), [true, true, false, false, true]);
        let d = distance(&pts);
        assert_eq!(d[0], 0.0);
        assert_eq!(d[1], 0.0);
        // (2, 6) against (2, 5): min(0, 1/6) = 0 — it ties the error and loses on cost.
        assert_eq!(d[2], 0.0);
        // (3, 10) against (2, 5): min(1/3, 1/2) = 1/3.
        assert!((d[3] - 1.0 / 3.0).abs() < 1e-15);
        let x = error_excess(&pts);
        assert_eq!(x[..3], [0.0, 0.0, 0.0]);
        // (3, 10): the lowest error at cost ≤ 10 is 1.
        assert!((x[3] - 2.0 / 3.0).abs() < 1e-15);
    }
}
