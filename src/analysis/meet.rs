//! Runs that meet: a run of a sweep group that starts a cycle in the state
//! an earlier run of the group started the same cycle in takes that run's
//! later cycles instead of stepping them.
//!
//! The runs of a group share the load cycle, the material and the nodes;
//! they differ only by the slip their transients left. A cycle often
//! wipes that memory out: at `lambda = 5`, `phi = 0`, seven of the 25
//! transients start cycle 2 in one state (their `W` agree from cycle 2 on
//! to about `1e-11`, round-off), and in the Fig. 3 map a fifth of the runs
//! end on the very `W` of an earlier run of their group. What a cycle does
//! depends on the state at its start only: the slip `g` up to a rigid
//! rotation (`H` and `|D|` do not see the mean of `g`) and the slip set
//! (model.md section 3). So a run whose state at the start of cycle `k`
//! is that of an earlier run at the start of its cycle `k` does, from
//! there on, what that run did; its verdict is still decided on its own
//! history, after every cycle, by the stepper's own rules
//! ([`Stepper::replay_cycle`]).
//!
//! "The same state" is: the same slip set and directions, and slip that
//! differs, after each run's mean is taken off, by at most [`TOLERANCE`]
//! of its range at every node. Over the Fig. 3 map the nearest earlier
//! state of a run at a cycle start lies either 1e-14 to 1e-12 away (529
//! and 17 of them: runs that met, apart by round-off) or from 1e-11 up,
//! spread over every decade to 1e-1 (runs heading for one attractor
//! approach each other geometrically, and those are not taken to have
//! met until they are within round-off of each other). Round-off of this
//! size already separates a run's row in a sweep from the same run made
//! alone (the response cache, [`crate::contact::ResponseCache`]): the rows
//! of the runs that meet keep their states and cycle counts, and their `W`
//! move by at most 2e-12.

use crate::contact::{Contact, SlipDirection};
use crate::stepping::steady::CycleRecord;
use crate::stepping::Stepper;

/// Two states are one when their slips, each less its mean, differ by at
/// most this fraction of the slip's range at every node.
pub(crate) const TOLERANCE: f64 = 1e-12;

/// Bytes of traces one group keeps (past it, later runs are not kept).
/// Kept whole, the 25 runs of a `lambda` of the Fig. 3 map would take up
/// to 1.8 MB at `N = 128` (the median 0.5 MB); a run that took another's
/// cycles is not kept, and the map's rows are the same at 1 MB as at 2 MB.
const BUDGET: usize = 1 << 20;

/// Runs of more cycles than this are not kept: runs meet within their
/// first few cycles (in the Fig. 3 map at cycle 2 nearly always, at 6 at
/// the latest), and a run that takes hundreds of cycles to its verdict
/// (asymptotic shakedown, slow ratchetting) would crowd out the rest.
const LONGEST: usize = 64;

/// The state at the start of a cycle.
struct Start {
    /// `g`.
    slip: Vec<f64>,
    /// The mean of `g` (the rigid rotation).
    mean: f64,
    directions: Vec<SlipDirection>,
}

impl Start {
    fn of(contact: &Contact) -> Self {
        Self {
            slip: contact.slip().to_vec(),
            mean: contact.rotation(),
            directions: contact.directions().to_vec(),
        }
    }

    fn bytes(&self) -> usize {
        self.slip.len() * (std::mem::size_of::<f64>() + std::mem::size_of::<SlipDirection>())
    }

    /// Whether `other` is this state (see the module's documentation).
    fn is(&self, other: &Start) -> bool {
        if self.directions != other.directions {
            return false;
        }
        let (lo, hi) = self
            .slip
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &g| {
                (lo.min(g), hi.max(g))
            });
        let tol = TOLERANCE * (hi - lo);
        let worst = self
            .slip
            .iter()
            .zip(&other.slip)
            .map(|(a, b)| ((a - self.mean) - (b - other.mean)).abs())
            .fold(0.0, f64::max);
        worst <= tol
    }
}

/// What one run did, cycle by cycle: its state at the start of each cycle
/// (of cycle `j` at `starts[j - 1]`, the last one after its last cycle)
/// and its cycles.
#[derive(Default)]
pub(crate) struct Trace {
    starts: Vec<Start>,
    records: Vec<CycleRecord>,
}

impl Trace {
    /// Note the stepper's state if it is at the start of the next cycle
    /// not yet noted.
    pub(crate) fn note(&mut self, stepper: &Stepper) {
        if self.starts.len() <= LONGEST && stepper.cycle_start() == Some(self.starts.len() + 1) {
            self.starts.push(Start::of(stepper.contact()));
        }
    }

    /// Complete the trace with the run's cycles.
    pub(crate) fn finish(mut self, stepper: &Stepper) -> Self {
        self.records = stepper.history().to_vec();
        self
    }

    fn bytes(&self) -> usize {
        let nodes = self.starts.first().map_or(0, |s| s.slip.len());
        self.starts.iter().map(Start::bytes).sum::<usize>()
            + self.records.len() * nodes * 2 * std::mem::size_of::<f64>()
    }
}

/// Where a run met an earlier one: that run's trace and the difference of
/// the two rigid rotations at the meeting.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Meeting {
    trace: usize,
    cycle: usize,
    shift: f64,
}

/// The traces of a group's runs so far.
#[derive(Default)]
pub(crate) struct Meets {
    traces: Vec<Trace>,
    bytes: usize,
}

impl Meets {
    /// Keep a finished run's trace, within the budget.
    pub(crate) fn keep(&mut self, trace: Trace) {
        let bytes = trace.bytes();
        if trace.records.len() <= LONGEST && self.bytes + bytes <= BUDGET {
            self.bytes += bytes;
            self.traces.push(trace);
        }
    }

