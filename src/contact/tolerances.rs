//! The tolerances of the contact solver, in one place at the bottom of
//! `contact/`: every module of it may use them, and they depend on nothing.
//! Tractions are in units of the shrink-fit pressure `p0`.

/// Tolerance on the friction inequality, in units of the traction `p0`.
pub(super) const TRACTION_TOL: f64 = 1e-12;

/// A slip node whose `s dg` is below `-DG_TOL * max|dg|` has reversed.
pub(super) const DG_TOL: f64 = 1e-10;

/// `|y|` within this relative distance of `2 pi` is on the torque limit.
pub(super) const GROSS_TOL: f64 = 1e-9;

/// A stick node at the limit leaves it only if the slack `f p - |q|` falls
/// faster than this per unit of the increment parameter: over a whole
/// increment the friction law then holds to `RATE_TOL`, well inside
/// [`TRACTION_TOL`].
pub(super) const RATE_TOL: f64 = 1e-13;

/// Relative width of a tie between the first events of two nodes: a node
/// whose first event comes within this of the earliest is tested exactly
/// (far wider than the round-off in which the branch-free times and the
/// exact test can differ).
pub(super) const EVENT_TIES: f64 = 1e-9;

/// The round-off allowed between a node's end margin as one scan takes it
/// and as the next scan, from the state the move there left, would take it
/// (in the same units as the tractions, like [`SCREEN`] and
/// [`TRACTION_TOL`]: the move recomputes `p` and `q` from their elastic and
/// residual parts, a few ulps of numbers of order one away), and,
/// relative, in the bound on the fall of a margin over a segment.
pub(super) const CLEARANCE_SLACK: f64 = 1e-10;

/// A node whose end margin (`kernels::end_margins`) is under this is tested exactly. The
/// margin is the exact test's quantity summed in another order, so a node a
/// round-off above zero is tested too.
pub(super) const SCREEN: f64 = 1e-9;

/// A pivot (Schur complement or capacitance pivot) below this fraction of
/// its scale makes an update unreliable: rebuild instead.
pub(super) const PIVOT_TOL: f64 = 1e-8;
