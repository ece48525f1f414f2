//! Running the `sim` binary from integration tests: captured output and a hard time limit,
//! so a hung run fails its test instead of hanging the suite.

use std::ffi::OsStr;
use std::io::Read;
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// What a finished run printed.
pub struct Run {
    /// Exit status.
    pub status: ExitStatus,
    /// Everything written to stdout.
    pub stdout: String,
    /// Everything written to stderr.
    pub stderr: String,
}

/// Runs `sim args` (in `cwd` if given); kills it and fails the test after `timeout`.
pub fn run_sim<S: AsRef<OsStr> + std::fmt::Debug>(
    args: &[S],
    cwd: Option<&Path>,
    timeout: Duration,
) -> Run {
    run_sim_env(args, cwd, &[], timeout)
}

/// [`run_sim`] with extra environment variables for the child.
pub fn run_sim_env<S: AsRef<OsStr> + std::fmt::Debug>(
    args: &[S],
    cwd: Option<&Path>,
    env: &[(&str, &str)],
    timeout: Duration,
) -> Run {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_sim"));
    cmd.envs(env.iter().copied())
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    if let Some(dir) = cwd {
        cmd.current_dir(dir);
    }
    let mut child = cmd.spawn().expect("start the sim binary");
    let mut out = child.stdout.take().expect("stdout is piped");
    let mut err = child.stderr.take().expect("stderr is piped");
    // Drain both pipes while waiting, or a chatty run could block on a full pipe.
    let out_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = out.read_to_end(&mut s);
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err.read_to_end(&mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait for sim") {
            break Some(s);
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let stdout = String::from_utf8_lossy(&out_reader.join().expect("stdout reader")).into_owned();
    let stderr = String::from_utf8_lossy(&err_reader.join().expect("stderr reader")).into_owned();
    let Some(status) = status else {
        panic!(
            "sim {args:?} ran longer than {} s and was killed\nstdout:\n{stdout}\nstderr:\n{stderr}",
            timeout.as_secs()
        );
    };
    Run {
        status,
        stdout,
        stderr,
    }
}

/// A scratch folder for a test's outputs, emptied on creation and removed when dropped.
pub struct Scratch(pub std::path::PathBuf);

impl Scratch {
    /// `<temp>/svo_<suite>_<name>_<pid>`: unique per test and per process.
    pub fn new(suite: &str, name: &str) -> Self {
        let d = std::env::temp_dir().join(format!("svo_{suite}_{name}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("create the scratch folder");
        Self(d)
    }

    /// A path inside the folder, as a string argument.
    pub fn p(&self, name: &str) -> String {
        self.0.join(name).display().to_string()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
