//! The one output writer: every file the program writes (PNG frames, the JSON report, hit
//! dumps, transaction logs, waveforms, study tables and figures, vectors, fuzz findings)
//! goes through [`Output`] or the helpers built on it.
//!
//! Pipeline position: the last step of every command. What the given path *is* decides how
//! it is written, once, when the output is opened ([`Destination::of`]):
//!
//! - a regular file, or a path that does not exist: written to a hidden temporary in the same
//!   folder (registered in [`super::temporaries`]) and renamed over the path only when complete
//!   and synced, so the path never holds a partial file; the old file's permissions are kept;
//! - a symbolic link: the chain is followed (relative links from the link's folder) and its
//!   final target is written as above; a dangling link's target is created, and the link stays;
//! - a device, FIFO or socket: opened for writing and written in place, never truncated,
//!   removed or renamed (`/dev/null` stays a device, a FIFO's reader gets the data);
//! - `-`: standard output, where the caller allows it (single outputs such as the JSON
//!   report; a folder of files cannot be `-`, see [`refuse_stdout_folder`]).

use super::temporaries::Temporary;
use std::fs::{File, Metadata};
use std::io::{self, BufWriter, Write};
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Symbolic links followed at most (as the kernel's limit for path resolution).
const MAX_LINKS: usize = 40;

/// An output that cannot be opened or written.
#[derive(Debug, Error)]
pub enum OutputError {
    /// An operating-system error while opening, writing or renaming.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The path as given.
        path: String,
        /// The OS error.
        source: io::Error,
    },
    /// A path that cannot take this output.
    #[error("cannot write {path}: {message}")]
    Refused {
        /// The path as given.
        path: String,
        /// Why.
        message: String,
    },
}

impl OutputError {
    fn io(path: &Path, source: io::Error) -> Self {
        Self::Io {
            path: path.display().to_string(),
            source,
        }
    }
    fn refused(path: &Path, message: impl Into<String>) -> Self {
        Self::Refused {
            path: path.display().to_string(),
            message: message.into(),
        }
    }
}

/// How an output path is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Destination {
    /// `-`: standard output.
    Stdout,
    /// A regular file or a new one at `target` (the end of any symlink chain): temporary,
    /// then rename.
    Replace {
        /// The file that receives the content.
        target: PathBuf,
    },
    /// A device, FIFO or socket at `target`: written in place.
    InPlace {
        /// The node that receives the content.
        target: PathBuf,
    },
}

impl Destination {
    /// Decides how `path` is written, without opening or creating anything (so it can be
    /// checked before a run starts; a FIFO is not opened here, which would wait for a
    /// reader). The folder that will hold a new file must exist.
    pub fn of(path: &Path) -> Result<Self, OutputError> {
        if path.as_os_str() == "-" {
            return Ok(Self::Stdout);
        }
        let (target, meta) = resolve(path)?;
        match meta {
            None => {
                let parent = folder_of(&target);
                if !parent.is_dir() {
                    return Err(OutputError::refused(
                        path,
                        format!("folder {} does not exist", parent.display()),
                    ));
                }
                Ok(Self::Replace { target })
            }
            Some(m) if m.is_file() => Ok(Self::Replace { target }),
            Some(m) if m.is_dir() => Err(OutputError::refused(path, "it is a folder")),
            Some(m) => {
                let t = m.file_type();
                if t.is_fifo() || t.is_char_device() || t.is_block_device() || t.is_socket() {
                    Ok(Self::InPlace { target })
                } else {
                    Err(OutputError::refused(path, "not a file, device or FIFO"))
                }
            }
        }
    }
}

/// The folder holding `path` (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    path.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Follows `path`'s symlink chain: the final path and its metadata (`None`: it does not
/// exist).
fn resolve(path: &Path) -> Result<(PathBuf, Option<Metadata>), OutputError> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok((p, None)),
            Err(e) => return Err(OutputError::io(path, e)),
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&p).map_err(|e| OutputError::io(path, e))?;
                p = if link.is_absolute() {
                    link
                } else {
                    folder_of(&p).join(link)
                };
            }
            Ok(m) => return Ok((p, Some(m))),
        }
    }
    Err(OutputError::refused(
        path,
        format!("more than {MAX_LINKS} symbolic links in a chain"),
    ))
}

/// Refuses `-` for an option that names a folder of files (`--out -` of a run or a study).
pub fn refuse_stdout_folder(option: &str, dir: &Path) -> Result<(), OutputError> {
    if dir.as_os_str() == "-" {
        return Err(OutputError::refused(
            dir,
            format!("{option} names a folder of files, which cannot go to standard output"),
        ));
    }
    Ok(())
}

enum Sink {
    Stdout(BufWriter<io::Stdout>),
    Temporary(Temporary, BufWriter<File>, PathBuf),
    InPlace(BufWriter<File>),
}

/// One output being written. Dropped before [`Output::commit`] (an error, an interruption),
/// a temporary is removed and the path keeps what it held; an in-place device or FIFO keeps
/// what was already sent to it.
pub struct Output {
    path: PathBuf,
    sink: Sink,
}

