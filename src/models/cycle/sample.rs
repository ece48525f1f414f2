//! Sampled timing (`--sample RATE`): a systematic sample of row bands is timed cycle by cycle,
//! the rest of the frame only warms the machine functionally, and the frame's cycles are
//! estimated with a 95 % confidence interval (docs/cycle-model.md §3.5).
//!
//! Pipeline position: inside `model::CycleModel::run_frame`. The plan ([`Sampler::plan`])
//! splits the frame into bands of `band_rows` rows; the first and last bands and every
//! `period`-th band in between (from a seeded start) are *timed*. Each timed band is run
//! through the pipeline inside a segment that reaches back before it and on after it until the
//! stretch holds enough rays that walk ([`Warming`]: detailed warming, so the FIFOs, ray
//! slots, walker contexts and MSHRs hold the rays they would hold in a full run); segments are
//! planned one at a time from the functional trace's rows ([`Sampler::next_planned`]). Ray
//! generation stops at the end of a segment, the pipeline drains, and the pixels up to the
//! next segment are applied functionally ([`warm_gap`]): their hit-buffer words are written
//! into the BRAM and every node read of their walks goes through the cache's tags (LRU order,
//! line installs), with no cycle. The next segment starts with the walk queue's backlog of the
//! last one: its transform waits until `check_to_transform` holds as many rays as it held when
//! the last segment's generation ended ([`Sampler::segment_band`] bounds the wait), since a
//! queue-bound stretch entered empty can settle into a slower steady state than the full run's.
//!
//! What is measured: `t_b`, the cycle at which the count of written pixels first reaches the
//! first pixel of band `b`. In a full run the frame's cycles telescope, `C = Σ_b (t_{b+1} −
//! t_b)` with `t_0` the frame's start and `t_B` its end, so each band has an increment
//! `y_b = t_{b+1} − t_b`. A timed band measures its `y_b` (the warming after it gives
//! `t_{b+1}`); the estimator and its interval are in [`Estimate::of`].

use super::error::CycleError;
use super::stages::internal;
use super::stats::fps_at_clock;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::vectors::rng::Rng;
use serde::Serialize;

mod warm;
pub use warm::{pipeline_capacity, walking_in_row, warm_gap, Warming, WARM_CAP_FACTOR};

/// Options of sampled timing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleConfig {
    /// One band in `period` (between the first and the last band) is timed: the sampling
    /// rate is 1/`period`.
    pub period: u32,
    /// Rows per band.
    pub band_rows: u32,
    /// Rows run in detail before each timed band (`None`: sized in rays that walk, [`SampleConfig::warming_for`]).
    pub warm_rows: Option<u32>,
    /// Seed of the systematic sample's random start (mixed with the frame number).
    pub seed: u64,
}

/// The documented default: one band in 8.
pub const DEFAULT_RATE: f64 = 0.125;
/// The documented default band height, rows (docs/cycle-model.md §3.5: worst error 0.52 % on
/// the validation matrix at 1280×768, against 1.87 % with bands of 4 rows).
pub const DEFAULT_BAND_ROWS: u32 = 2;

impl SampleConfig {
    /// From a rate in (0, 1]: the period is the nearest integer to 1/rate. Rate 1 times
    /// every band in one segment, so its estimate is the full model's cycles exactly, with
    /// every band's increment in the report (`band_cycles`): the reference a sample's bands
    /// are compared with band by band.
    pub fn from_rate(
        rate: f64,
        band_rows: u32,
        warm_rows: Option<u32>,
        seed: u64,
    ) -> Result<Self, String> {
        if !(rate > 0.0 && rate <= 1.0) {
            return Err(format!(
                "--sample {rate}: the rate must be above 0 and at most 1 (1 times every band)"
            ));
        }
        if band_rows == 0 {
            return Err("--sample-band must be at least 1 row".into());
        }
        let period = (1.0 / rate).round();
        if period > f64::from(u32::MAX) {
            return Err(format!("--sample {rate}: the rate is too small"));
        }
        Ok(Self {
            period: period as u32,
            band_rows,
            warm_rows,
            seed,
        })
    }

