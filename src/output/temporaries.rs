//! The registry of live temporary files: every output being written under a temporary name is
//! listed here until it is renamed to its final name or removed.
//!
//! Pipeline position: under [`super::writer`], the one output writer. On an error the writer's
//! guard removes its temporary when it is dropped; on SIGINT/SIGTERM the exit path
//! ([`super::interrupt`], the `sim` binary's `main`) calls [`remove_all`], which also covers
//! temporaries whose guard is never dropped (a second signal ends the process at once). A
//! rename and a removal never race: both happen under the registry's lock, so a file is either
//! complete under its final name or gone.

use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

/// Live temporaries: (id, path).
static LIVE: Mutex<Vec<(u64, PathBuf)>> = Mutex::new(Vec::new());
/// Temporaries removed unfinished so far (by a guard's drop or by [`remove_all`]).
static REMOVED: AtomicUsize = AtomicUsize::new(0);
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// The registry, also after a panic elsewhere held it (the list stays valid: every change
/// is a single push or remove).
fn live() -> MutexGuard<'static, Vec<(u64, PathBuf)>> {
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// A registered temporary file; removed when dropped unless [`Temporary::persist`] renamed it.
#[derive(Debug)]
pub struct Temporary {
    id: u64,
    path: PathBuf,
    done: bool,
}

impl Temporary {
    /// Creates a new, empty, hidden temporary beside `target` (same folder, so the final
    /// rename stays on one file system and is atomic): `.NAME.PID.N.tmp`. It is registered
    /// before it exists, so no moment leaves an unlisted file.
    pub fn create_beside(target: &Path) -> io::Result<(Self, File)> {
        let name = target
            .file_name()
            .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path names no file"))?;
        let id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
        let mut tmp = std::ffi::OsString::from(".");
        tmp.push(name);
        tmp.push(format!(".{}.{id}.tmp", std::process::id()));
        let path = target.with_file_name(tmp);
        let mut list = live();
        list.push((id, path.clone()));
        // `create_new`: a leftover or concurrent file of the same name is never clobbered.
        match File::options().write(true).create_new(true).open(&path) {
            Ok(file) => Ok((
                Self {
                    id,
                    path,
                    done: false,
                },
                file,
            )),
            Err(e) => {
                list.retain(|(i, _)| *i != id);
                Err(e)
            }
        }
    }

    /// The temporary's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Renames the temporary to `target` and unregisters it. Fails (and the drop removes the
    /// temporary) if the exit path already removed it.
    pub fn persist(mut self, target: &Path) -> io::Result<()> {
        let mut list = live();
        let Some(k) = list.iter().position(|(i, _)| *i == self.id) else {
            self.done = true;
            return Err(io::Error::new(
                io::ErrorKind::Interrupted,
                "the unfinished file was removed by an interruption",
            ));
        };
        std::fs::rename(&self.path, target)?;
        list.swap_remove(k);
        self.done = true;
        Ok(())
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if self.done {
            return;
        }
        let mut list = live();
        if let Some(k) = list.iter().position(|(i, _)| *i == self.id) {
            list.swap_remove(k);
            // The error being reported is the one that matters; a failed removal adds nothing.
            if std::fs::remove_file(&self.path).is_ok() {
                REMOVED.fetch_add(1, Ordering::Relaxed);
            }
        }
    }
}

/// Removes every live temporary and returns how many unfinished files were removed in this
/// process so far (by guards and by this call).
pub fn remove_all() -> usize {
    let mut list = live();
    for (_, p) in list.drain(..) {
        if std::fs::remove_file(&p).is_ok() {
            REMOVED.fetch_add(1, Ordering::Relaxed);
        }
    }
    REMOVED.load(Ordering::Relaxed)
}

/// Removes every live temporary and ends the process with `code` while still holding the
/// registry, so no rename can complete in between (a second signal's exit).
pub fn remove_all_and_exit(code: i32, message: impl FnOnce(usize) -> String) -> ! {
    let mut list = live();
    for (_, p) in list.drain(..) {
        if std::fs::remove_file(&p).is_ok() {
            REMOVED.fetch_add(1, Ordering::Relaxed);
        }
    }
    eprintln!("{}", message(REMOVED.load(Ordering::Relaxed)));
    std::process::exit(code)
}