impl Output {
    /// Opens `path` as [`Destination::of`] decides. Opening a FIFO waits for its reader.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let sink = match Destination::of(path)? {
            Destination::Stdout => Sink::Stdout(BufWriter::new(io::stdout())),
            Destination::Replace { target } => {
                let (tmp, file) =
                    Temporary::create_beside(&target).map_err(|e| OutputError::io(path, e))?;
                // A replaced file keeps its permissions (a new one gets the default).
                if let Ok(m) = std::fs::metadata(&target) {
                    std::fs::set_permissions(tmp.path(), m.permissions())
                        .map_err(|e| OutputError::io(path, e))?;
                }
                Sink::Temporary(tmp, BufWriter::new(file), target)
            }
            Destination::InPlace { target } => {
                // Write only: no create, no truncate (neither means anything for a device).
                let file = File::options()
                    .write(true)
                    .open(&target)
                    .map_err(|e| OutputError::io(path, e))?;
                Sink::InPlace(BufWriter::new(file))
            }
        };
        Ok(Self {
            path: path.to_path_buf(),
            sink,
        })
    }

    /// The path as given.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Finishes the output: flushes; a temporary is synced and renamed to its target.
    pub fn commit(self) -> Result<(), OutputError> {
        let path = self.path;
        let err = |e| OutputError::io(&path, e);
        match self.sink {
            Sink::Stdout(mut w) => w.flush().map_err(err),
            Sink::InPlace(mut w) => w.flush().map_err(err),
            Sink::Temporary(tmp, w, target) => {
                let file = w.into_inner().map_err(|e| err(e.into_error()))?;
                file.sync_all().map_err(err)?;
                drop(file);
                tmp.persist(&target).map_err(err)
            }
        }
    }
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.sink {
            Sink::Stdout(w) => w.write(buf),
            Sink::Temporary(_, w, _) => w.write(buf),
            Sink::InPlace(w) => w.write(buf),
        }
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        match &mut self.sink {
            Sink::Stdout(w) => w.write_all(buf),
            Sink::Temporary(_, w, _) => w.write_all(buf),
            Sink::InPlace(w) => w.write_all(buf),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        match &mut self.sink {
            Sink::Stdout(w) => w.flush(),
            Sink::Temporary(_, w, _) => w.flush(),
            Sink::InPlace(w) => w.flush(),
        }
    }
}

/// Writes a whole output at once.
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    let mut out = Output::create(path)?;
    out.write_all(bytes).map_err(|e| OutputError::io(path, e))?;
    out.commit()
}

/// Writes each `(name, bytes)` into `dir` (which must exist), each through [`write_whole`],
/// in order, and returns their paths. Callers encode everything first, so an encoding error
/// writes nothing; a write error names the file.
pub fn write_files(dir: &Path, files: &[(&str, Vec<u8>)]) -> Result<Vec<PathBuf>, String> {
    refuse_stdout_folder("--out", dir).map_err(|e| e.to_string())?;
    let mut paths = Vec::with_capacity(files.len());
    for (name, bytes) in files {
        let p = dir.join(name);
        write_whole(&p, bytes).map_err(|e| e.to_string())?;
        paths.push(p);
    }
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    /// A fresh folder per test under the system's temporary folder.
    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("svo_writer_{name}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_regular_file_is_replaced_whole_and_keeps_its_permissions() {
        let d = scratch("regular");
        let p = d.join("a.txt");
        std::fs::write(&p, "old").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_whole(&p, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o640);
        assert_eq!(names(&d), ["a.txt"], "no temporary left");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn an_output_dropped_before_commit_leaves_the_old_file_and_no_temporary() {
        let d = scratch("dropped");
        let p = d.join("a.txt");
        std::fs::write(&p, "old").unwrap();
        {
            let mut o = Output::create(&p).unwrap();
            o.write_all(b"half").unwrap();
            assert_eq!(names(&d).len(), 2, "the temporary exists while writing");
        }
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(names(&d), ["a.txt"]);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn bad_paths_are_refused_naming_the_problem_and_create_nothing() {
        let d = scratch("refused");
        let missing = d.join("no_such_folder").join("r.json");
        let e = write_whole(&missing, b"x").unwrap_err().to_string();
        assert!(
            e.contains("no_such_folder") && e.contains("does not exist"),
            "{e}"
        );
        std::fs::create_dir(d.join("sub")).unwrap();
        let e = write_whole(&d.join("sub"), b"x").unwrap_err().to_string();
        assert!(e.contains("it is a folder"), "{e}");
        // A symlink loop.
        std::os::unix::fs::symlink("b", d.join("a")).unwrap();
        std::os::unix::fs::symlink("a", d.join("b")).unwrap();
        let e = write_whole(&d.join("a"), b"x").unwrap_err().to_string();
        assert!(e.contains("symbolic links"), "{e}");
        assert_eq!(names(&d), ["a", "b", "sub"]);
        let e = refuse_stdout_folder("--out", Path::new("-"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("--out") && e.contains("standard output"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn destinations_follow_chains_of_links() {
        let d = scratch("chain");
        std::os::unix::fs::symlink("middle", d.join("first")).unwrap();
        std::os::unix::fs::symlink(d.join("last.txt"), d.join("middle")).unwrap();
        assert_eq!(
            Destination::of(&d.join("first")).unwrap(),
            Destination::Replace {
                target: d.join("last.txt")
            }
        );
        assert_eq!(
            Destination::of(Path::new("-")).unwrap(),
            Destination::Stdout
        );
        assert_eq!(
            Destination::of(Path::new("/dev/null")).unwrap(),
            Destination::InPlace {
                target: PathBuf::from("/dev/null")
            }
        );
        write_whole(&d.join("first"), b"through two links").unwrap();
        assert_eq!(
            std::fs::read_to_string(d.join("last.txt")).unwrap(),
            "through two links"
        );
        assert!(std::fs::symlink_metadata(d.join("first"))
            .unwrap()
            .file_type()
            .is_symlink());
        std::fs::remove_dir_all(&d).unwrap();
    }
}
