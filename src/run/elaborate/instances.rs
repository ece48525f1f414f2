//! Elaboration of the two-level instance scheme (docs/instances.md §7): whether the pipeline
//! gets the tile-list reader in front of its sphere lanes, and the instance-id width a scene
//! with many instances needs in the hit record.
//!
//! Pipeline position: called by [`super::plan::plan`] after the sphere-lane decision; adds
//! its decisions only for scenes with more instances than sphere lanes, so every scene the
//! flat lanes already test in one pass elaborates (and prints) exactly as before.
//!
//! The rule: flat, a ray occupies the lanes ⌈n / lanes⌉ cycles; with lists, ⌈list / lanes⌉
//! (at least 1) plus the reader's 4 cycles of latency, at the price of the list memory
//! (`units::tile_list::bram36_count`). When n ≤ lanes both take one pass, so the lists could
//! only add latency and block RAM: left out (no line is printed: the `sphere_lanes` line
//! already says one pass tests every instance). When n > lanes the flat stage cannot take one
//! ray per cycle, and the lists are kept. Neither choice can change a record: the lists are
//! conservative (`models::reference::cull`, `tests/two_level.rs`).

use super::analyse::SceneFacts;
use super::plan::{decision, Action, Decision};
use super::savings::Saving;
use rtl_model::cycle::hw_config::{HwConfig, Placement};
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::tile_list::{bram36_count, TileListConfig};

/// Bits an instance id needs for `n` instances with the all-ones code kept for "none".
pub fn instance_bits_for(n: u64) -> u8 {
    let mut b = 1u8;
    while b < 16 && (1u64 << b) - 1 < n {
        b += 1;
    }
    b
}

/// The scheme's decisions for `facts`, changing `hw` and `dp` where the scene needs it;
/// returns the decisions and the list memory the run uses (`None`: flat).
pub fn decide(
    facts: &SceneFacts,
    hw: &mut HwConfig,
    dp: &mut DatapathConfig,
) -> (Vec<Decision>, Option<TileListConfig>) {
    let n = facts.instances.len() as u64;
    let lanes = u64::from(hw.sphere_units.max(1));
    let mut ds = Vec::new();
    if n <= lanes {
        return (ds, None);
    }
    let tl = TileListConfig::default();
    let (w, h) = (hw.frame.width, hw.frame.height);
    let bram = bram36_count(&tl, hw.sphere_units, w, h);
    ds.push(decision(
        "instance_lists",
        Action::Kept,
        format!(
            "{n} instances > {lanes} lanes: flat, every ray takes {} lane cycles; per-tile lists \
             ({}-pixel tiles) take ⌈list/{lanes}⌉, at {bram} BRAM36 and {} cycles of latency",
            n.div_ceil(lanes),
            tl.tile,
            rtl_model::units::tile_list::LATENCY_CYCLES
        ),
    ));
    let need = instance_bits_for(n);
    if need > dp.hit_record.instance_bits {
        let narrow = dp.clone();
        let from = dp.hit_record.instance_bits;
        dp.hit_record.instance_bits = need;
        ds.push(decision(
            "instance_bits",
            Action::Resized {
                from: u64::from(from),
                to: u64::from(need),
            },
            format!(
                "{n} instances need {need}-bit ids (all ones = none): the hit record widens to {} bits",
                dp.hit_record.word_bits()
            ),
        ));
        // A record wider than a URAM288's 72 bits takes two columns: with the direction table
        // also in URAM the part's 960 would not hold both, so the table streams from DRAM
        // (docs/cycle-model.md §1.3, as for the 105-bit record).
        if dp.hit_record.word_bits() > 72 && hw.direction_table == Placement::Uram {
            let before = hw.resources(&narrow).map(|r| r.used);
            let hb_growth = hw
                .hit_buffer_bits(dp)
                .saturating_sub(hw.hit_buffer_bits(&narrow));
            let table_bits = hw.direction_table_bits(dp);
            hw.direction_table = Placement::External;
            let after = hw.resources(dp).map(|r| r.used);
            let mut d = decision(
                "direction_table",
                Action::LeftOut,
                format!(
                    "the {}-bit hit record takes two URAM288 columns: the direction table streams from DRAM (saving net of the wider hit buffer)",
                    dp.hit_record.word_bits()
                ),
            );
            // Both changes together, so the printed totals equal the elaborated estimate.
            if let (Ok(b), Ok(a)) = (before, after) {
                d.saved = Saving {
                    dsp48e2: b.dsp48e2.saturating_sub(a.dsp48e2),
                    bram36: b.bram36.saturating_sub(a.bram36),
                    uram288: b.uram288.saturating_sub(a.uram288),
                    ram_bits: table_bits.saturating_sub(hb_growth),
                    ..Saving::default()
                };
            }
            ds.push(d);
        }
    }
    (ds, Some(tl))
}

#[cfg(test)]
mod tests {
    use super::instance_bits_for;

    #[test]
    fn id_bits_keep_a_none_code() {
        assert_eq!(instance_bits_for(254), 8);
        assert_eq!(instance_bits_for(255), 8);
        assert_eq!(instance_bits_for(256), 9);
        assert_eq!(instance_bits_for(1000), 10);
        assert_eq!(instance_bits_for(10_000), 14);
    }
}
