//! The sorting network as the RTL elaborates it: the model's comparator layers for `n` lanes
//! (`units::sorter::network_stages`) packed as `svo_sorter`'s PAIRS parameter.
//!
//! Pipeline position: the sorter stage's description, shared by the vectors' sorter package
//! (`vectors::stage::sorter`, NET_PAIRS) and the hardware package (`cycle::hw_package`,
//! SORTER_NET_PAIRS), so that the RTL, the vectors and the model read one network.

/// The model's network for `n` lanes as the RTL takes it (`svo_sorter`'s PAIRS): every layer
/// `slots` comparator slots of 16 bits, {i[7:0], j[7:0]}, unused slots (0, 0).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NetworkPairs {
    /// Lanes N.
    pub lanes: u8,
    /// Layers D.
    pub depth: usize,
    /// Comparator slots per layer: max(N / 2, 1), the most a layer of disjoint pairs holds.
    pub slots: usize,
    /// Slot values, layer by layer, least significant first.
    pub words: Vec<u16>,
}

impl NetworkPairs {
    /// The network of `n` lanes (`units::sorter::network_stages`).
    pub fn new(n: u8) -> Self {
        let stages = crate::units::sorter::network_stages(n);
        let slots = usize::from(n / 2).max(1);
        let mut words = vec![0u16; stages.len() * slots];
        for (l, layer) in stages.iter().enumerate() {
            for (p, &(i, j)) in layer.iter().enumerate() {
                // i < j < n ≤ 255 and a layer has at most n / 2 disjoint pairs.
                words[l * slots + p] = ((i as u16) << 8) | (j as u16 & 0xff);
            }
        }
        Self {
            lanes: n,
            depth: stages.len(),
            slots,
            words,
        }
    }

    /// Bits of the vector: D · slots · 16.
    pub fn width(&self) -> u32 {
        (self.words.len() * 16) as u32
    }

    /// The vector as hex digits, most significant first (`0` for an empty network).
    pub fn hex(&self) -> String {
        if self.words.is_empty() {
            return "0".into();
        }
        self.words
            .iter()
            .rev()
            .map(|w| format!("{w:04x}"))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn network_pairs_pack_the_models_layers() {
        // By hand from BEST_8's first and last layers: (0,2) (1,3) (4,6) (5,7) ...
        // (1,2) (3,4) (5,6) and an empty slot.
        let p = NetworkPairs::new(8);
        assert_eq!((p.lanes, p.depth, p.slots, p.width()), (8, 6, 4, 384));
        assert_eq!(&p.words[..4], &[0x0002, 0x0103, 0x0406, 0x0507]);
        assert_eq!(&p.words[20..], &[0x0102, 0x0304, 0x0506, 0x0000]);
        assert!(p.hex().starts_with("0000050603040102"));
        assert!(p.hex().ends_with("0507040601030002"));
        let p16 = NetworkPairs::new(16);
        assert_eq!((p16.depth, p16.slots, p16.width()), (10, 8, 1280));
        assert_eq!(p16.words.iter().filter(|&&w| w != 0).count(), 60);
    }
}
