//! The seed inputs the fuzzer mutates: real files of each format, so that mutations start from
//! inputs that reach deep into the parsers.
//!
//! Pipeline position: none — input to [`super::runner`]. The `.vox` seeds are the shared
//! models (CC BY 4.0, read from their folder at run time, never copied into the repository)
//! plus two small files built here (a plain model, and one placed through a scene graph with a
//! rotation); the scene seeds are the repository's example scenes, compiled in; the hardware
//! and datapath seeds are the defaults as `sim hardware` and `sim datapath` print them (with
//! their comments) and as bare RON.

use super::targets::Target;
use crate::output::config_text::{datapath_text, hardware_text};
use anyhow::{Context, Result};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use std::path::Path;

/// One seed input and where it came from.
#[derive(Clone, Debug)]
pub struct Seed {
    /// File name or a short description.
    pub name: String,
    /// The bytes.
    pub bytes: Vec<u8>,
}

const SCENES: [(&str, &str); 4] = [
    ("scenes/car.ron", include_str!("../../../scenes/car.ron")),
    (
        "scenes/moving_camera.ron",
        include_str!("../../../scenes/moving_camera.ron"),
    ),
    (
        "scenes/static_single.ron",
        include_str!("../../../scenes/static_single.ron"),
    ),
    (
        "scenes/vox_traffic.ron",
        include_str!("../../../scenes/vox_traffic.ron"),
    ),
];

/// The seeds of `target`; `vox_dir` is the folder of shared `.vox` models (skipped if absent:
/// the built-in seeds remain). `max_vox_bytes` leaves out larger models, whose every mutated
/// copy takes long to load.
pub fn seeds(target: Target, vox_dir: Option<&Path>, max_vox_bytes: u64) -> Result<Vec<Seed>> {
    let text = |name: &str, s: String| Seed {
        name: name.to_string(),
        bytes: s.into_bytes(),
    };
    Ok(match target {
        Target::Vox => {
            let mut out = vec![
                Seed {
                    name: "built-in plain model".into(),
                    bytes: plain_vox(),
                },
                Seed {
                    name: "built-in scene graph".into(),
                    bytes: graph_vox(),
                },
            ];
            if let Some(dir) = vox_dir {
                out.extend(vox_files(dir, max_vox_bytes)?);
            }
            out
        }
        Target::Scene => SCENES.iter().map(|(n, s)| text(n, s.to_string())).collect(),
        Target::Hardware => {
            let hw = HwConfig::default();
            let (commented, _) = hardware_text(&hw, &DatapathConfig::default());
            vec![
                text("sim hardware", commented),
                text("default (RON)", ron::ser::to_string(&hw)?),
            ]
        }
        Target::Datapath => {
            let dp = DatapathConfig::default();
            vec![
                text("sim datapath", datapath_text(&dp)?),
                text("default (RON)", ron::ser::to_string(&dp)?),
            ]
        }
    })
}

fn vox_files(dir: &Path, max_bytes: u64) -> Result<Vec<Seed>> {
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot read the seed folder {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "vox"))
        .collect();
    names.sort();
    let mut out = Vec::new();
    for p in names {
        let len = std::fs::metadata(&p)
            .with_context(|| format!("cannot read {}", p.display()))?
            .len();
        if len > max_bytes {
            continue;
        }
        // Bounded as well: a device or FIFO named *.vox reports length 0 above.
        let bytes = crate::input::read_bytes(
            &p,
            crate::input::Cap {
                what: "seed",
                bytes: max_bytes,
                hint: "",
            },
        )?;
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        out.push(Seed { name, bytes });
    }
    Ok(out)
}

fn chunk(id: &[u8; 4], content: &[u8], children: &[u8]) -> Vec<u8> {
    let mut out = id.to_vec();
    out.extend((content.len() as u32).to_le_bytes());
    out.extend((children.len() as u32).to_le_bytes());
    out.extend_from_slice(content);
    out.extend_from_slice(children);
    out
}

