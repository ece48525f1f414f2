//! `sim render` end to end on a hand-made `.vox`: the solid box it prints, the plane rule in
//! the model's own coordinates on each axis (including y, which the loader reflects), the
//! dump's miss encoding, and clean errors with nothing written for bad inputs.
//!
//! The expected hits are derived by hand from the contract of `docs/render.md` (a ray lying in
//! the plane x = k belongs to cell k, as a floor-based DDA has it), not from the code.

use std::path::Path;
use std::process::Command;

mod common;
use common::bad_input::Tmp;

/// A `.vox` without scene graph: one 4×4×4 model with solid voxels `cells` (file indices).
fn vox_bytes(cells: &[[u8; 3]]) -> Vec<u8> {
    let mut chunks = Vec::new();
    chunks.extend(b"SIZE");
    chunks.extend(12u32.to_le_bytes());
    chunks.extend(0u32.to_le_bytes());
    for s in [4u32, 4, 4] {
        chunks.extend(s.to_le_bytes());
    }
    chunks.extend(b"XYZI");
    chunks.extend((4 + 4 * cells.len() as u32).to_le_bytes());
    chunks.extend(0u32.to_le_bytes());
    chunks.extend((cells.len() as u32).to_le_bytes());
    for c in cells {
        chunks.extend([c[0], c[1], c[2], 1]);
    }
    let mut b = b"VOX ".to_vec();
    b.extend(150u32.to_le_bytes());
    b.extend(b"MAIN");
    b.extend(0u32.to_le_bytes());
    b.extend((chunks.len() as u32).to_le_bytes());
    b.extend(chunks);
    b
}

struct Out {
    ok: bool,
    stdout: String,
    stderr: String,
}