    /// An earlier run that started this stepper's present cycle in its
    /// present state and went on from there for at least that cycle.
    pub(crate) fn find(&self, stepper: &Stepper) -> Option<Meeting> {
        if self.traces.is_empty() {
            return None;
        }
        let cycle = stepper.cycle_start()?;
        let here = Start::of(stepper.contact());
        self.traces.iter().enumerate().find_map(|(i, t)| {
            let start = t.starts.get(cycle - 1)?;
            (t.starts.len() > cycle && t.records.len() >= cycle && start.is(&here)).then_some(
                Meeting {
                    trace: i,
                    cycle,
                    shift: here.mean - start.mean,
                },
            )
        })
    }

    /// The run `stepper` continued with the cycles of the run it met, to
    /// its verdict; `None` if that run's cycles ran out before one (it
    /// ended inside a cycle, or its own verdict came from cycles before
    /// the meeting): `stepper` must then be stepped on.
    pub(crate) fn replay(&self, meeting: Meeting, stepper: &Stepper) -> Option<Stepper> {
        let trace = &self.traces[meeting.trace];
        let mut run = stepper.clone();
        for cycle in meeting.cycle..=trace.records.len() {
            let end = trace.starts.get(cycle)?;
            if !run.replay_cycle(&trace.records[cycle - 1], &end.slip, meeting.shift) {
                return None;
            }
            if run.outcome().is_some() {
                return Some(run);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Cycle, Discretisation, Initial, Material};
    use crate::stepping::{drive, Control, Goal, Outcome, StepOptions, StepReport};

    fn stepper(initial: &Initial) -> Stepper {
        let disc = Discretisation::new(64, 200).unwrap();
        let cycle = Cycle::paper(5.0, 0.0).unwrap();
        let mut s = Stepper::new(
            Material::paper(),
            disc,
            initial,
            cycle,
            StepOptions::default(),
        );
        s.set_straight_runs(true);
        s
    }

    fn run_alone(initial: &Initial) -> Outcome {
        stepper(initial).run_to_steady().unwrap()
    }

    /// Two transients of `lambda = 5`, `phi = 0` that the first cycle
    /// brings to one state: the second meets the first at the start of
    /// cycle 2, and the cycles it takes give the verdict, cycle count and
    /// `W` that stepping it gives.
    #[test]
    fn a_run_that_meets_another_gets_the_verdict_stepping_gives() {
        let (first, second) = (Initial::Direct, Initial::Via { a: 7, b: 3 });
        let mut meets = Meets::default();
        let mut a = stepper(&first);
        let mut trace = Trace::default();
        trace.note(&a);
        drive(&mut a, Goal::Steady, &mut |s: &Stepper, _: &StepReport| {
            trace.note(s);
            Control::Continue
        })
        .unwrap();
        meets.keep(trace.finish(&a));

        let mut b = stepper(&second);
        let mut met = None;
        drive(&mut b, Goal::Steady, &mut |s: &Stepper, _: &StepReport| {
            met = meets.find(s);
            if met.is_some() {
                Control::Stop
            } else {
                Control::Continue
            }
        })
        .unwrap();
        let meeting = met.expect("the runs meet");
        assert_eq!(meeting.cycle, 2, "{meeting:?}");
        let replayed = meets.replay(meeting, &b).expect("to a verdict");
        let took = replayed.outcome().unwrap();
        let stepped = run_alone(&second);
        assert_eq!(took.state(), stepped.state());
        assert_eq!(took.approach(), stepped.approach());
        assert_eq!(took.cycles, stepped.cycles);
        assert!(stepped.dissipation > 0.0, "{stepped:?}");
        let dw = (took.dissipation - stepped.dissipation).abs() / stepped.dissipation;
        assert!(dw < 1e-10, "{took:?} against {stepped:?}");
        let dr = (took.rotation_per_cycle - stepped.rotation_per_cycle).abs();
        assert!(
            dr < 1e-10 * stepped.dissipation.max(1e-12),
            "{took:?} against {stepped:?}"
        );
        // The first run's own cycles from the meeting on are the ones taken.
        let own = run_alone(&first);
        assert_eq!(took.dissipation, own.dissipation);
    }

    fn start(slip: Vec<f64>, directions: Vec<SlipDirection>) -> Start {
        let mean = slip.iter().sum::<f64>() / slip.len() as f64;
        Start {
            slip,
            mean,
            directions,
        }
    }

    /// A rigid rotation and round-off leave a state the same; a slip
    /// change past round-off, or another slip set, do not.
    #[test]
    fn states_are_the_same_up_to_rotation_and_round_off_only() {
        let n = 32;
        let g: Vec<f64> = (0..n).map(|j| (j as f64 * 0.7).sin() * 1e-2).collect();
        let dirs: Vec<SlipDirection> = (0..n)
            .map(|j| {
                if j % 3 == 0 {
                    SlipDirection::Forward
                } else {
                    SlipDirection::Stick
                }
            })
            .collect();
        let here = start(g.clone(), dirs.clone());
        let rotated = start(g.iter().map(|x| x + 0.25).collect(), dirs.clone());
        assert!(here.is(&rotated));
        let mut rounded = g.clone();
        rounded[5] *= 1.0 + 1e-13;
        assert!(here.is(&start(rounded, dirs.clone())));
        let mut moved = g.clone();
        moved[5] += 1e-9 * 2e-2;
        assert!(!here.is(&start(moved, dirs.clone())));
        let mut other = dirs;
        other[1] = SlipDirection::Backward;
        assert!(!here.is(&start(g, other)));
    }
}
