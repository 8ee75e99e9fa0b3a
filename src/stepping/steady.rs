//! Steady state: convergence of the cycle dissipation and classification
//! (model.md section 6).

use serde::Serialize;

use super::outcome::Level;
use super::verdict::level;
use crate::model::{ranges, ParamError};

/// The steady state a run reaches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, PartialOrd, Ord)]
#[serde(rename_all = "kebab-case")]
pub enum SteadyState {
    /// No slip anywhere during the steady cycle.
    Shakedown,
    /// Slip occurs, but some nodes never slip during the cycle.
    CyclicSlip,
    /// Every node slips and no node slips against the net rotation.
    RatchettingMonotonic,
    /// Every node slips, and some slip back and forth within the cycle.
    RatchettingNonMonotonic,
    /// The whole interface slides at some instant.
    GrossSlip,
    /// The pressure became negative somewhere.
    Separation,
    /// The cycle cap was reached before the dissipation settled.
    NotConverged,
}

impl SteadyState {
    /// Every state, in the order of model.md section 6.2 (the order of
    /// tables and legends); parsing with `FromStr` searches it by
    /// [`SteadyState::as_str`].
    pub const ALL: [SteadyState; 7] = [
        SteadyState::Shakedown,
        SteadyState::CyclicSlip,
        SteadyState::RatchettingMonotonic,
        SteadyState::RatchettingNonMonotonic,
        SteadyState::GrossSlip,
        SteadyState::Separation,
        SteadyState::NotConverged,
    ];

    /// The word used in tables, JSON and the TUI.
    pub fn as_str(self) -> &'static str {
        match self {
            SteadyState::Shakedown => "shakedown",
            SteadyState::CyclicSlip => "cyclic-slip",
            SteadyState::RatchettingMonotonic => "ratchetting-monotonic",
            SteadyState::RatchettingNonMonotonic => "ratchetting-non-monotonic",
            SteadyState::GrossSlip => "gross-slip",
            SteadyState::Separation => "separation",
            SteadyState::NotConverged => "not-converged",
        }
    }

    /// Whether the state is ratchetting, monotonic or non-monotonic
    /// (model.md section 6.2): every node slips each cycle and the disc turns
    /// by a net `rotation_per_cycle`.
    pub fn is_ratchetting(self) -> bool {
        matches!(
            self,
            SteadyState::RatchettingMonotonic | SteadyState::RatchettingNonMonotonic
        )
    }
}

impl std::fmt::Display for SteadyState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::str::FromStr for SteadyState {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        SteadyState::ALL
            .into_iter()
            .find(|v| v.as_str() == s)
            .ok_or_else(|| format!("unknown state '{s}'"))
    }
}

/// What one complete cycle did at each node.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CycleRecord {
    /// 1-based cycle number.
    pub cycle: usize,
    /// `W` of this cycle (model.md section 4).
    pub dissipation: f64,
    /// Change of the rigid rotation `mean g` over the cycle.
    pub rotation: f64,
    /// Total positive slip at each node.
    #[serde(skip)]
    pub forward: Vec<f64>,
    /// Total negative slip at each node (as a positive number).
    #[serde(skip)]
    pub backward: Vec<f64>,
}

impl CycleRecord {
    /// An empty record for cycle `cycle` (1-based) on `nodes` nodes: no
    /// dissipation `W`, no rotation, no slip yet.
    pub fn new(cycle: usize, nodes: usize) -> Self {
        Self {
            cycle,
            dissipation: 0.0,
            rotation: 0.0,
            forward: vec![0.0; nodes],
            backward: vec![0.0; nodes],
        }
    }

    /// Whether anything slipped during the cycle: positive dissipation `W`
    /// or any nodal slip `|dg| > 0`. A cycle that did not slip is
    /// shakedown (model.md section 6.1).
    pub fn slipped(&self) -> bool {
        self.dissipation > 0.0
            || self.forward.iter().any(|&v| v > 0.0)
            || self.backward.iter().any(|&v| v > 0.0)
    }

    /// The largest slip any node accumulated in the cycle (forward plus
    /// backward): the scale for "did it slip".
    pub fn largest_slip(&self) -> f64 {
        self.forward
            .iter()
            .zip(&self.backward)
            .map(|(f, b)| f + b)
            .fold(0.0, f64::max)
    }

    /// Nodes that slipped during the cycle, counting only slip above a small
    /// fraction of the largest, so that round-off does not count as slip.
    pub fn slipping_nodes(&self) -> Vec<bool> {
        let tol = SLIP_FRACTION * self.largest_slip();
        self.forward
            .iter()
            .zip(&self.backward)
            .map(|(f, b)| f + b > tol)
            .collect()
    }

