//! Atomic file writing: write to a temporary sibling, then rename over the final name.
//! A file that is dropped before [`AtomicFile::commit`] is removed, so an error or a panic
//! never leaves a half-written file under the final name.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written under a temporary name.
pub struct AtomicFile {
    tmp: PathBuf,
    path: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Creates the temporary sibling of `path`.
    pub fn create(path: &Path) -> std::io::Result<Self> {
        let mut name = path
            .file_name()
            .map(|n| n.to_os_string())
            .unwrap_or_default();
        name.push(format!(".{}.tmp", std::process::id()));
        let tmp = path.with_file_name(name);
        let writer = BufWriter::new(File::create(&tmp)?);
        Ok(Self {
            tmp,
            path: path.to_path_buf(),
            writer: Some(writer),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("writer exists until commit")
    }

    /// Flushes, syncs and renames to the final name.
    pub fn commit(mut self) -> std::io::Result<()> {
        let w = self.writer.take().expect("writer exists until commit");
        w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        std::fs::rename(&self.tmp, &self.path)
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Writes a whole file atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.writer().write_all(bytes)?;
    f.commit()
}

/// Writes each `(name, bytes)` into `dir` (which must exist), each atomically, in order, and
/// returns their paths. Callers encode everything first, so an encoding error writes nothing;
/// a write error names the file.
pub fn write_files_atomic(dir: &Path, files: &[(&str, Vec<u8>)]) -> Result<Vec<PathBuf>, String> {
    let mut paths = Vec::with_capacity(files.len());
    for (name, bytes) in files {
        let p = dir.join(name);
        write_atomic(&p, bytes).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
        paths.push(p);
    }
    Ok(paths)
}