    /// Detailed warming around a timed band (docs/cycle-model.md §3.5): `(min_rows,
    /// walking, max_rows)`. The stretch before a band (and the tail after it) grows row by row
    /// until it has at least `min_rows` rows and holds `walking` rays that walk, but no more than
    /// `max_rows` rows. `min_rows` holds twice every ray the pipeline can hold at once (FIFOs,
    /// ray slots and the unit pipes' latencies); `walking` is that same count in rays that
    /// walk, since the queue to be warmed is the rays waiting for walkers, and where few
    /// pixels walk (hit-buffer reuse, sparse scenes) it spans many more rows; `max_rows` is
    /// [`WARM_CAP_FACTOR`] times `min_rows`. `--sample-warm ROWS` fixes all three to ROWS rows.
    pub fn warming_for(&self, hw: &HwConfig, width: u32) -> Warming {
        if let Some(w) = self.warm_rows {
            return Warming {
                min_rows: w,
                walking: 0,
                max_rows: w,
            };
        }
        let rays = 2 * pipeline_capacity(hw);
        let min_rows = rays.div_ceil(u64::from(width.max(1))) as u32;
        Warming {
            min_rows,
            walking: rays,
            max_rows: min_rows.saturating_mul(WARM_CAP_FACTOR),
        }
    }
}

/// A band whose increment is measured.
#[derive(Clone, Copy, Debug)]
struct Band {
    /// Band index.
    index: u32,
    /// Its first pixel.
    first: u64,
    /// The first pixel of the next band (`None` for the last band: the frame's end).
    next: Option<u64>,
    /// First and last band: timed in every frame (not part of the sample).
    certain: bool,
    /// Its rows [r0, r1).
    rows: (u32, u32),
}

/// The sample of one frame while it runs: the timed segments, where the pipeline is, and
/// the cycles at which ray generation accepted the bands' first pixels.
pub struct Sampler {
    cfg: SampleConfig,
    width: u32,
    height: u32,
    warming: Warming,
    /// The most rows of detailed warming before a timed band so far.
    warm_rows_max: u32,
    bands_total: u32,
    start_offset: u32,
    bands: Vec<Band>,
    /// Pixel ranges [from, to) run through the pipeline, in order, disjoint: planned one at a
    /// time ([`Sampler::next_planned`]), since their warming depends on the trace's rows.
    segments: Vec<(u64, u64)>,
    /// The first timed band not yet in a segment.
    next_band: usize,
    /// Cycle at which the count of written pixels reached each mark (sorted).
    marks: Vec<(u64, Option<u64>)>,
    /// The first mark not yet reached.
    next_mark: usize,
    /// Pixels applied functionally.
    warmed: u64,
    /// First pixel of the first timed band of the segment generation is in.
    segment_band: u64,
}

impl Sampler {
    /// The plan of frame `frame` of `width`×`height` pixels on `hw`.
    pub fn plan(cfg: SampleConfig, hw: &HwConfig, frame: u32, width: u32, height: u32) -> Self {
        let w = u64::from(width);
        let rows = cfg.band_rows.max(1);
        let nb = height.div_ceil(rows).max(1);
        let warming = cfg.warming_for(hw, width);
        let k = cfg.period.max(1);
        let start_offset =
            Rng::new(cfg.seed ^ (u64::from(frame) << 32 | 0x5a5a)).below(u64::from(k)) as u32;
        let mut bands = Vec::new();
        for b in 0..nb {
            let certain = b == 0 || b + 1 == nb;
            if !certain && (b - 1) % k != start_offset {
                continue;
            }
            let r0 = b * rows;
            let r1 = ((b + 1) * rows).min(height);
            let first = u64::from(r0) * w;
            let next = (r1 < height).then(|| u64::from(r1) * w);
            bands.push(Band {
                index: b,
                first,
                next,
                certain,
                rows: (r0, r1),
            });
        }
        let mut marks: Vec<(u64, Option<u64>)> = bands
            .iter()
            .flat_map(|b| [Some(b.first), b.next])
            .flatten()
            .map(|p| (p, None))
            .collect();
        marks.sort_unstable_by_key(|m| m.0);
        marks.dedup_by_key(|m| m.0);
        Self {
            cfg,
            width,
            height,
            warming,
            warm_rows_max: 0,
            bands_total: nb,
            start_offset,
            bands,
            segments: Vec::new(),
            next_band: 0,
            marks,
            next_mark: 0,
            warmed: 0,
            segment_band: 0,
        }
    }

