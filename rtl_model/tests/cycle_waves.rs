//! Waveform recorder: a synthetic pipeline trace (two stages' valid/ready, the FIFO occupancy
//! between them, a walker's state and memory requests) is recorded, written, and read back with
//! the `vcd` crate's own parser; header, every value change, the window's start values, the
//! optional clock, determinism and the atomic write are checked against the trace itself.
//! Set `WAVES_SEED` to replay a failing run; the seed is printed.

use rtl_model::cycle::waves::{
    ScopeId, SignalId, Timebase, Waves, WavesError, Window, CLOCK_NAME, TOP_SCOPE,
};
use vcd::{Command, Header, IdCode, Parser, ReferenceIndex, ScopeItem, SimulationCommand, Value};

/// `rtl_model`'s splitmix64 (`rtl_model::vectors::rng::Rng`, not a copy: it only picks test
/// inputs) with the draws this test needs.
struct Rng(rtl_model::vectors::rng::Rng);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(rtl_model::vectors::rng::Rng::new(seed))
    }
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    /// True with probability `percent` / 100.
    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }
}

fn seed(test: &str) -> u64 {
    let s = std::env::var("WAVES_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0000_0000_0004);
    println!("{test}: WAVES_SEED={s}");
    s
}

/// Signals of the synthetic trace in declaration order: (scope, name, width).
const SIGNALS: [(&str, &str, u32); 8] = [
    ("sphere", "valid", 1),
    ("sphere", "ready", 1),
    ("sorter", "valid", 1),
    ("sorter", "ready", 1),
    ("sorter", "occupancy", 4),
    ("walker0", "state", 3),
    ("walker0", "mem_req", 1),
    ("walker0", "mem_addr", 32),
];
const FIFO_DEPTH: u64 = 8;

/// Per-cycle values of every signal of a small pipeline: the sphere stage offers items into a
/// FIFO of depth 8 (ready while not full), the sorter drains it under random backpressure, and
/// a walker cycles Idle → Fetch → Wait (random latency) → Step → Done with a memory request in
/// Fetch. The walker's address holds between requests, as a register would.
fn synthetic_trace(cycles: usize, seed: u64) -> Vec<[u64; 8]> {
    let mut rng = Rng::new(seed);
    let mut occupancy = 0u64;
    let (mut state, mut wait_left, mut addr) = (0u64, 0u32, 0u64);
    let mut trace = Vec::with_capacity(cycles);
    for _ in 0..cycles {
        let s_valid = rng.chance(70);
        let s_ready = occupancy < FIFO_DEPTH;
        let t_valid = occupancy > 0;
        let t_ready = rng.chance(60);
        let mem_req = state == 1;
        if mem_req {
            addr = (rng.next() & 0xFFFF_FFFC) >> (rng.next() % 20);
        }
        trace.push([
            u64::from(s_valid),
            u64::from(s_ready),
            u64::from(t_valid),
            u64::from(t_ready),
            occupancy,
            state,
            u64::from(mem_req),
            addr,
        ]);
        occupancy = occupancy + u64::from(s_valid && s_ready) - u64::from(t_valid && t_ready);
        state = match state {
            0 if rng.chance(50) => 1,
            1 => {
                wait_left = 1 + (rng.next() % 12) as u32;
                2
            }
            2 if wait_left > 1 => {
                wait_left -= 1;
                2
            }
            2 => 3,
            3 if rng.chance(30) => 1,
            3 => 4,
            4 => 0,
            s => s,
        };
    }
    trace
}

fn declare(waves: &mut Waves) -> Vec<SignalId> {
    let mut scopes: Vec<(&str, ScopeId)> = Vec::new();
    SIGNALS
        .iter()
        .map(|&(scope, name, width)| {
            let id = match scopes.iter().find(|(n, _)| *n == scope) {
                Some(&(_, id)) => id,
                None => {
                    let id = waves.scope(scope).unwrap();
                    scopes.push((scope, id));
                    id
                }
            };
            waves.signal(id, name, width).unwrap()
        })
        .collect()
}

/// Records `trace`, setting every signal every cycle (`dense`) or only on change.
fn record(trace: &[[u64; 8]], window: Window, clock: bool, dense: bool) -> Waves {
    let mut waves = Waves::new(Timebase::from_clock_mhz(300.0).unwrap(), window).with_clock(clock);
    let ids = declare(&mut waves);
    for (cycle, values) in trace.iter().enumerate() {
        for (s, (&id, &v)) in ids.iter().zip(values).enumerate() {
            if dense || cycle == 0 || trace[cycle - 1][s] != v {
                waves.set(id, cycle as u64, v).unwrap();
            }
        }
    }
    waves.advance_to(trace.len() as u64 - 1);
    waves
}

fn to_bytes(waves: &Waves) -> Vec<u8> {
    let mut out = Vec::new();
    waves.write_to(&mut out).unwrap();
    out
}

/// `$dumpvars` values: (code, value), `None` for `x`.
type Dump = Vec<(IdCode, Option<u64>)>;
/// Value changes: (time, code, value), `None` for `x`.
type Changes = Vec<(u64, IdCode, Option<u64>)>;

/// A file read back with the `vcd` crate's parser.
struct ReadBack {
    header: Header,
    /// Time of the `$dumpvars` block and its values in file order.
    dump_time: u64,
    dump: Dump,
    /// Every later change: (time, code, value), in file order.
    changes: Changes,
    /// Every timestamp in file order.
    times: Vec<u64>,
}

fn decode(v: &vcd::Vector) -> Option<u64> {
    if v.iter().any(|b| b == Value::X) {
        assert_eq!(v.len(), 1, "x is written as a single extended bit");
        return None;
    }
    assert!(v.len() <= 64 && v.len() >= 1);
    Some(
        v.iter()
            .fold(0, |acc, b| acc << 1 | u64::from(b == Value::V1)),
    )
}

fn scalar(v: Value) -> Option<u64> {
    match v {
        Value::V0 => Some(0),
        Value::V1 => Some(1),
        Value::X => None,
        Value::Z => panic!("recorder never writes z"),
    }
}

fn read_back(bytes: &[u8]) -> ReadBack {
    let mut parser = Parser::new(bytes);
    let header = parser.parse_header().unwrap();
    let (mut time, mut dump_time) = (None, None);
    let (mut in_dump, mut dump, mut changes, mut times) = (false, vec![], vec![], vec![]);
    for command in parser {
        let (code, value) = match command.unwrap() {
            Command::Timestamp(t) => {
                time = Some(t);
                times.push(t);
                continue;
            }
            Command::Begin(SimulationCommand::Dumpvars) => {
                assert!(dump_time.is_none(), "one $dumpvars block");
                in_dump = true;
                dump_time = time;
                continue;
            }
            Command::End(SimulationCommand::Dumpvars) => {
                in_dump = false;
                continue;
            }
            Command::ChangeScalar(code, v) => (code, scalar(v)),
            Command::ChangeVector(code, v) => (code, decode(&v)),
            other => panic!("unexpected command {other:?}"),
        };
        if in_dump {
            dump.push((code, value));
        } else {
            assert!(dump_time.is_some(), "changes follow $dumpvars");
            changes.push((time.unwrap(), code, value));
        }
    }
    assert!(times.windows(2).all(|w| w[0] < w[1]), "timestamps increase");
    ReadBack {
        header,
        dump_time: dump_time.unwrap(),
        dump,
        changes,
        times,
    }
}

/// What the file must hold for `trace` in `[from, to]`: start values, then the changes
/// (by cycle, then declaration order) as (time, code, value), then the end time.
fn expected(trace: &[[u64; 8]], from: u64, to: u64, period: u64) -> (Dump, Changes, u64) {
    let last = (trace.len() as u64 - 1).min(to);
    let dump = (0..8)
        .map(|s| (IdCode::from(s as u64), Some(trace[from as usize][s])))
        .collect();
    let mut changes = Vec::new();
    for c in from + 1..=last {
        let (before, after) = (&trace[c as usize - 1], &trace[c as usize]);
        for (s, (prev, now)) in before.iter().zip(after).enumerate() {
            if prev != now {
                changes.push((c * period, IdCode::from(s as u64), Some(*now)));
            }
        }
    }
    (dump, changes, (last + 1) * period)
}

fn check_header(header: &Header, clock: bool) {
    assert_eq!(header.timescale, Some((1, vcd::TimescaleUnit::PS)));
    let top = header.find_scope(&[TOP_SCOPE]).expect("top scope");
    let mut scopes = 0;
    let mut comment = None;
    for item in &header.items {
        match item {
            ScopeItem::Scope(_) => scopes += 1,
            ScopeItem::Comment(c) => comment = Some(c.as_str()),
            other => panic!("unexpected top-level item {other:?}"),
        }
    }
    assert_eq!(scopes, 1, "one top scope");
    assert!(
        comment.is_some_and(|c| c.contains("cycle = time / ")),
        "time base documented"
    );
    let scope_names: Vec<&str> = top
        .items
        .iter()
        .filter_map(|i| match i {
            ScopeItem::Scope(s) => Some(s.identifier.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(scope_names, ["sphere", "sorter", "walker0"]);
    let clk = top.find_var(CLOCK_NAME);
    assert_eq!(clk.is_some(), clock);
    if let Some(clk) = clk {
        assert_eq!((clk.size, clk.code), (1, IdCode::from(8u64)));
    }
    for (i, &(scope, name, width)) in SIGNALS.iter().enumerate() {
        let var = header
            .find_var(&[TOP_SCOPE, scope, name])
            .unwrap_or_else(|| panic!("{scope}.{name} declared"));
        assert_eq!(var.size, width, "{scope}.{name} width");
        assert_eq!(var.code, IdCode::from(i as u64), "{scope}.{name} code");
        let index = (width > 1).then(|| ReferenceIndex::Range(width as i32 - 1, 0));
        assert_eq!(var.index, index, "{scope}.{name} index");
    }
}

#[test]
fn round_trip_every_change() {
    let trace = synthetic_trace(400, seed("round_trip_every_change"));
    let waves = record(&trace, Window::all(), false, true);
    let period = waves.timebase().period_ps();
    assert_eq!(period, 3334, "300 MHz rounds to an even 3334 ps");
    let back = read_back(&to_bytes(&waves));
    check_header(&back.header, false);

    let (dump, changes, end_time) = expected(&trace, 0, u64::MAX, period);
    assert_eq!(back.dump_time, 0);
    assert_eq!(back.dump, dump);
    assert_eq!(back.changes, changes);
    assert_eq!(waves.change_count(), changes.len());
    assert_eq!(back.times.last(), Some(&end_time));
    assert!(changes.len() > 400, "trace exercises the signals");
    // Every state and a spread of addresses appear, so multi-bit values are really checked.
    for state in 0..5 {
        assert!(
            trace.iter().any(|v| v[5] == state),
            "walker state {state} seen"
        );
    }
}

#[test]
fn window_keeps_start_values_and_drops_the_rest() {
    let trace = synthetic_trace(400, seed("window_keeps_start_values"));
    let (from, to) = (120, 260);
    let waves = record(&trace, Window::cycles(from, to).unwrap(), false, false);
    let period = waves.timebase().period_ps();
    let back = read_back(&to_bytes(&waves));
    check_header(&back.header, false);

    let (dump, changes, end_time) = expected(&trace, from, to, period);
    assert_eq!(
        back.dump_time,
        from * period,
        "$dumpvars at the window start"
    );
    assert_eq!(back.dump, dump, "values in force at the window start");
    assert_eq!(back.changes, changes);
    assert_eq!(back.times.first(), Some(&(from * period)));
    assert_eq!(back.times.last(), Some(&end_time));
    assert_eq!(end_time, (to + 1) * period);
    assert!(back
        .changes
        .iter()
        .all(|&(t, _, _)| t > from * period && t <= to * period));

    // A window reaching past the run ends at the last cycle reached.
    let waves = record(&trace, Window::cycles(350, 10_000).unwrap(), false, true);
    let back = read_back(&to_bytes(&waves));
    let (dump, changes, end_time) = expected(&trace, 350, 10_000, period);
    assert_eq!((back.dump, back.changes), (dump, changes));
    assert_eq!(back.times.last(), Some(&end_time));
    assert_eq!(end_time, 400 * period);
}

#[test]
fn unset_signals_start_as_x_and_old_values_carry_into_the_window() {
    let mut waves = Waves::new(
        Timebase::from_period_ps(4000).unwrap(),
        Window::cycles(100, 200).unwrap(),
    );
    let cfg = waves.scope("config").unwrap();
    let mode = waves.signal(cfg, "mode", 2).unwrap();
    let late = waves.signal(cfg, "late", 1).unwrap();
    let never = waves.signal(cfg, "never", 16).unwrap();
    waves.set(mode, 0, 1u8).unwrap();
    waves.set(mode, 40, 3u8).unwrap(); // before the window: only the start value changes
    waves.set(late, 150, true).unwrap();
    waves.set(mode, 300, 0u8).unwrap(); // after the window: dropped
    let back = read_back(&to_bytes(&waves));
    assert_eq!(back.dump_time, 100 * 4000);
    assert_eq!(
        back.dump,
        [
            (IdCode::from(0u64), Some(3)),
            (IdCode::from(1u64), None),
            (IdCode::from(2u64), None)
        ]
    );
    assert_eq!(back.changes, [(150 * 4000, IdCode::from(1u64), Some(1))]);
    assert_eq!(back.times.last(), Some(&(201 * 4000)));
    let _ = never;
}

#[test]
fn clock_toggles_each_cycle_without_moving_other_changes() {
    let trace = synthetic_trace(300, seed("clock_toggles"));
    let (from, to) = (50, 120);
    let window = Window::cycles(from, to).unwrap();
    let plain = read_back(&to_bytes(&record(&trace, window, false, true)));
    let clocked_waves = record(&trace, window, true, true);
    let period = clocked_waves.timebase().period_ps();
    let half = period / 2;
    let clocked = read_back(&to_bytes(&clocked_waves));
    check_header(&clocked.header, true);

    let clk = IdCode::from(8u64);
    assert_eq!(
        clocked.dump.first(),
        Some(&(clk, Some(1))),
        "clk high at start"
    );
    assert_eq!(&clocked.dump[1..], &plain.dump[..]);
    let (edges, others): (Vec<_>, Vec<_>) = clocked.changes.iter().partition(|c| c.1 == clk);
    let others: Vec<_> = others.into_iter().copied().collect();
    assert_eq!(others, plain.changes);
    let mut want = vec![(from * period + half, clk, Some(0))];
    for c in from + 1..=to {
        want.push((c * period, clk, Some(1)));
        want.push((c * period + half, clk, Some(0)));
    }
    let edges: Vec<_> = edges.into_iter().copied().collect();
    assert_eq!(edges, want, "two edges per cycle");
    assert_eq!(clocked.times.last(), Some(&((to + 1) * period)));
}

#[test]
fn output_is_deterministic() {
    let trace = synthetic_trace(500, seed("output_is_deterministic"));
    for clock in [false, true] {
        let a = record(&trace, Window::all(), clock, true);
        let b = record(&trace, Window::all(), clock, true);
        let sparse = record(&trace, Window::all(), clock, false);
        let bytes = to_bytes(&a);
        assert_eq!(bytes, to_bytes(&b), "two recorders, same bytes");
        assert_eq!(bytes, to_bytes(&a), "two writes, same bytes");
        assert_eq!(bytes, to_bytes(&sparse), "repeated values record nothing");
    }
}

#[test]
fn same_cycle_sets_keep_the_last_value() {
    let mut waves = Waves::new(Timebase::from_period_ps(2).unwrap(), Window::all());
    let s = waves.scope("s").unwrap();
    let v = waves.signal(s, "v", 8).unwrap();
    waves.set(v, 0, 5u8).unwrap();
    waves.set(v, 3, 9u8).unwrap();
    waves.set(v, 3, 5u8).unwrap(); // back to the value in force: no change at 3
    waves.set(v, 4, 7u8).unwrap();
    waves.set(v, 4, 6u8).unwrap(); // replaces 7
    waves.set(v, 4, 6u8).unwrap();
    assert_eq!(waves.change_count(), 1);
    let back = read_back(&to_bytes(&waves));
    assert_eq!(back.dump, [(IdCode::from(0u64), Some(5))]);
    assert_eq!(back.changes, [(8, IdCode::from(0u64), Some(6))]);
}

#[test]
fn bad_declarations_and_values_are_errors() {
    let mut waves = Waves::new(Timebase::from_clock_mhz(100.0).unwrap(), Window::all());
    let s = waves.scope("stage").unwrap();
    assert!(matches!(
        waves.scope("stage"),
        Err(WavesError::DuplicateName(_))
    ));
    assert!(matches!(
        waves.signal(ScopeId::TOP, CLOCK_NAME, 1),
        Err(WavesError::DuplicateName(_))
    ));
    for bad in ["", "two words", "$var", "tab\there"] {
        assert!(matches!(
            waves.signal(s, bad, 1),
            Err(WavesError::InvalidName(_))
        ));
    }
    assert!(matches!(
        waves.signal(s, "w", 0),
        Err(WavesError::InvalidWidth(0))
    ));
    assert!(matches!(
        waves.signal(s, "w", 65),
        Err(WavesError::InvalidWidth(65))
    ));
    let v = waves.signal(s, "v", 3).unwrap();
    assert!(matches!(
        waves.signal(s, "v", 3),
        Err(WavesError::DuplicateName(_))
    ));
    let wide = waves.signal(s, "wide", 64).unwrap();
    waves.set(wide, 0, u64::MAX).unwrap();
    assert!(matches!(
        waves.set(v, 0, 8u8),
        Err(WavesError::ValueTooWide { .. })
    ));
    waves.set(v, 10, 7u8).unwrap();
    assert!(matches!(
        waves.set(v, 9, 1u8),
        Err(WavesError::TimeWentBack { .. })
    ));
    assert!(Window::cycles(5, 4).is_err());
    assert_eq!(Timebase::from_clock_mhz(250.0).unwrap().period_ps(), 4000);
    assert_eq!(Timebase::from_clock_mhz(100.0).unwrap().period_ps(), 10_000);
    for mhz in [0.0, -1.0, f64::NAN, f64::INFINITY, 2.0e6] {
        assert!(Timebase::from_clock_mhz(mhz).is_err(), "{mhz} MHz");
    }
    assert!(Timebase::from_period_ps(3333).is_err());
    assert!(Timebase::from_period_ps(0).is_err());

    // A 64-bit value round-trips.
    let back = read_back(&to_bytes(&waves));
    assert_eq!(back.dump[1], (IdCode::from(1u64), Some(u64::MAX)));
}

/// File sizes of a typical trace: 4 stages (valid, ready, 4-bit occupancy) and 8 walkers
/// (3-bit state, request, 32-bit address) over 20 000 cycles, with the activity of a busy
/// pipeline: handshakes toggle often, occupancies move by one, a walker changes state every few
/// cycles and fetches a node in one cycle of four. Run with `--nocapture` to see the sizes; the
/// bounds only catch a format that grew by accident.
#[test]
fn typical_trace_size() {
    let cycles = 20_000u64;
    let run_seed = seed("typical_trace_size");
    let mut sizes = Vec::new();
    for clock in [false, true] {
        let mut rng = Rng::new(run_seed);
        let mut waves =
            Waves::new(Timebase::from_clock_mhz(300.0).unwrap(), Window::all()).with_clock(clock);
        let mut stages = Vec::new();
        for name in ["transform", "sphere", "sorter", "dispatch"] {
            let s = waves.scope(name).unwrap();
            let ids = [
                waves.signal(s, "valid", 1).unwrap(),
                waves.signal(s, "ready", 1).unwrap(),
                waves.signal(s, "occupancy", 4).unwrap(),
            ];
            stages.push((ids, 0u64));
        }
        let walkers_scope = waves.scope("walkers").unwrap();
        let mut walkers = Vec::new();
        for w in 0..8 {
            let s = waves
                .subscope(walkers_scope, &format!("walker{w}"))
                .unwrap();
            let ids = [
                waves.signal(s, "state", 3).unwrap(),
                waves.signal(s, "mem_req", 1).unwrap(),
                waves.signal(s, "mem_addr", 32).unwrap(),
            ];
            walkers.push((ids, 0u64));
        }
        for c in 0..cycles {
            for ([valid, ready, occ], level) in &mut stages {
                waves.set(*valid, c, rng.chance(80)).unwrap();
                waves.set(*ready, c, rng.chance(90)).unwrap();
                match rng.next() % 4 {
                    0 if *level < 8 => *level += 1,
                    1 if *level > 0 => *level -= 1,
                    _ => {}
                }
                waves.set(*occ, c, *level).unwrap();
            }
            for ([state, req, addr], st) in &mut walkers {
                if rng.chance(30) {
                    *st = rng.next() % 5;
                }
                let fetch = rng.chance(25);
                waves.set(*state, c, *st).unwrap();
                waves.set(*req, c, fetch).unwrap();
                if fetch {
                    waves.set(*addr, c, rng.next() & 0x00FF_FFFC).unwrap();
                }
            }
        }
        let bytes = to_bytes(&waves);
        println!(
            "typical trace, {cycles} cycles, 36 signals, clock {}: {} changes, {} bytes \
             ({:.1} bytes/cycle, {:.1} bytes/change)",
            if clock { "on" } else { "off" },
            waves.change_count(),
            bytes.len(),
            bytes.len() as f64 / cycles as f64,
            bytes.len() as f64 / waves.change_count() as f64,
        );
        assert!(bytes.len() < 12 * waves.change_count() + 30 * cycles as usize);
        sizes.push((waves.change_count(), bytes.len()));
    }
    assert_eq!(sizes[0].0, sizes[1].0, "the clock is not a stored change");
    assert!(sizes[1].1 > sizes[0].1);
}
