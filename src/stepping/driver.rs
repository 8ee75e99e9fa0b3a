//! The one driver: steps a [`Stepper`] until a goal is met, calling an
//! [`Observer`] after every increment (in the spirit of argmin's executor
//! and observers). `run`, `sweep`, `figure`, the memory runs of Fig. 4 and
//! the explorer's "to the steady state" all go through [`drive`], so the
//! loop "step until the steady state" exists once.

use super::options::StepError;
use super::outcome::Outcome;
use super::report::{Phase, StepReport};
use super::stepper::Stepper;

/// What an observer tells the driver after an increment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Go on stepping.
    Continue,
    /// Stop now (for example on Ctrl-C); [`drive`] returns
    /// [`Driven::Stopped`].
    Stop,
}

/// Where [`drive`] stops stepping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Goal {
    /// Until the run is classified ([`super::Status::Steady`]) or ends
    /// ([`super::Status::Ended`]).
    Steady,
    /// Until the initial transient is over (the stepper is in cycle 1) or
    /// the run ends.
    TransientEnd,
    /// Until the cycle in progress is complete or the run ends.
    CycleEnd,
    /// Until `n` more increments are done or the run ends.
    Increments(usize),
}

/// How [`drive`] came back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Driven {
    /// The run has its outcome: [`Goal::Steady`] was met, or the run ended
    /// (gross slip, separation) on the way to another goal.
    Finished(Outcome),
    /// Another goal was met; the run goes on.
    Reached,
    /// The observer asked to stop before the goal.
    Stopped,
}

impl Driven {
    /// The outcome, when the drive finished the run.
    pub fn outcome(self) -> Option<Outcome> {
        match self {
            Driven::Finished(outcome) => Some(outcome),
            Driven::Reached | Driven::Stopped => None,
        }
    }
}

/// Watches a run increment by increment. Closures
/// `FnMut(&Stepper, &StepReport) -> Control` are observers.
pub trait Observer {
    /// Called after every increment with the stepper as it is now and what
    /// the increment did (its events included).
    fn observe(&mut self, stepper: &Stepper, report: &StepReport) -> Control;
}

impl<F: FnMut(&Stepper, &StepReport) -> Control> Observer for F {
    fn observe(&mut self, stepper: &Stepper, report: &StepReport) -> Control {
        self(stepper, report)
    }
}

/// An observer that watches nothing and never stops the run.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Observer for Silent {
    fn observe(&mut self, _: &Stepper, _: &StepReport) -> Control {
        Control::Continue
    }
}

/// Step `stepper` until `goal` is met, the run ends, or `observer` says
/// stop; with [`Goal::Steady`] it comes back with the run's [`Outcome`]
/// ([`Driven::Finished`]) unless the observer stopped it.
///
/// # Errors
///
/// A numerical failure of an increment ([`StepError`]); the stepper is left
/// as it was before that increment.
///
/// # Example
///
/// ```
/// use shakedown::stepping::{drive, Control, Driven, Goal};
/// use shakedown::{Cycle, Discretisation, Initial, Material, StepOptions, Stepper};
///
/// let disc = Discretisation::new(32, 200).unwrap();
/// let cycle = Cycle::paper(3.0, 0.0).unwrap();
/// let mut stepper = Stepper::new(
///     Material::paper(), disc, &Initial::Direct, cycle, StepOptions::default(),
/// );
/// let mut increments = 0;
/// let how = drive(&mut stepper, Goal::Steady, &mut |_: &Stepper, _: &_| {
///     increments += 1;
///     Control::Continue
/// })
/// .unwrap();
/// let Driven::Finished(outcome) = how else { panic!("{how:?}") };
/// assert_eq!(outcome.state(), shakedown::SteadyState::Shakedown);
/// assert!(increments > 200);
/// ```
pub fn drive(
    stepper: &mut Stepper,
    goal: Goal,
    observer: &mut impl Observer,
) -> Result<Driven, StepError> {
    let start_cycles = stepper.history().len();
    let mut done = 0usize;
    // One report for the whole drive: its buffers are reused step to step.
    let mut report = StepReport::default();
    loop {
        if let Some(outcome) = stepper.outcome() {
            if goal == Goal::Steady || stepper.is_finished() {
                return Ok(Driven::Finished(*outcome));
            }
        }
        let reached = match goal {
            Goal::Steady => false,
            Goal::TransientEnd => matches!(stepper.phase(), Phase::Cycle { .. }),
            Goal::CycleEnd => stepper.history().len() > start_cycles,
            Goal::Increments(n) => done >= n,
        };
        if reached {
            return Ok(Driven::Reached);
        }
        stepper.step_into(&mut report)?;
        // A step that paused at an event inside its increment is not a
        // whole increment.
        done += usize::from(report.partial.is_none());
        if observer.observe(stepper, &report) == Control::Stop {
            return Ok(Driven::Stopped);
        }
    }
}
