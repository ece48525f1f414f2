//! Two non-default datapaths for the unit property tests and `bound_caps.rs`: each unit's
//! worst observed error is checked against its bound (above and, for tightness, below) on the
//! default datapath and on these, and `bound_caps.rs` pins their bounds by hand derivations.
//!
//! - **narrow**: every 30-fraction-bit unit format cut to 22 bits and every 32-bit position
//!   to 24 (sQ2.22 directions and matrix entries, sQ8.24 positions, 1/d sQ22.22), and the
//!   sphere's squares uQ16.40 (square root uQ8.20), all rounded to nearest even as the default;
//! - **truncating**: the default widths, but every rounding truncates (AP_TRN: the host's
//!   positions, directions and matrix entries, the transform's outputs, 1/d), and the
//!   sphere's squares uQ20.44 (square root uQ10.22).

use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::{Format, Quant};

/// The two non-default datapaths, named, each valid (`DatapathConfig::validate`).
pub fn non_default() -> [(&'static str, DatapathConfig); 2] {
    let q = Quant::RndConv;
    let mut n = DatapathConfig::default();
    let (dir, pos) = (
        Format::sq(2, 22).with_quant(q),
        Format::sq(8, 24).with_quant(q),
    );
    n.raygen.dir = dir;
    n.raygen.pos = pos;
    n.raygen.mat = dir;
    n.sphere.dir = dir;
    n.sphere.pos = pos;
    n.sphere.sq = Format::uq(16, 40).with_quant(n.sphere.sq.quant);
    n.transform.pos = pos;
    n.transform.dir = dir;
    n.transform.mat = dir;
    n.transform.local_pos = pos;
    n.transform.local_dir = dir;
    n.reciprocal.input = dir;
    n.reciprocal.output = Format::sq(22, 22).with_quant(q);
    n.walker.pos = pos;
    n.walker.inv = n.reciprocal.output;

    let t = Quant::Trn;
    let mut r = DatapathConfig::default();
    r.raygen.dir = r.raygen.dir.with_quant(t);
    r.raygen.pos = r.raygen.pos.with_quant(t);
    r.raygen.mat = r.raygen.mat.with_quant(t);
    r.sphere.pos = r.raygen.pos;
    r.sphere.dir = r.raygen.dir;
    r.sphere.sq = Format::uq(20, 44).with_quant(r.sphere.sq.quant);
    r.transform.pos = r.transform.pos.with_quant(t);
    r.transform.dir = r.transform.dir.with_quant(t);
    r.transform.mat = r.transform.mat.with_quant(t);
    r.transform.local_pos = r.transform.local_pos.with_quant(t);
    r.transform.local_dir = r.transform.local_dir.with_quant(t);
    r.reciprocal.input = r.reciprocal.input.with_quant(t);
    r.reciprocal.output = r.reciprocal.output.with_quant(t);
    r.walker.inv = r.reciprocal.output;
    r.walker.pos = r.transform.local_pos;
    for (name, dp) in [("narrow", &n), ("truncating", &r)] {
        if let Err(e) = dp.validate() {
            panic!("the {name} datapath is invalid: {e}");
        }
    }
    [("narrow", n), ("truncating", r)]
}

/// The default datapath and the two of [`non_default`], named.
#[allow(dead_code)] // bound_caps.rs pins the default's bounds on their own and uses only non_default
pub fn all() -> [(&'static str, DatapathConfig); 3] {
    let [a, b] = non_default();
    [("default", DatapathConfig::default()), a, b]
}