    /// Classify a cycle that slipped (model.md section 6).
    pub fn classify(&self) -> SteadyState {
        if !self.slipped() {
            return SteadyState::Shakedown;
        }
        if !self.slipping_nodes().iter().all(|&s| s) {
            return SteadyState::CyclicSlip;
        }
        let tol = SLIP_FRACTION * self.largest_slip();
        let against = if self.rotation >= 0.0 {
            &self.backward
        } else {
            &self.forward
        };
        if against.iter().any(|&v| v > tol) {
            SteadyState::RatchettingNonMonotonic
        } else {
            SteadyState::RatchettingMonotonic
        }
    }
}

/// Slip below this fraction of the cycle's largest nodal slip is round-off.
const SLIP_FRACTION: f64 = 1e-6;

/// Criteria for the steady state (model.md section 6), validated by
/// [`Convergence::new`] (or [`crate::stepping::StepOptions::builder`]).
///
/// ```
/// use shakedown::stepping::steady::Convergence;
///
/// let c = Convergence::new(1e-4, 300, true)?;
/// assert_eq!((c.tolerance(), c.max_cycles(), c.safe_state()), (1e-4, 300, true));
/// assert_eq!(Convergence::default().max_cycles(), 2000);
/// // A cap of no cycle, or a tolerance that accepts any change, is refused.
/// assert!(Convergence::new(1e-4, 0, true).is_err());
/// assert!(Convergence::new(1.0, 300, true).is_err());
/// # Ok::<(), shakedown::model::ParamError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Convergence {
    tolerance: f64,
    max_cycles: usize,
    safe_state: bool,
}

impl Convergence {
    /// The criteria: `tolerance` on the relative change of `W`, at most
    /// `max_cycles` cycles, and whether to look for a safe state.
    ///
    /// # Errors
    ///
    /// [`ParamError`] unless `tolerance` is in [`ranges::TOLERANCE`] and
    /// `max_cycles` in [`ranges::MAX_CYCLES`].
    pub fn new(tolerance: f64, max_cycles: usize, safe_state: bool) -> Result<Self, ParamError> {
        Ok(Self {
            tolerance: ranges::TOLERANCE.check(tolerance)?,
            max_cycles: ranges::MAX_CYCLES.check(max_cycles)?,
            safe_state,
        })
    }
    /// `|W_k - W_(k-1)| <= tolerance W_(k-1)`: the paper's 0.01 % is `1e-4`.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }
    /// Give up after this many cycles: the run is then `not-converged`.
    /// There is no other way out: no verdict is drawn from a trend.
    pub fn max_cycles(&self) -> usize {
        self.max_cycles
    }
    /// Look for a safe state that proves shakedown before the first cycle
    /// without slip (model.md section 6.4). Off, a run that shakes down
    /// asymptotically is run out to its first cycle without slip.
    pub fn safe_state(&self) -> bool {
        self.safe_state
    }
    /// The same criteria with the safe-state search on or off (which
    /// carries no invariant).
    pub fn with_safe_state(self, on: bool) -> Self {
        Self {
            safe_state: on,
            ..self
        }
    }
}

/// The default cycle cap: boundary runs that shake down asymptotically
/// need up to about 1900 cycles to reach a cycle without slip (`fig6`:
/// `phi = 17 pi/48`, path `7,-5`, 1906 cycles) when run out; a safe state
/// (model.md section 6.4) usually proves them after tens. Only runs that
/// never settle pay for the cap.
pub const DEFAULT_MAX_CYCLES: usize = 2000;

/// The paper's 0.01 % rule on the cycle dissipation `W`.
pub const DEFAULT_TOLERANCE: f64 = 1e-4;

impl Default for Convergence {
    fn default() -> Self {
        Self {
            tolerance: DEFAULT_TOLERANCE,
            max_cycles: DEFAULT_MAX_CYCLES,
            safe_state: true,
        }
    }
}

/// How the verdict was reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Approach {
    /// A whole cycle without slip: shakedown, proven (the state at the start
    /// of the next cycle is the same, so no cycle ever slips again).
    NoSlipCycle,
    /// `W` changed by at most the tolerance over [`SETTLE_CYCLES`]
    /// successive cycles, all classified alike: the paper's 0.01 % rule.
    Converged,
    /// A safe state close enough to the slip reached that all slip still to
    /// come is bounded: shakedown, proven before the first cycle without
    /// slip (model.md section 6.4).
    SafeState,
    /// Gross slip or separation ended the run.
    Terminal,
    /// The cycle cap was reached without a verdict: `not-converged`.
    Cap,
}