    /// Plans the next segment and returns it (from, to), or `None` after the last one.
    /// `walking(j)` is the number of pixels of row `j` that walk ([`walking_in_row`]). The
    /// segment starts [`Warming`] rows before its first timed band (never before the previous
    /// segment's end) and ends after the warming tail of its last one; a timed band whose
    /// warming would reach back to the segment's end joins it.
    pub fn next_planned(
        &mut self,
        walking: &mut dyn FnMut(u32) -> Result<u64, CycleError>,
    ) -> Result<Option<(u64, u64)>, CycleError> {
        let Some(first) = self.bands.get(self.next_band).copied() else {
            return Ok(None);
        };
        let floor = self
            .segments
            .last()
            .map_or(0, |s| (s.1 / u64::from(self.width)) as u32);
        let from = self.warm_back(first.rows.0, floor, walking)?;
        let mut to = self.warm_forward(first.rows.1, walking)?;
        self.next_band += 1;
        while let Some(b) = self.bands.get(self.next_band).copied() {
            if self.warm_back(b.rows.0, to, walking)? > to {
                break;
            }
            to = to.max(self.warm_forward(b.rows.1, walking)?);
            self.next_band += 1;
        }
        let w = u64::from(self.width);
        let seg = (u64::from(from) * w, u64::from(to) * w);
        if let Some(last) = self.segments.last() {
            self.warmed += seg.0 - last.1;
        } else {
            self.warmed += seg.0;
        }
        self.segments.push(seg);
        self.segment_band = first.first;
        Ok(Some(seg))
    }

    /// The first row of the detailed warming before a band starting at row `r0`, not before
    /// row `floor`; records the rows used.
    fn warm_back(
        &mut self,
        r0: u32,
        floor: u32,
        walking: &mut dyn FnMut(u32) -> Result<u64, CycleError>,
    ) -> Result<u32, CycleError> {
        let wm = self.warming;
        let (mut j, mut held) = (r0, 0u64);
        while j > floor && (r0 - j < wm.min_rows || held < wm.walking) && r0 - j < wm.max_rows {
            j -= 1;
            held += walking(j)?;
        }
        self.warm_rows_max = self.warm_rows_max.max(r0 - j);
        Ok(j)
    }

    /// The end row of the warming tail after a band ending at row `r1`.
    fn warm_forward(
        &self,
        r1: u32,
        walking: &mut dyn FnMut(u32) -> Result<u64, CycleError>,
    ) -> Result<u32, CycleError> {
        let wm = self.warming;
        let (mut j, mut held) = (r1, 0u64);
        while j < self.height && (j - r1 < wm.min_rows || held < wm.walking) && j - r1 < wm.max_rows
        {
            held += walking(j)?;
            j += 1;
        }
        Ok(j)
    }

    /// First pixel of the first timed band of the segment ray generation is in.
    #[inline]
    pub fn segment_band(&self) -> u64 {
        self.segment_band
    }

    /// End of the segment ray generation is in.
    #[inline]
    pub fn segment_end(&self) -> u64 {
        self.segments.last().map_or(u64::MAX, |s| s.1)
    }

    /// After the edge ending cycle `now`, `written` pixels have been written: every mark
    /// reached is stamped `now + 1` (the cycle in which the count is first seen).
    #[inline]
    pub fn written(&mut self, written: u64, now: u64) {
        while let Some(m) = self.marks.get_mut(self.next_mark) {
            if m.0 > written {
                break;
            }
            m.1 = Some(now + 1);
            self.next_mark += 1;
        }
    }

    fn mark(&self, pixel: u64) -> Result<u64, CycleError> {
        self.marks
            .binary_search_by_key(&pixel, |m| m.0)
            .ok()
            .and_then(|i| self.marks[i].1)
            .ok_or_else(|| {
                CycleError::Internal(format!(
                    "sampled timing: the written count never reached {pixel} in a timed segment"
                ))
            })
    }

