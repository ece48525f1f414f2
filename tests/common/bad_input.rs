//! Helpers of the bad-input tests (`tests/bad_input_scene.rs`, `tests/bad_input_cli.rs`,
//! `tests/bad_input_vox.rs`): each feeds one bad input to the real `sim` binary
//! (`CARGO_BIN_EXE_sim`) in a fresh temporary folder, and [`expect_failure`] checks that the
//! program
//!
//! * exits with a non-zero code (and is not killed by a signal),
//! * prints a clear message on stderr that names the problem and where it is (the scene file
//!   with `line:column`, a path into the scene such as `instances[0](body).keys[0].scale`, the
//!   command-line option, or the asset and its file), without repeating itself,
//! * does not panic (stderr never contains "panicked"),
//! * leaves nothing half-written: no PNG anywhere in the folder, neither the `--report-json`
//!   nor the `--dump-hits` file, no `*.tmp` file, and no per-frame line on stdout.
//!
//! Scene cases start from `scenes/car.ron` with one edit ([`replace_once`], [`scene_case`]).

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::process::run_sim;

/// Time after which a run of the binary is killed and the test fails.
pub const TIMEOUT: Duration = Duration::from_secs(120);

/// A scratch folder, unique per test and process, removed when dropped.
pub struct Tmp {
    /// The folder.
    pub dir: PathBuf,
}

impl Tmp {
    pub fn new(test: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("svo_sim_bad_input_{test}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the scratch folder");
        Self { dir }
    }

    /// A path inside the folder, as a string argument.
    pub fn p(&self, name: &str) -> String {
        path_str(&self.dir.join(name))
    }

    /// Writes a file into the folder and returns its path.
    pub fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> String {
        let p = self.dir.join(name);
        std::fs::write(&p, bytes).expect("write a scratch file");
        path_str(&p)
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

pub fn path_str(p: &Path) -> String {
    p.to_str().expect("temporary paths are UTF-8").to_string()
}

/// The value following `flag` in `args`.
pub fn flag_value<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    args.iter()
        .position(|a| a == flag)
        .and_then(|i| args.get(i + 1))
        .map(String::as_str)
}

/// Every file below `dir`.
pub fn files_below(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p);
            }
        }
    }
    out
}

/// Fails if a `": "`-separated clause of the error line occurs twice (an error chain printed
/// with its causes repeated).
pub fn assert_no_repetition(args: &[String], stderr: &str) {
    for line in stderr.lines().filter(|l| l.starts_with("error:")) {
        let clauses: Vec<&str> = line.split(": ").map(str::trim).collect();
        for (i, c) in clauses.iter().enumerate() {
            if c.len() >= 12 && clauses[..i].contains(c) {
                panic!(
                    "sim {args:?}: the error message repeats itself (\"{c}\" occurs more than once), \
                     which is not a clear message:\n{stderr}"
                );
            }
        }
    }
}

/// Runs `sim` with `args` (plus `--out`, `--report-json` and `--dump-hits` into `t` unless
/// `args` sets them), expects a clean failure whose stderr contains every string of `expect`,
/// and returns stderr.
pub fn expect_failure(t: &Tmp, args: &[String], expect: &[&str]) -> String {
    let mut full = args.to_vec();
    for (flag, name) in [
        ("--out", "out"),
        ("--report-json", "report.json"),
        ("--dump-hits", "hits.bin"),
    ] {
        if flag_value(args, flag).is_none() {
            full.push(flag.into());
            full.push(t.p(name));
        }
    }
    let r = run_sim(&full, None, TIMEOUT);
    let ctx = format!(
        "sim {full:?}\nexit: {:?}\nstdout:\n{}\nstderr:\n{}",
        r.status, r.stdout, r.stderr
    );
    assert!(
        r.status.code().is_some(),
        "sim was killed by a signal\n{ctx}"
    );
    assert!(!r.status.success(), "sim exited 0 on a bad input\n{ctx}");
    assert!(
        !r.stderr.contains("panicked"),
        "sim panicked instead of reporting an error\n{ctx}"
    );
    assert!(
        !r.stderr.trim().is_empty(),
        "sim failed without a message on stderr\n{ctx}"
    );
    for e in expect {
        assert!(
            r.stderr.contains(e),
            "the message does not contain {e:?}\n{ctx}"
        );
    }
    assert!(
        !r.stdout
            .lines()
            .any(|l| l.starts_with("frame ") || l.starts_with("summary:")),
        "frames were rendered before the error\n{ctx}"
    );
    for flag in ["--report-json", "--dump-hits"] {
        let p = flag_value(&full, flag).unwrap();
        assert!(
            !Path::new(p).exists(),
            "{flag} {p} exists after a failed run\n{ctx}"
        );
    }
    let left: Vec<PathBuf> = files_below(&t.dir)
        .into_iter()
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            n.ends_with(".png") || n.ends_with(".tmp")
        })
        .collect();
    assert!(
        left.is_empty(),
        "files left behind by a failed run: {left:?}\n{ctx}"
    );
    // Checked last, so a failure here means everything above passed.
    assert_no_repetition(&full, &r.stderr);
    r.stderr
}

/// String arguments.
pub fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// A small, fast run of the default scene.
pub fn small_default(extra: &[&str]) -> Vec<String> {
    let mut v = args(&[
        "--width", "32", "--height", "24", "--frames", "1", "--depth", "5",
    ]);
    v.extend(args(extra));
    v
}

/// The example scene's text.
pub fn car() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/car.ron"))
        .expect("read scenes/car.ron")
}

/// `text` with the first occurrence of `from` replaced; fails if `from` is absent (so the test
/// notices when `scenes/car.ron` changes under it).
pub fn replace_once(text: &str, from: &str, to: &str) -> String {
    assert!(
        text.contains(from),
        "scenes/car.ron no longer contains {from:?}; update the test"
    );
    text.replacen(from, to, 1)
}

/// Writes `text` as a scene into `t`, runs it and expects failure with the scene path and every
/// string of `expect`. The scene is loaded and checked before the command line's small
/// resolution, frame count and depth apply, so those only keep a wrongly accepted scene fast.
pub fn scene_case(t: &Tmp, text: &str, expect: &[&str]) -> String {
    let path = t.write("scene.ron", text);
    let mut want = vec![path.as_str()];
    want.extend_from_slice(expect);
    expect_failure(t, &small_default(&["--scene", &path]), &want)
}

/// The (line, column) of the `{path}:{line}:{column}:` prefix in `stderr`.
pub fn line_col(stderr: &str, path: &str) -> (usize, usize) {
    let at = stderr
        .find(&format!("{path}:"))
        .unwrap_or_else(|| panic!("no \"{path}:\" in\n{stderr}"));
    let rest = &stderr[at + path.len() + 1..];
    let mut it = rest.splitn(3, ':');
    let line = it.next().and_then(|s| s.parse().ok());
    let col = it.next().and_then(|s| s.parse().ok());
    match (line, col) {
        (Some(l), Some(c)) => (l, c),
        _ => panic!("no line:column after {path} in\n{stderr}"),
    }
}

/// 1-based number of the first line of `text` containing `needle`.
pub fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not in the text"))
        + 1
}