fn sim(args: &[String]) -> Out {
    let o = Command::new(env!("CARGO_BIN_EXE_sim"))
        .args(args)
        .output()
        .expect("run sim");
    Out {
        ok: o.status.success(),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

fn strings(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// The single pixel of a 1×1 pinhole image looks exactly along `look − eye`.
fn one_ray(t: &Tmp, model: &str, eye: &str, look: &str) -> (bool, f64, [i32; 3]) {
    let dump = t.p("one.bin");
    let mut a = strings(&[
        "render", model, "--eye", eye, "--look", look, "--width", "1", "--height", "1",
    ]);
    a.extend(strings(&["--up", "0.3,0.4,1", "--dump-hits", &dump]));
    let r = sim(&a);
    assert!(r.ok, "sim {a:?}: {}", r.stderr);
    let b = std::fs::read(&dump).unwrap();
    assert_eq!(b.len(), 32 + 80);
    let rec = &b[32..];
    let t_hit = f64::from_le_bytes(rec[48..56].try_into().unwrap());
    let v = |o: usize| i32::from_le_bytes(rec[o..o + 4].try_into().unwrap());
    (rec[68] == 1, t_hit, [v(56), v(60), v(64)])
}

#[test]
fn plane_rule_in_model_coordinates() {
    let t = Tmp::new("render_plane");
    // File voxel (1, 2, 1) of a 4³ model without scene graph sits at v − floor(4/2):
    // model voxel (−1, 0, −1), the cell [−1, 0] × [0, 1] × [−1, 0].
    let model = t.write("one.vox", vox_bytes(&[[1, 2, 1]]));
    let r = sim(&strings(&[
        "render", &model, "--eye", "9,9,9", "--look", "0,0,0", "--width", "2", "--height", "2",
    ]));
    assert!(r.ok, "{}", r.stderr);
    assert!(
        r.stdout
            .contains("x -1..-1, y 0..0, z -1..-1 (1x1x1 voxels)"),
        "{}",
        r.stdout
    );
    // Rays lying in a voxel plane, moving along another axis: the plane x = k (or y, z) gives
    // cell k, the one above the plane. Each case: eye, look, expected hit, expected t.
    let cases: [(&str, &str, bool, f64); 12] = [
        // plane y = 0 (the voxel's lower y face), moving ±x: in cell y = 0 → hit
        ("-10,0,-0.5", "10,0,-0.5", true, 9.0),
        ("10,0,-0.5", "-10,0,-0.5", true, 10.0),
        // plane y = 1 (its upper face): cell y = 1, empty → miss
        ("-10,1,-0.5", "10,1,-0.5", false, -1.0),
        ("10,1,-0.5", "-10,1,-0.5", false, -1.0),
        // plane x = −1 (lower x face) moving ±y: hit; x = 0 (upper): miss
        ("-1,-10,-0.5", "-1,10,-0.5", true, 10.0),
        ("-1,10,-0.5", "-1,-10,-0.5", true, 9.0),
        ("0,-10,-0.5", "0,10,-0.5", false, -1.0),
        ("0,10,-0.5", "0,-10,-0.5", false, -1.0),
        // plane z = −1 (lower z face) moving ±x: hit; z = 0 (upper): miss
        ("-10,0.5,-1", "10,0.5,-1", true, 9.0),
        ("10,0.5,-1", "-10,0.5,-1", true, 10.0),
        ("-10,0.5,0", "10,0.5,0", false, -1.0),
        ("10,0.5,0", "-10,0.5,0", false, -1.0),
    ];
    for (eye, look, hit, t_hit) in cases {
        let got = one_ray(&t, &model, eye, look);
        let want = (hit, t_hit, if hit { [-1, 0, -1] } else { [0, 0, 0] });
        assert_eq!(got, want, "eye {eye} look {look}");
    }
    // CSV variant of a miss.
    let csv = t.p("miss.csv");
    let r = sim(&strings(&[
        "render",
        &model,
        "--eye",
        "-10,1,-0.5",
        "--look",
        "10,1,-0.5",
        "--width",
        "1",
        "--height",
        "1",
        "--dump-hits",
        &csv,
    ]));
    assert!(r.ok, "{}", r.stderr);
    let text = std::fs::read_to_string(&csv).unwrap();
    let line = text.lines().nth(1).unwrap();
    assert!(
        line.starts_with("0,0,0,-1.0000000000000000e0,0,0,0,"),
        "{line}"
    );
}

#[test]
fn bad_inputs_fail_cleanly_and_write_nothing() {
    let t = Tmp::new("render_bad");
    let model = t.write("one.vox", vox_bytes(&[[1, 2, 1]]));
    let garbage = t.write("bad.vox", b"VOX \x96\x00\x00\x00MAIN garbage");
    let empty = t.write("empty.vox", vox_bytes(&[]));
    let base = |m: &str| strings(&["render", m, "--eye", "9,9,9", "--look", "0,0,0"]);
    let with = |m: &str, extra: &[&str]| {
        let mut a = base(m);
        a.extend(strings(extra));
        a
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (base(&garbage), "bad.vox"),
        (base(&empty), "no visible voxels"),
        (base(&t.p("missing.vox")), "missing.vox"),
        (
            strings(&["render", &model, "--eye", "nan,0,0", "--look", "0,0,0"]),
            "eye.x = NaN",
        ),
        (
            strings(&["render", &model, "--eye", "1,2,3", "--look", "1,2,3"]),
            "coincide",
        ),
        (with(&model, &["--up", "1,1,1"]), "parallel"),
        (with(&model, &["--up", "0,0,0"]), "parallel"),
        (with(&model, &["--fov", "0"]), "--fov 0"),
        (with(&model, &["--fov", "180"]), "--fov 180"),
        (with(&model, &["--fov", "inf"]), "fov = inf"),
        (with(&model, &["--ortho", "0"]), "--ortho 0"),
        (with(&model, &["--ortho", "-3"]), "--ortho -3"),
        (with(&model, &["--repeat", "0"]), "--repeat 0"),
        (with(&model, &["--repeat", "101"]), "--repeat 101"),
        (with(&model, &["--width", "0"]), "image size 0x480"),
        (with(&model, &["--width", "20000"]), "image size 20000x480"),
        (
            with(&model, &["--width", "8000", "--height", "8000"]),
            "image size 8000x8000",
        ),
        (
            strings(&["render", &model, "--eye", "1e300,0,0", "--look", "0,0,0"]),
            "eye.x = 1e300",
        ),
        (
            strings(&["render", &model, "--eye", "1,2", "--look", "0,0,0"]),
            "three numbers",
        ),
    ];
    for (args, expect) in cases {
        let mut a = args.clone();
        a.extend(strings(&[
            "--out",
            &t.p("img.png"),
            "--dump-hits",
            &t.p("hits.bin"),
        ]));
        let r = sim(&a);
        assert!(!r.ok, "sim {a:?} succeeded");
        assert!(
            !r.stderr.contains("panicked"),
            "sim {a:?} panicked: {}",
            r.stderr
        );
        assert!(
            r.stderr.contains(expect),
            "sim {a:?}: {:?} not in {}",
            expect,
            r.stderr
        );
        for f in ["img.png", "hits.bin"] {
            assert!(!t.dir.join(f).exists(), "sim {a:?} wrote {f}");
        }
        let left: Vec<_> = std::fs::read_dir(&t.dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(left.is_empty(), "sim {a:?} left {left:?}");
    }
    // A missing output folder is found before any work.
    let r = sim(&with(&model, &["--dump-hits", &t.p("no/such/hits.bin")]));
    assert!(!r.ok && r.stderr.contains("does not exist"), "{}", r.stderr);
    assert!(!Path::new(&t.p("no")).exists());
}

/// `--repeat N` traces the image N times for a best-of-N time: the dump and the counts are
/// those of a single trace, byte for byte.
#[test]
fn repeated_trace_gives_the_same_records() {
    let t = Tmp::new("render_repeat");
    let model = t.write(
        "few.vox",
        vox_bytes(&[[1, 2, 1], [2, 2, 1], [1, 3, 2], [0, 0, 0]]),
    );
    let mut outs = Vec::new();
    for n in ["1", "3"] {
        let dump = t.p(&format!("hits{n}.bin"));
        let r = sim(&strings(&[
            "render",
            &model,
            "--eye",
            "7.3,-5.1,4.2",
            "--look",
            "0,0,0",
            "--width",
            "33",
            "--height",
            "17",
            "--threads",
            "2",
            "--repeat",
            n,
            "--dump-hits",
            &dump,
        ]));
        assert!(r.ok, "{}", r.stderr);
        let counts = r
            .stdout
            .lines()
            .last()
            .and_then(|l| l.split(" walk steps").next())
            .unwrap_or_default()
            .to_string();
        outs.push((std::fs::read(&dump).expect("dump"), counts));
    }
    assert!(outs[0].1.contains("hits"), "{}", outs[0].1);
    assert_eq!(outs[0].1, outs[1].1, "hit and step counts");
    assert!(
        outs[0].0 == outs[1].0,
        "the dumps of --repeat 1 and 3 differ"
    );
}