    /// The frame's estimate once it ended: `start` and `end` are its first and last cycles
    /// (the frame ends when its last pixel is written), `timed_cycles` the cycles simulated.
    pub fn finish(
        &self,
        start: u64,
        end: u64,
        clock_mhz: u32,
        pixels: u64,
        work: &[f64],
    ) -> Result<SampledCycles, CycleError> {
        let mut certain = 0.0f64;
        let mut ys = Vec::new();
        let mut xs = Vec::new();
        let mut band_cycles = Vec::with_capacity(self.bands.len());
        for b in &self.bands {
            let t0 = if b.index == 0 {
                start
            } else {
                self.mark(b.first)?
            };
            let t1 = match b.next {
                Some(n) => self.mark(n)?,
                None => end,
            };
            let y = t1.checked_sub(t0).ok_or_else(|| {
                internal(format!(
                    "sampled timing: band {} ends before it starts",
                    b.index
                ))
            })?;
            band_cycles.push([u64::from(b.index), y]);
            let y = y as f64;
            if b.certain {
                certain += y;
            } else {
                ys.push(y);
                xs.push(work.get(b.index as usize).copied().unwrap_or(0.0));
            }
        }
        // The auxiliary: a band's cycles as its work predicts them, z = max(P, x/θ) — the
        // front end's one pixel per cycle, or the walkers' work at θ work units per cycle,
        // θ from the sampled bands the walkers held back (y > 1.1·P).
        let nb = self.bands_total as usize;
        let p = f64::from(self.cfg.band_rows) * f64::from(self.width);
        let slow: (f64, f64) = xs
            .iter()
            .zip(&ys)
            .filter(|(_, &y)| y > 1.1 * p)
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
        let theta = if slow.1 > 0.0 {
            slow.0 / slow.1
        } else {
            xs.iter().sum::<f64>() / ys.iter().sum::<f64>().max(1.0)
        }
        .max(1e-9);
        let z = |x: f64| p.max(x / theta);
        let zs: Vec<f64> = xs.iter().map(|&x| z(x)).collect();
        let middle: Vec<f64> = (1..nb.saturating_sub(1))
            .map(|b| z(work.get(b).copied().unwrap_or(0.0)))
            .collect();
        let est = Estimate::regression(certain, &ys, &zs, &middle);
        Ok(SampledCycles {
            method: "systematic sample of row bands, first and last band always timed".into(),
            rate: 1.0 / f64::from(self.cfg.period.max(1)),
            period: self.cfg.period,
            band_rows: self.cfg.band_rows,
            warm_rows: self.warm_rows_max,
            warm_rows_min: self.warming.min_rows,
            warm_walking_rays: self.warming.walking,
            start_band: self.start_offset + 1,
            bands: self.bands_total,
            bands_timed: self.bands.len() as u32,
            pixels,
            pixels_timed: pixels - self.warmed,
            cycles_simulated: end - start,
            cycles_estimate: est.total,
            cycles_std_error: est.std_error,
            confidence: 0.95,
            degrees_of_freedom: est.df,
            cycles_low: est.low,
            cycles_high: est.high,
            fps_low: fps_at_clock(clock_mhz, 1.0, est.high),
            fps_high: fps_at_clock(clock_mhz, 1.0, est.low),
            band_cycles,
        })
    }
}

/// The frame's cycles as estimated from the sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Estimated cycles.
    pub total: f64,
    /// Its standard error.
    pub std_error: f64,
    /// Degrees of freedom of the t quantile (sampled bands − 1; 0 when no interval).
    pub df: u32,
    /// 95 % interval.
    pub low: f64,
    /// 95 % interval.
    pub high: f64,
}

impl Estimate {
    /// The estimate from the certain bands' cycles `certain` and the sampled bands'
    /// increments `ys` (in band order), sampled with period `k`:
    /// `T = certain + k·Σ y` (each band had probability 1/k: the Horvitz–Thompson estimator,
    /// unbiased over the random start), with the successive-difference variance of a
    /// systematic sample, `v = k²·n·(1 − 1/k)·Σ_{i≥2} (y_i − y_{i−1})² / (2(n − 1))`
    /// (Wolter, *Introduction to Variance Estimation*, 2nd ed., §8.2, estimator v₂), and
    /// `T ± t_{0.975, n−1}·√v`. With fewer than two sampled bands there is no interval
    /// (the bounds are the estimate).
    pub fn of(certain: f64, ys: &[f64], k: u32) -> Self {
        let kf = f64::from(k.max(1));
        let n = ys.len();
        let total = certain + kf * ys.iter().sum::<f64>();
        if n < 2 {
            return Self {
                total,
                std_error: 0.0,
                df: 0,
                low: total,
                high: total,
            };
        }
        let nf = n as f64;
        let sd2 = ys.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (2.0 * (nf - 1.0));
        let v = kf * kf * nf * (1.0 - 1.0 / kf) * sd2;
        Self::with_interval(total, v.sqrt(), n as u32 - 1)
    }