impl Approach {
    /// Every approach, in the order of model.md section 6.3.
    pub const ALL: [Approach; 5] = [
        Approach::Terminal,
        Approach::NoSlipCycle,
        Approach::SafeState,
        Approach::Converged,
        Approach::Cap,
    ];

    /// The word used in JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Approach::NoSlipCycle => "no-slip-cycle",
            Approach::Converged => "converged",
            Approach::SafeState => "safe-state",
            Approach::Terminal => "terminal",
            Approach::Cap => "cap",
        }
    }
}

impl std::fmt::Display for Approach {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The 0.01 % rule must hold over this many successive cycle pairs (a
/// single pair can agree by chance where `W` turns, at a minimum).
pub const SETTLE_CYCLES: usize = 3;

/// The verdict after a cycle, if the run has one. At the cap the verdict
/// is `not-converged` (see [`Trend`](super::verdict::Trend) for what is known then).
pub fn assess(history: &[CycleRecord], criteria: &Convergence) -> Option<(SteadyState, Approach)> {
    let last = history.last()?;
    if !last.slipped() {
        return Some((SteadyState::Shakedown, Approach::NoSlipCycle));
    }
    if let Some(state) = settled(history, criteria.tolerance()) {
        return Some((state, Approach::Converged));
    }
    if history.len() >= criteria.max_cycles() {
        return Some((SteadyState::NotConverged, Approach::Cap));
    }
    None
}

/// How many times the 0.01 % tolerance the bound on the level of `W` may
/// be for the run to have settled: `4e-4` at the paper's tolerance, so that
/// the level reported is within 0.05 % of the level run out.
pub const LEVEL_BOUND: f64 = 4.0;

/// The state of a run whose `W` has settled: the last [`SETTLE_CYCLES`]
/// relative changes of `W` within `tolerance`, the cycles classified
/// alike, and the level of `W` known to within [`LEVEL_BOUND`] times
/// `tolerance` (which a turning point of `W`, with changes of both signs,
/// or an approach still bending, does not give).
fn settled(history: &[CycleRecord], tolerance: f64) -> Option<SteadyState> {
    if history.len() < SETTLE_CYCLES + 1 {
        return None;
    }
    let tail = &history[history.len() - SETTLE_CYCLES - 1..];
    let steady = tail.windows(2).all(|p| {
        let (a, b) = (p[0].dissipation, p[1].dissipation);
        a > 0.0 && (b - a).abs() <= tolerance * a
    });
    if !steady {
        return None;
    }
    let state = tail[SETTLE_CYCLES].classify();
    if !tail[1..].iter().all(|r| r.classify() == state) {
        return None;
    }
    let w = dissipation_level(history)?;
    (w.uncertainty <= LEVEL_BOUND * tolerance * w.value.abs()).then_some(state)
}

/// The level `W` approaches over the cycles of `history`, with its bound
/// (model.md section 6.1); `None` while it is not known (a turning point,
/// changes that do not shrink, too few cycles).
pub fn dissipation_level(history: &[CycleRecord]) -> Option<Level> {
    let w: Vec<f64> = history.iter().map(|r| r.dissipation).collect();
    level(&w)
}

/// The steady net rotation per cycle of a run settled in `state`: exactly 0
/// for cyclic slip (the nodes that never slip keep the mean of `g`:
/// model.md section 6.2), the level the rotation per cycle approaches for
/// ratchetting (`None` while it is not known), `None` for other states.
pub fn steady_rotation(history: &[CycleRecord], state: SteadyState) -> Option<Level> {
    match state {
        SteadyState::CyclicSlip => Some(Level {
            value: 0.0,
            uncertainty: 0.0,
        }),
        SteadyState::RatchettingMonotonic | SteadyState::RatchettingNonMonotonic => {
            let r: Vec<f64> = history.iter().map(|r| r.rotation).collect();
            level(&r)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(cycle: usize, w: f64) -> CycleRecord {
        let mut r = CycleRecord::new(cycle, 4);
        r.dissipation = w;
        r.forward = vec![1.0, 0.0, 0.0, 0.0];
        r
    }

    #[test]
    fn no_decay_is_a_verdict_before_the_cap() {
        // Geometric and power-law decays towards zero, and decays towards a
        // small positive level, look alike over tens of cycles: none of them
        // is a verdict by itself.
        let geometric: Vec<_> = (1..=40).map(|k| record(k, 0.8f64.powi(k as i32))).collect();
        let power: Vec<_> = (1..=60)
            .map(|k| record(k, (k as f64).powf(-1.8 - 0.05 * k as f64)))
            .collect();
        let level: Vec<_> = (1..=30)
            .map(|k| record(k, 1e-7 + 0.5 * 0.7f64.powi(k as i32)))
            .collect();
        for h in [geometric, power, level] {
            assert_eq!(assess(&h, &Convergence::default()), None);
        }
    }

    #[test]
    fn one_flat_pair_at_a_turning_point_is_not_settled() {
        // W falls, turns and rises: two cycles agree at the minimum only.
        let w = [1.2, 1.1, 1.0, 1.00001, 1.1, 1.2];
        let h: Vec<_> = w
            .iter()
            .enumerate()
            .map(|(i, &w)| record(i + 1, w))
            .collect();
        for n in 2..=h.len() {
            assert_eq!(assess(&h[..n], &Convergence::default()), None);
        }
    }

    #[test]
    fn settled_when_within_tolerance() {
        // Changes halving each cycle: within 0.01 % from the fourth on, and
        // the level then known to well within the bound.
        let h: Vec<_> = (1..=12)
            .map(|k| record(k, 1.0 + 1e-3 * 0.5f64.powi(k as i32)))
            .collect();
        assert_eq!(assess(&h[..4], &Convergence::default()), None);
        assert_eq!(
            assess(&h, &Convergence::default()),
            Some((SteadyState::CyclicSlip, Approach::Converged))
        );
        let level = dissipation_level(&h).unwrap();
        assert!((level.value - 1.0).abs() < 1e-15, "{level:?}");
    }

    #[test]
    fn a_turning_point_is_not_settled() {
        // A fast fall and a slow rise: W turns at a minimum at cycle 22 and
        // levels off 1 % above it. The changes are within 0.01 % around the
        // minimum, but the level is not known there.
        let w = |k: usize| 1.0 + 0.2 * 0.8f64.powi(k as i32) - 0.02 * 0.97f64.powi(k as i32);
        let h: Vec<_> = (1..=400).map(|k| record(k, w(k))).collect();
        let turn = (2..400)
            .find(|&k| w(k) < w(k - 1) && w(k) <= w(k + 1))
            .unwrap();
        let settled = (4..=h.len())
            .find(|&n| assess(&h[..n], &Convergence::default()).is_some())
            .expect("settles");
        assert!(
            settled > turn + 10,
            "settled at {settled}, turned at {turn}"
        );
        let level = dissipation_level(&h[..settled]).unwrap();
        assert!((level.value - 1.0).abs() <= level.uncertainty, "{level:?}");
        assert!(level.uncertainty <= 4e-4, "{level:?}");
    }

    #[test]
    fn changes_that_do_not_shrink_are_not_settled() {
        // Within 0.01 % a cycle, but W goes on rising by as much each
        // cycle: no level, however small the changes.
        let h: Vec<_> = (1..=30).map(|k| record(k, 1.0 + 5e-5 * k as f64)).collect();
        for n in 4..=h.len() {
            assert_eq!(assess(&h[..n], &Convergence::default()), None);
        }
    }

    #[test]
    fn the_criteria_are_checked_against_their_ranges() {
        let (t, m) = (ranges::TOLERANCE, ranges::MAX_CYCLES);
        assert!(Convergence::new(t.low, 10, true).is_err());
        assert!(Convergence::new(t.high, 10, true).is_err());
        assert!(Convergence::new(f64::NAN, 10, true).is_err());
        assert!(Convergence::new(0.5 * (t.low + t.high), m.min, true).is_ok());
        assert!(Convergence::new(1e-4, m.max, true).is_ok());
        assert!(Convergence::new(1e-4, m.min - 1, true).is_err());
        assert!(Convergence::new(1e-4, m.max + 1, true).is_err());
        let d = Convergence::default();
        assert_eq!(
            Convergence::new(d.tolerance(), d.max_cycles(), d.safe_state()),
            Ok(d)
        );
    }

    #[test]
    fn classification_by_nodes() {
        let mut r = CycleRecord::new(1, 3);
        r.dissipation = 1.0;
        r.rotation = 0.5;
        r.forward = vec![1.0, 1.0, 1.0];
        assert_eq!(r.classify(), SteadyState::RatchettingMonotonic);
        r.backward = vec![0.0, 0.2, 0.0];
        assert_eq!(r.classify(), SteadyState::RatchettingNonMonotonic);
        r.forward = vec![1.0, 0.0, 1.0];
        r.backward = vec![0.0; 3];
        assert_eq!(r.classify(), SteadyState::CyclicSlip);
    }

    #[test]
    fn cap_reports_not_converged() {
        let c = Convergence::new(1e-4, 3, true).unwrap();
        let h = vec![record(1, 1.0), record(2, 2.0), record(3, 1.0)];
        assert_eq!(
            assess(&h, &c),
            Some((SteadyState::NotConverged, Approach::Cap))
        );
    }
}
