//! `shakedown events`: every event of one run as a labelled CSV
//! ([`shakedown::io::events`]), for pandas and friends.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{anyhow, Result};
use clap::Args;
use shakedown::analysis::case::CaseParams;
use shakedown::analysis::episodes::{EpisodeTracker, ThetaRange};
use shakedown::io::csv::case_metadata;
use shakedown::io::events::{events_csv, EventKind, EventRow};
use shakedown::io::output::is_nonempty_file;
use shakedown::stepping::{Event, GrossSlip, Phase, Separation, Stepper, ZoneChange};

use super::batch::{lock_output, write_file};
use super::{CaseArgs, InputError};

/// The flags of `shakedown events`.
#[derive(Debug, Args)]
pub struct EventsArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// The CSV to write.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Replace FILE if it exists (without it, an existing file is refused).
    #[arg(long)]
    pub force: bool,
    /// Keep only events of this kind: advancing-stick, slip-start, zone-appeared, zone-split, zone-merged, zone-vanished, cycle-end, state, gross-slip or separation.
    #[arg(long, value_name = "K")]
    pub kind: Option<String>,
    /// Keep only events of at least M nodes.
    #[arg(long, value_name = "M", default_value_t = 0)]
    pub min_nodes: usize,
}

/// The cycle (0 in the transient) the stepper is in.
fn cycle_of(s: &Stepper) -> usize {
    match s.phase() {
        Phase::Transient { .. } => 0,
        Phase::Cycle { cycle, .. } => cycle,
    }
}

/// Every event of the run of `s` to its steady state (or its end), each
/// at its own instant: the stepper pauses at events, so the episode slip
/// an advancing stick locks in is exact.
pub fn collect(s: &mut Stepper) -> Result<Vec<EventRow>> {
    s.set_pause_at_events(true);
    s.set_zone_events(true);
    s.set_event_reports(true);
    let n = s.discretisation().nodes();
    let mut tracker = EpisodeTracker::new(s);
    let mut rows = Vec::new();
    let arc = |nodes: &[usize]| ThetaRange::of_nodes(nodes, n).map(|r| (r.from, r.to));
    while s.outcome().is_none() && !s.is_finished() {
        let cycle = cycle_of(s);
        let report = s.step()?;
        tracker.update(s.contact().slip(), s.contact().directions(), &report);
        let load = s.contact().load();
        let now = s.time();
        for e in &report.events {
            let base = EventRow {
                cycle,
                omega_t: now,
                x: load.x(),
                y: load.y(),
                kind: EventKind::State,
                nodes: 0,
                theta: None,
                locked_slip: None,
            };
            match e {
                Event::AdvancingStick {
                    nodes, time, load, ..
                } => {
                    let locked = tracker.locked_slip(e);
                    rows.push(EventRow {
                        omega_t: *time,
                        x: load.x(),
                        y: load.y(),
                        kind: EventKind::AdvancingStick,
                        nodes: nodes.len(),
                        theta: arc(nodes),
                        locked_slip: locked.map(|l| (l.max, l.mean)),
                        ..base
                    });
                }
                Event::SlipEntry { nodes, time, load } => rows.push(EventRow {
                    omega_t: *time,
                    x: load.x(),
                    y: load.y(),
                    kind: EventKind::SlipStart,
                    nodes: nodes.len(),
                    theta: arc(nodes),
                    ..base
                }),
                Event::SlipSetChanged {
                    slipping, changes, ..
                } => {
                    for c in changes {
                        let kind = match c {
                            ZoneChange::Appeared(_) => EventKind::ZoneAppeared,
                            ZoneChange::Split(_) => EventKind::ZoneSplit,
                            ZoneChange::Merged(_) => EventKind::ZoneMerged,
                            ZoneChange::Vanished(_) => EventKind::ZoneVanished,
                        };
                        rows.push(EventRow {
                            kind,
                            nodes: *slipping,
                            ..base.clone()
                        });
                    }
                }
                Event::CycleCompleted { cycle: c, .. } => rows.push(EventRow {
                    cycle: *c,
                    kind: EventKind::CycleEnd,
                    ..base
                }),
                Event::SteadyStateReached(_) => rows.push(EventRow { nodes: n, ..base }),
                Event::GrossSlip(GrossSlip { load, time }) => rows.push(EventRow {
                    omega_t: *time,
                    x: load.x(),
                    y: load.y(),
                    kind: EventKind::GrossSlip,
                    nodes: n,
                    ..base
                }),
                Event::Separation(Separation { load, time, .. }) => rows.push(EventRow {
                    omega_t: *time,
                    x: load.x(),
                    y: load.y(),
                    kind: EventKind::Separation,
                    ..base
                }),
                Event::TransientFinished => {}
            }
        }
    }
    Ok(rows)
}

/// Run `shakedown events`.
pub fn events(args: EventsArgs) -> Result<ExitCode> {
    let kind = match &args.kind {
        Some(k) => Some(
            k.parse::<EventKind>()
                .map_err(|e| anyhow!(InputError(format!("--kind {k}: {e}"))))?,
        ),
        None => None,
    };
    super::batch::refuse_input_as_output("--out", &args.out, &args.case.input_files())?;
    if is_nonempty_file(&args.out) && !args.force {
        return Err(anyhow!(InputError(format!(
            "--out {}: the file exists: add --force to replace it",
            args.out.display()
        ))));
    }
    let base = args.case.base(CaseParams::default())?;
    let (_, case) = args.case.case(base)?;
    let _lock = lock_output("--out", &args.out)?;
    let mut s = case.stepper();
    let rows: Vec<EventRow> = collect(&mut s)?
        .into_iter()
        .filter(|r| kind.is_none_or(|k| r.kind == k))
        .filter(|r| r.nodes >= args.min_nodes)
        .collect();
    let mut meta = case_metadata("events", &case, &case.initial().name());
    if let Some(k) = kind {
        meta.push("kind", k);
    }
    meta.push("min-nodes", args.min_nodes);
    write_file("--out", &args.out, events_csv(&meta, &rows).as_bytes())?;
    outln!("{} events written to {}", rows.len(), args.out.display());
    Ok(ExitCode::SUCCESS)
}