    /// `total ± t_{0.975, df}·se`.
    fn with_interval(total: f64, se: f64, df: u32) -> Self {
        let t = t_975(df);
        Self {
            total,
            std_error: se,
            df,
            low: total - t * se,
            high: total + t * se,
        }
    }
}

impl Estimate {
    /// The regression estimator on the functional model's work (docs/cycle-model.md §3.5):
    /// with `ys` the sampled bands' increments, `xs` their work and `population` the work of
    /// every middle band (known: the functional model ran them all), M = |population|,
    /// `T = certain + M·(ȳ + b·(X̄ − x̄))`, b the least-squares slope of y on x in the sample.
    /// Residuals eᵢ = yᵢ − ȳ − b(xᵢ − x̄); variance `M²·(1 − n/M)/n · s²`, s² the larger of
    /// Σeᵢ²/(n − 2) and the successive-difference Σ(eᵢ − eᵢ₋₁)²/(2(n − 1)) (the second keeps
    /// what a trend along the frame leaves in the residuals); `T ± t_{0.975, n−2}·√v`. Fewer
    /// than three sampled bands, or no spread in x: [`Estimate::of`]'s expansion estimator
    /// with period M/n.
    pub fn regression(certain: f64, ys: &[f64], xs: &[f64], population: &[f64]) -> Self {
        let n = ys.len();
        let m = population.len() as f64;
        let nf = n as f64;
        let mean = |v: &[f64]| v.iter().sum::<f64>() / (v.len().max(1) as f64);
        let (ym, xm) = (mean(ys), mean(xs));
        let sxx: f64 = xs.iter().map(|x| (x - xm).powi(2)).sum();
        if n < 3 || xs.len() != n || sxx <= 0.0 {
            let k = if n == 0 {
                1
            } else {
                (m / nf).round().max(1.0) as u32
            };
            return Self::of(certain, ys, k);
        }
        let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - xm) * (y - ym)).sum();
        let b = sxy / sxx;
        let total = certain + m * (ym + b * (mean(population) - xm));
        let e: Vec<f64> = xs
            .iter()
            .zip(ys)
            .map(|(x, y)| y - ym - b * (x - xm))
            .collect();
        let srs = e.iter().map(|r| r * r).sum::<f64>() / (nf - 2.0);
        let sd = e.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (2.0 * (nf - 1.0));
        let f = (nf / m).min(1.0);
        let v = m * m * (1.0 - f) / nf * srs.max(sd);
        Self::with_interval(total, v.sqrt(), n as u32 - 2)
    }
}

/// The work of each band of `band_rows` rows in the functional model's trace: per pixel that
/// walks, its walks' issue slots plus their node and attribute reads (what the walker pool
/// spends its cycles on), the auxiliary variable of [`Estimate::regression`].
pub fn band_work(rows: &[&crate::models::fixed::trace::RowTrace], band_rows: u32) -> Vec<f64> {
    let mut out = Vec::new();
    for band in rows.chunks(band_rows.max(1) as usize) {
        let mut w = 0u64;
        for r in band {
            for pw in &r.pixels {
                if pw.reused {
                    continue;
                }
                for tw in r.walks_of(pw) {
                    for &o in r.ops_of(tw) {
                        w += if o >> 32 == 0 { o & 0xffff_ffff } else { 1 };
                    }
                }
            }
        }
        out.push(w as f64);
    }
    out
}

/// The 0.975 quantile of Student's t with `df` degrees of freedom: tabulated to 30, then the
/// Cornish–Fisher expansion around the normal quantile (error below 1e-4 there).
pub fn t_975(df: u32) -> f64 {
    const T: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
        2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
        2.052, 2.048, 2.045, 2.042,
    ];
    match df {
        0 => f64::INFINITY,
        1..=30 => T[df as usize - 1],
        _ => {
            let z = 1.959_963_985_f64;
            let v = f64::from(df);
            z + (z.powi(3) + z) / (4.0 * v)
                + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * v * v)
        }
    }
}

