//! Reading input files with a size cap: the one reader behind every file the library takes
//! (scene, hardware, datapath and sweep configurations, `.vox` models, fuzz replays).
//!
//! Pipeline position: the very first step of a run, before any parsing. A file is read through
//! `Read::take(cap + 1)`, so a path to `/dev/zero`, `/dev/urandom` or a FIFO that never ends
//! stops at the cap with an error naming the file and the cap, instead of reading until memory
//! runs out. Non-regular files (devices, FIFOs) are allowed: the cap bounds them the same way,
//! whatever their reported length. The caps are far above any real input: the largest scene or
//! configuration in the repository is a few kB, the largest `.vox` in the shared models a few MB.

use std::io::Read;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Cap of the text configuration files (scene, hardware, datapath, sweep `--configs`): 16 MiB.
pub const CONFIG_CAP_BYTES: u64 = 16 << 20;

/// Default cap of a MagicaVoxel `.vox` file: 256 MiB (`--max-vox-mib` raises it). A `.vox`
/// holds at most 256³ voxels per model at 4 bytes each (64 MiB) per model.
pub const DEFAULT_VOX_CAP_BYTES: u64 = 256 << 20;

/// Why an input file could not be read.
#[derive(Debug, Error)]
pub enum InputError {
    /// The OS refused the file or a read failed.
    #[error("cannot read {what} file {}: {source}", path.display())]
    Io {
        /// What the file is ("scene", "hardware", "MagicaVoxel", …).
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The file holds more than the cap; reading stopped there.
    #[error(
        "{what} file {} is larger than {} (the limit for {what} files); reading stopped there{hint}",
        path.display(),
        mib(*cap_bytes)
    )]
    TooLarge {
        /// What the file is.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// The cap in bytes.
        cap_bytes: u64,
        /// How to raise the cap, if it can be raised (e.g. "; raise it with --max-vox-mib").
        hint: &'static str,
    },
    /// A text file is not UTF-8.
    #[error("{what} file {} is not UTF-8 text: {source}", path.display())]
    NotText {
        /// What the file is.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// Where the first invalid byte is.
        #[source]
        source: std::string::FromUtf8Error,
    },
}

fn mib(bytes: u64) -> String {
    if bytes % (1 << 20) == 0 {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}

/// What is read and how much of it is allowed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cap {
    /// What the file is, for messages ("scene", "hardware", …).
    pub what: &'static str,
    /// Most bytes accepted.
    pub bytes: u64,
    /// How to raise the cap, appended to the error ("" when it cannot be raised).
    pub hint: &'static str,
}

impl Cap {
    /// The 16 MiB cap of a configuration file of kind `what`.
    pub const fn config(what: &'static str) -> Self {
        Self {
            what,
            bytes: CONFIG_CAP_BYTES,
            hint: "",
        }
    }

    /// The cap of a `.vox` file, `bytes` long (from `--max-vox-mib`, default
    /// [`DEFAULT_VOX_CAP_BYTES`]).
    pub const fn vox(bytes: u64) -> Self {
        Self {
            what: "MagicaVoxel",
            bytes,
            hint: "; raise it with --max-vox-mib",
        }
    }
}

/// The bytes of `path`, at most `cap.bytes` of them.
pub fn read_bytes(path: &Path, cap: Cap) -> Result<Vec<u8>, InputError> {
    let io = |source| InputError::Io {
        what: cap.what,
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    // One byte past the cap tells a file of exactly the cap from a longer one.
    file.take(cap.bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > cap.bytes {
        return Err(InputError::TooLarge {
            what: cap.what,
            path: path.to_path_buf(),
            cap_bytes: cap.bytes,
            hint: cap.hint,
        });
    }
    Ok(bytes)
}

/// The text of `path` (UTF-8), at most `cap.bytes` bytes of it.
pub fn read_text(path: &Path, cap: Cap) -> Result<String, InputError> {
    String::from_utf8(read_bytes(path, cap)?).map_err(|source| InputError::NotText {
        what: cap.what,
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, len: usize) -> PathBuf {
        let p = std::env::temp_dir().join(format!("svo_input_{}_{name}", std::process::id()));
        std::fs::write(&p, vec![b'a'; len]).expect("temp file");
        p
    }

    #[test]
    fn a_file_of_exactly_the_cap_is_read_and_one_byte_more_is_refused() {
        let cap = Cap {
            what: "test",
            bytes: 100,
            hint: "",
        };
        let at = temp("at", 100);
        assert_eq!(read_bytes(&at, cap).expect("at the cap").len(), 100);
        let over = temp("over", 101);
        let e = read_bytes(&over, cap).expect_err("over the cap");
        assert!(
            e.to_string()
                .contains("is larger than 100 bytes (the limit for test files)"),
            "{e}"
        );
        let _ = std::fs::remove_file(at);
        let _ = std::fs::remove_file(over);
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_device_stops_at_the_cap() {
        let e = read_text(Path::new("/dev/zero"), Cap::config("scene")).expect_err("endless");
        assert_eq!(
            e.to_string(),
            "scene file /dev/zero is larger than 16 MiB (the limit for scene files); reading \
             stopped there"
        );
    }

    #[test]
    fn invalid_utf8_is_named_as_such() {
        let p = std::env::temp_dir().join(format!("svo_input_{}_utf8", std::process::id()));
        std::fs::write(&p, [0xff, 0xfe]).expect("temp file");
        let e = read_text(&p, Cap::config("hardware")).expect_err("not text");
        assert!(e.to_string().contains("is not UTF-8 text"), "{e}");
        let _ = std::fs::remove_file(p);
    }
}