fn file(children: &[u8]) -> Vec<u8> {
    let mut out = b"VOX ".to_vec();
    out.extend(150u32.to_le_bytes());
    out.extend(chunk(b"MAIN", &[], children));
    out
}

fn model(size: [u32; 3], voxels: &[[u8; 4]]) -> Vec<u8> {
    let size_bytes: Vec<u8> = size.iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut xyzi = (voxels.len() as u32).to_le_bytes().to_vec();
    xyzi.extend(voxels.iter().flatten());
    let mut out = chunk(b"SIZE", &size_bytes, &[]);
    out.extend(chunk(b"XYZI", &xyzi, &[]));
    out
}

/// A dictionary of `(key, value)` string pairs as `.vox` scene chunks store them.
fn dict(pairs: &[(&str, &str)]) -> Vec<u8> {
    let mut out = (pairs.len() as u32).to_le_bytes().to_vec();
    for s in pairs.iter().flat_map(|(k, v)| [k, v]) {
        out.extend((s.len() as u32).to_le_bytes());
        out.extend(s.bytes());
    }
    out
}

/// A 3 × 2 × 4 model of eight voxels (an L and a column), no scene graph.
fn plain_vox() -> Vec<u8> {
    let v = [
        [0, 0, 0, 1],
        [1, 0, 0, 2],
        [2, 0, 0, 3],
        [0, 1, 0, 4],
        [0, 0, 1, 5],
        [0, 0, 2, 6],
        [0, 0, 3, 7],
        [2, 1, 3, 8],
    ];
    file(&model([3, 2, 4], &v))
}

/// Two models placed through nTRN → nGRP → (nTRN → nSHP) × 2, one translated and rotated
/// (`_r` 0x26: a signed permutation), one mirrored on a hidden layer's sibling.
fn graph_vox() -> Vec<u8> {
    let mut children = model([2, 2, 2], &[[0, 0, 0, 1], [1, 1, 1, 2]]);
    children.extend(model(
        [3, 1, 1],
        &[[0, 0, 0, 3], [1, 0, 0, 4], [2, 0, 0, 5]],
    ));
    let trn = |id: u32, child: u32, frame: &[(&str, &str)]| {
        let mut c = id.to_le_bytes().to_vec();
        c.extend(dict(&[]));
        c.extend(child.to_le_bytes());
        c.extend(u32::MAX.to_le_bytes()); // reserved id
        c.extend(0u32.to_le_bytes()); // layer
        c.extend(1u32.to_le_bytes()); // one frame
        c.extend(dict(frame));
        chunk(b"nTRN", &c, &[])
    };
    let shp = |id: u32, model_id: u32| {
        let mut c = id.to_le_bytes().to_vec();
        c.extend(dict(&[]));
        c.extend(1u32.to_le_bytes());
        c.extend(model_id.to_le_bytes());
        c.extend(dict(&[]));
        chunk(b"nSHP", &c, &[])
    };
    children.extend(trn(0, 1, &[]));
    let mut grp = 1u32.to_le_bytes().to_vec();
    grp.extend(dict(&[]));
    grp.extend(2u32.to_le_bytes());
    grp.extend(2u32.to_le_bytes());
    grp.extend(4u32.to_le_bytes());
    children.extend(chunk(b"nGRP", &grp, &[]));
    children.extend(trn(2, 3, &[("_t", "4 -2 1"), ("_r", "38")]));
    children.extend(shp(3, 0));
    children.extend(trn(4, 5, &[("_t", "-3 0 2"), ("_r", "20")]));
    children.extend(shp(5, 1));
    file(&children)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_built_in_seed_is_accepted() {
        for t in Target::ALL {
            for s in seeds(t, None, 0).expect("seeds") {
                if let Err(e) = t.run(&s.bytes) {
                    panic!("{} seed {} rejected: {e}", t.name(), s.name);
                }
            }
        }
    }

    #[test]
    fn the_graph_seed_places_both_models() {
        let a = crate::world::assets::vox::load_vox_bytes(&graph_vox(), Path::new("graph"), None)
            .expect("graph seed loads");
        assert_eq!(a.models, 2);
        assert_eq!(a.voxels, 5);
    }
}