/// The sample's description and estimate in a frame's report (`cycle.sampled`,
/// docs/report.md).
#[derive(Clone, Debug, Serialize)]
pub struct SampledCycles {
    /// How the sample was drawn.
    pub method: String,
    /// Sampling rate of the middle bands (1/period).
    pub rate: f64,
    /// One band in `period` timed.
    pub period: u32,
    /// Rows per band.
    pub band_rows: u32,
    /// The most rows run in detail before a timed band (its warming; the same after it).
    pub warm_rows: u32,
    /// Rows of warming at least.
    pub warm_rows_min: u32,
    /// Rays that walk the warming holds at least (0: `--sample-warm` fixed it in rows).
    pub warm_walking_rays: u64,
    /// The first sampled middle band (the systematic sample's start).
    pub start_band: u32,
    /// Bands in the frame.
    pub bands: u32,
    /// Bands timed (sampled ones and the first and last).
    pub bands_timed: u32,
    /// Pixels in the frame.
    pub pixels: u64,
    /// Pixels that went through the pipeline (timed bands and their warming).
    pub pixels_timed: u64,
    /// Cycles simulated (timed segments and their drains).
    pub cycles_simulated: u64,
    /// The frame's estimated cycles (the report's `cycles` is this, rounded).
    pub cycles_estimate: f64,
    /// Its standard error.
    pub cycles_std_error: f64,
    /// Confidence of the interval.
    pub confidence: f64,
    /// Degrees of freedom of its t quantile.
    pub degrees_of_freedom: u32,
    /// Interval of the cycles.
    pub cycles_low: f64,
    /// Interval of the cycles.
    pub cycles_high: f64,
    /// Interval of the frame rate at the clock.
    pub fps_low: f64,
    /// Interval of the frame rate at the clock.
    pub fps_high: f64,
    /// Every timed band as `[index, cycles]` (its increment y_b), in band order: the first,
    /// the sampled ones and the last.
    pub band_cycles: Vec<[u64; 2]>,
}

/// The sampled estimate of a whole run (the report's `summary.sampled`): frames are sampled
/// independently, so their cycles' variances add; the run's interval has half-width
/// √Σ hᵢ², hᵢ each frame's half-width (each frame's t quantile kept, which is conservative).
#[derive(Clone, Debug, Serialize)]
pub struct SampledSummary {
    /// How each frame was sampled.
    pub method: String,
    /// Estimated cycles over all frames.
    pub cycles_estimate: f64,
    /// 95 % interval.
    pub cycles_low: f64,
    /// 95 % interval.
    pub cycles_high: f64,
    /// Frames per second at the clock from the estimate.
    pub fps: f64,
    /// 95 % interval.
    pub fps_low: f64,
    /// 95 % interval.
    pub fps_high: f64,
}

impl SampledSummary {
    /// Of the sampled frames `frames` at `clock_mhz`, each with the cycles its frame reports
    /// (its estimate rounded, `CycleFrame::cycles`); `None` when no frame was sampled. The
    /// total is the sum of those reported cycles, so that the run's sampled line and its
    /// cycle summary print one figure (the same cycles, the same `fps_at_clock`).
    pub fn of(frames: &[(u64, &SampledCycles)], clock_mhz: u32) -> Option<Self> {
        let (_, first) = frames.first()?;
        let total = frames.iter().map(|(c, _)| *c as f64).sum::<f64>();
        let half = frames
            .iter()
            .map(|(_, f)| ((f.cycles_high - f.cycles_low) / 2.0).powi(2))
            .sum::<f64>()
            .sqrt();
        let n = frames.len() as f64;
        let (low, high) = (total - half, total + half);
        Some(Self {
            method: first.method.clone(),
            cycles_estimate: total,
            cycles_low: low,
            cycles_high: high,
            fps: fps_at_clock(clock_mhz, n, total),
            fps_low: fps_at_clock(clock_mhz, n, high),
            fps_high: fps_at_clock(clock_mhz, n, low),
        })
    }
}

#[cfg(test)]
mod tests;
