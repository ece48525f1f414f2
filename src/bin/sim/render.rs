//! `sim render MODEL.vox`: parses the camera (in the model's own voxel coordinates), runs
//! `svo_sim::run::render::render_model` and writes the PNG and the model-coordinate hit dump
//! (`docs/render.md`).

use anyhow::{bail, Context, Result};
use clap::Args;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use svo_sim::models::reference::HitRecord;
use svo_sim::output::model_dump::encode_dump;
use svo_sim::output::png::{encode_png, shade};
use svo_sim::output::writer::{Destination, Output};
use svo_sim::run::render::{render_model, ModelCamera, ModelRender, Projection};

/// Options of `sim render`.
#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// The MagicaVoxel model.
    #[arg(value_name = "MODEL.vox")]
    model: PathBuf,
    /// Render only the file's model N (0-based, in file order; the file's scene graph is not
    /// used). Default: the whole scene, or model 0 of a file of animation frames (several
    /// models, no scene graph), with a warning.
    #[arg(long, value_name = "N")]
    model_index: Option<usize>,
    /// Eye (pinhole) or centre of the view plane (--ortho), model voxel coordinates "x,y,z".
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    eye: [f64; 3],
    /// Point the camera looks at, "x,y,z".
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    look: [f64; 3],
    /// Up hint, "x,y,z" (MagicaVoxel is z up).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,0,1")]
    up: [f64; 3],
    /// Vertical field of view of the pinhole, degrees in (0, 180).
    #[arg(long, default_value_t = 40.0, allow_hyphen_values = true)]
    fov: f64,
    /// Orthographic view of this width (voxels) instead of a pinhole; --fov is then unused.
    #[arg(long, value_name = "WIDTH", allow_hyphen_values = true)]
    ortho: Option<f64>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 640)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 480)]
    height: u32,
    /// Write the shaded image here (PNG).
    #[arg(long, value_name = "FILE.png")]
    out: Option<PathBuf>,
    /// Write every pixel's ray and hit here, in model coordinates (binary, or CSV if the name
    /// ends in .csv; docs/render.md §5).
    #[arg(long, value_name = "FILE")]
    dump_hits: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Trace the image this many times and report the fastest (for benchmarks: the OpenVDB
    /// peer takes its best of the same count); the records are those of one trace.
    #[arg(long, default_value_t = 1, value_name = "N")]
    repeat: u32,
    /// Largest model file read, MiB (1 to 65536); a larger one is refused without reading
    /// past the limit.
    #[arg(long, value_name = "MIB", default_value_t = crate::args::DEFAULT_VOX_MIB)]
    max_vox_mib: u64,
}

fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y, z] = parts.as_slice() else {
        return Err(format!("expected three numbers \"x,y,z\", got {s:?}"));
    };
    let num = |p: &str| {
        p.parse::<f64>()
            .map_err(|_| format!("{p:?} is not a number (in {s:?})"))
    };
    Ok([num(x)?, num(y)?, num(z)?])
}

/// Checks an output path before the work (its folder exists, it is no folder); `-` is
/// refused because the summary goes to standard output.
fn check_output(path: &Path, option: &str) -> Result<()> {
    match Destination::of(path).with_context(|| option.to_string())? {
        Destination::Stdout => {
            bail!("{option} -: sim render prints its summary on standard output; give a file name")
        }
        _ => Ok(()),
    }
}

fn summary(a: &RenderArgs, r: &ModelRender) -> String {
    let f = &r.frame;
    let e = f.extent();
    let hits = r.hits.iter().filter(|h| h.hit).count();
    let rays = r.hits.len();
    let [b0, b1, b2] = f.base;
    let s = f.side() as i64;
    format!(
        "model {}{}: {} model instance(s), {} solid voxels, {} surface leaves\n\
         solid bounding box (model voxel indices, inclusive): x {}..{}, y {}..{}, z {}..{} ({}x{}x{} voxels)\n\
         octree: depth {}, side {} voxels, solid box offset ({}, {}, {}) voxels from its corner; \
         it covers model coordinates [{b0}, {}] x [{b1}, {}] x [{b2}, {}]\n\
         {}x{} rays: {hits} hits ({:.1}%), {} walk steps, {:.2} Mrays/s",
        a.model.display(),
        match a.model_index {
            Some(n) => format!(" (model index {n} of {})", f.file_models),
            None => String::new(),
        },
        f.models,
        f.voxels,
        f.leaves,
        f.solid_min[0],
        f.solid_max[0],
        f.solid_min[1],
        f.solid_max[1],
        f.solid_min[2],
        f.solid_max[2],
        e[0],
        e[1],
        e[2],
        f.depth,
        f.side(),
        f.offset[0],
        f.offset[1],
        f.offset[2],
        b0 + s,
        b1 + s,
        b2 + s,
        r.width,
        r.height,
        100.0 * hits as f64 / rays.max(1) as f64,
        r.counters.steps,
        rays as f64 / r.trace_seconds.max(1e-9) / 1e6,
    )
}

/// Runs `sim render`.
pub fn render_command(a: RenderArgs) -> Result<()> {
    if let Some(n) = a.threads {
        if n == 0 || n > 1024 {
            bail!("--threads {n} is out of range (1 to 1024)");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("cannot start the worker threads")?;
    }
    if let Some(p) = &a.out {
        check_output(p, "--out")?;
    }
    if let Some(p) = &a.dump_hits {
        check_output(p, "--dump-hits")?;
    }
    let projection = match a.ortho {
        Some(view_width) => Projection::Ortho { view_width },
        None => Projection::Pinhole { vfov_deg: a.fov },
    };
    let camera = ModelCamera {
        eye: a.eye,
        look: a.look,
        up: a.up,
        projection,
    };
    let max_vox = crate::args::vox_cap_bytes(a.max_vox_mib)?;
    let r = render_model(
        &a.model,
        &camera,
        (a.width, a.height),
        a.repeat,
        a.model_index,
        max_vox,
    )?;
    if let Some(notice) = &r.notice {
        eprintln!("warning: {notice}");
    }
    println!("{}", summary(&a, &r));
    let png = match &a.out {
        Some(_) => {
            let records: Vec<HitRecord> = r
                .hits
                .iter()
                .map(|h| HitRecord {
                    hit: h.hit,
                    shade_normal: h.normal,
                    colour: h.rgba,
                    ..HitRecord::MISS
                })
                .collect();
            // The scene default light (docs/scene-format.md) in model axes (z up).
            let img = shade(
                &records,
                r.width,
                r.height,
                [-0.4, -0.3, -1.0],
                0.3,
                [40, 44, 52],
            );
            Some(encode_png(&img).context("cannot encode the PNG")?)
        }
        None => None,
    };
    // Nothing half-done: both outputs are written in full before either is committed, so a
    // failed dump leaves no image either (and never removes what the path held).
    let mut outputs = Vec::new();
    let dump = a
        .dump_hits
        .as_ref()
        .map(|p| (p, encode_dump(p, &r, projection)));
    for (p, bytes) in a
        .out
        .as_ref()
        .zip(png.as_ref())
        .into_iter()
        .chain(dump.as_ref().map(|(p, b)| (*p, b)))
    {
        let mut o = Output::create(p)?;
        o.write_all(bytes)
            .with_context(|| format!("cannot write {}", p.display()))?;
        outputs.push(o);
    }
    for o in outputs {
        o.commit()?;
    }
    Ok(())
}
