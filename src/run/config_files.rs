//! Reading the two configuration files a run takes: the datapath (`--datapath`, the format
//! `sim datapath` prints) and the hardware (`--hw`, the format `sim hardware` prints). Each
//! names only what it changes from the default; a malformed file is reported with its line
//! and column, an invalid one with the rule it breaks.
//!
//! Pipeline position: before elaboration and the run; the studies that take these files
//! (`sim bench`, `sim hardware`) read them here too.

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why a configuration file could not be used.
#[derive(Debug, Error)]
pub enum ConfigFileError {
    /// The file could not be read, or is larger than its cap.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// The file is not valid RON of the configuration's schema.
    #[error("{path}:{line}:{col}: malformed {what} configuration: {message}")]
    Malformed {
        /// "datapath" or "hardware".
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// Line of the error (1-based).
        line: usize,
        /// Column of the error (1-based).
        col: usize,
        /// What the parser expected.
        message: String,
    },
    /// The configuration parses but breaks a rule of the model.
    #[error("{path}: invalid {what} configuration: {message}")]
    Invalid {
        /// "datapath" or "hardware".
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// The rule broken.
        message: String,
    },
}

fn parse<T: DeserializeOwned>(what: &'static str, path: &Path) -> Result<T, ConfigFileError> {
    let text = crate::input::read_text(path, crate::input::Cap::config(what))?;
    parse_text(what, &text, path)
}

fn parse_text<T: DeserializeOwned>(
    what: &'static str,
    text: &str,
    path: &Path,
) -> Result<T, ConfigFileError> {
    ron::from_str(text).map_err(|e| ConfigFileError::Malformed {
        what,
        path: path.to_path_buf(),
        line: e.position.line,
        col: e.position.col,
        message: e.code.to_string(),
    })
}

fn checked_datapath(cfg: DatapathConfig, path: &Path) -> Result<DatapathConfig, ConfigFileError> {
    cfg.validate().map_err(|message| ConfigFileError::Invalid {
        what: "datapath",
        path: path.to_path_buf(),
        message: message.to_string(),
    })?;
    Ok(cfg)
}

fn checked_hardware(cfg: HwConfig, path: &Path) -> Result<HwConfig, ConfigFileError> {
    cfg.validate().map_err(|message| ConfigFileError::Invalid {
        what: "hardware",
        path: path.to_path_buf(),
        message: message.to_string(),
    })?;
    Ok(cfg)
}

/// A datapath configuration from RON text already in memory (the parser fuzzer's entry, and
/// the rules [`load_datapath`] applies); `path` only names the text in errors.
pub fn datapath_from_text(text: &str, path: &Path) -> Result<DatapathConfig, ConfigFileError> {
    checked_datapath(parse_text("datapath", text, path)?, path)
}

/// A hardware configuration from RON text already in memory; `path` only names it in errors.
pub fn hardware_from_text(text: &str, path: &Path) -> Result<HwConfig, ConfigFileError> {
    checked_hardware(parse_text("hardware", text, path)?, path)
}

/// The datapath configuration in `path`, or the documented default without one.
pub fn load_datapath(path: Option<&Path>) -> Result<DatapathConfig, ConfigFileError> {
    let Some(p) = path else {
        return Ok(DatapathConfig::default());
    };
    checked_datapath(parse("datapath", p)?, p)
}

/// That the hardware configuration (from `hw_path`, the default without one) times the
/// datapath (`dp_path`): `HwConfig::validate_for`, named by the hardware file, before anything
/// is elaborated or written.
pub fn check_pair(
    hw: &HwConfig,
    hw_path: Option<&Path>,
    dp: &DatapathConfig,
    dp_path: Option<&Path>,
) -> Result<(), ConfigFileError> {
    let name = |p: Option<&Path>, default: &str| {
        p.map_or_else(|| PathBuf::from(default), Path::to_path_buf)
    };
    hw.validate_for(dp)
        .map_err(|message| ConfigFileError::Invalid {
            what: "hardware",
            path: name(hw_path, "<default hardware>"),
            message: format!(
                "{message} (for the datapath of {})",
                name(dp_path, "<default datapath>").display()
            ),
        })
}

/// The hardware configuration in `path`, or the documented default without one.
pub fn load_hardware(path: Option<&Path>) -> Result<HwConfig, ConfigFileError> {
    let Some(p) = path else {
        return Ok(HwConfig::default());
    };
    checked_hardware(parse("hardware", p)?, p)
}
