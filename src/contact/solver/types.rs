//! The contact's vocabulary: a node's slip direction, how a step ends
//! ([`ContactEnd`], [`Advanced`], [`Solved`], [`ContactError`]) and a
//! solved, uncommitted increment ([`Trial`]).

use crate::model::LoadPoint;

/// Direction of slip at one node during the last increment, named as the
/// paper names it (model.md section 1.3): **forward** slip is `dh > 0`, that
/// is `dg < 0` (`g` is proportional to `-h`), with `q = -f p`: the disc
/// moves clockwise relative to the plate, the way a positive torque drives
/// it. It is the direction of the ratchet at the paper's points B and C.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SlipDirection {
    /// No slip.
    #[default]
    Stick,
    /// The paper's forward slip: `dh > 0`, `dg < 0`, `q = -f p`.
    Forward,
    /// The paper's backward slip: `dh < 0`, `dg > 0`, `q = +f p`.
    Backward,
}

impl SlipDirection {
    /// The sign of `dg` for this direction: `-1` forward, `+1` backward,
    /// `0` for stick (it is also the sign of `q` at the friction limit).
    pub fn sign(self) -> f64 {
        match self {
            SlipDirection::Stick => 0.0,
            SlipDirection::Backward => 1.0,
            SlipDirection::Forward => -1.0,
        }
    }
    /// The direction whose `dg` has the sign of `s`.
    pub(crate) fn from_sign(s: f64) -> Self {
        if s > 0.0 {
            SlipDirection::Backward
        } else {
            SlipDirection::Forward
        }
    }
    /// `+1` for forward slip, `-1` for backward, `0` for stick: the paper's
    /// sense, as the slip-map CSV writes it.
    pub fn paper_sign(self) -> i8 {
        match self {
            SlipDirection::Stick => 0,
            SlipDirection::Forward => 1,
            SlipDirection::Backward => -1,
        }
    }
    /// Whether the node slips.
    pub fn is_slipping(self) -> bool {
        self != SlipDirection::Stick
    }
}

/// A physical end of the contact problem within an increment: the load
/// cannot go further along its path. These are outcomes of the physics
/// (the stepper reports them as [`crate::stepping::Outcome`]s), not failures.
#[derive(Debug, Clone, PartialEq)]
pub enum ContactEnd {
    /// `|y|` reached `2 pi`: the friction torque cannot grow further and the
    /// whole interface slides (model.md section 2).
    GrossSlip {
        /// Where it happened.
        load: LoadPoint,
    },
    /// The pressure reached zero at a node.
    Separation {
        /// Where it happened.
        load: LoadPoint,
        /// The node that separated.
        node: usize,
        /// Its angle.
        theta: f64,
        /// Its pressure (at most 0).
        pressure: f64,
    },
}

impl std::fmt::Display for ContactEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ContactEnd::GrossSlip { load } => {
                write!(f, "gross slip at load point {load}: the whole interface slides")
            }
            ContactEnd::Separation {
                load,
                node,
                theta,
                pressure,
            } => write!(
                f,
                "separation at load point {load}: p = {pressure:.4} at theta = {theta:.4} rad (node {node})"
            ),
        }
    }
}

/// What [`Contact::advance`] reached.
#[derive(Debug, Clone, PartialEq)]
pub enum Advanced {
    /// The target load point, with the friction law satisfied on the way.
    Reached,
    /// A physical end on the way; the contact is left at that point
    /// ([`Increment::reached`] tells how far along the segment).
    Ended(ContactEnd),
    /// Stopped at an event (entry into slip, advancing stick) short of the
    /// target, as [`Contact::set_pause_at_events`] asked. The contact is
    /// left at the event's load point with the slip set decided there;
    /// advancing to the same target again goes on along the same segment.
    Paused,
}

impl Advanced {
    /// Whether the target was reached.
    pub fn is_reached(&self) -> bool {
        matches!(self, Advanced::Reached)
    }
}

/// What [`Contact::solve`] found for one finite increment.
#[derive(Debug, Clone)]
pub enum Solved {
    /// The increment's solution, to [`Contact::commit`].
    Trial(Trial),
    /// A physical end: the increment has no frictional solution.
    Ended(ContactEnd),
}

impl Solved {
    /// The trial, or `None` at a physical end.
    pub fn trial(self) -> Option<Trial> {
        match self {
            Solved::Trial(t) => Some(t),
            Solved::Ended(_) => None,
        }
    }
}

/// A numerical failure of the contact solver (the physical ends are
/// [`ContactEnd`]s, not errors).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ContactError {
    /// The active set did not settle.
    #[error("active set did not settle at load point {load} after {iterations} iterations")]
    NotSettled {
        /// Where it happened.
        load: LoadPoint,
        /// Iterations tried.
        iterations: usize,
    },
}

/// Whether two slip sets with directions are the same. A branch-free pass
/// over the direction codes: slice `==` on an enum compares element by
/// element with an early exit, which does not vectorise, and the increment
/// asks at every event.
pub(in crate::contact) fn same_directions(a: &[SlipDirection], b: &[SlipDirection]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .fold(0u8, |acc, (&x, &y)| acc | (x as u8 ^ y as u8))
            == 0
}

/// The nodes at which two slip sets' directions differ, appended to `out`
/// in node order. Chunks of 16 nodes are compared at once, as two 128-bit
/// numbers, and the differing bytes of a chunk that differs give its
/// nodes: an event changes a node or two of the `N`, and passes with a
/// branch per node (here and in the set's update) were some 4 % of a
/// sweep's instructions.
pub(in crate::contact) fn push_differences(
    a: &[SlipDirection],
    b: &[SlipDirection],
    out: &mut Vec<usize>,
) {
    const CHUNK: usize = 16;
    debug_assert_eq!(a.len(), b.len());
    let (xs, ys) = (a.chunks_exact(CHUNK), b.chunks_exact(CHUNK));
    let (x_tail, y_tail) = (xs.remainder(), ys.remainder());
    // A chunk's sixteen directions as the bytes of one number (one load).
    let bytes = |s: &[SlipDirection]| {
        let chunk: &[SlipDirection; CHUNK] = s.try_into().expect("a whole chunk");
        u128::from_le_bytes(chunk.map(|d| d as u8))
    };
    for (c, (x, y)) in xs.zip(ys).enumerate() {
        // The bytes that differ mark the nodes, in node order from the
        // lowest (a loop over the sixteen nodes of a differing chunk, with
        // a branch each, was most of this function's time).
        let mut differ = bytes(x) ^ bytes(y);
        while differ != 0 {
            let i = (differ.trailing_zeros() / 8) as usize;
            out.push(c * CHUNK + i);
            differ &= !(0xff_u128 << (8 * i));
        }
    }
    let from = a.len() - x_tail.len();
    let differ = x_tail
        .iter()
        .zip(y_tail)
        .enumerate()
        .filter(|(_, (u, v))| u != v);
    out.extend(differ.map(|(i, _)| from + i));
}

/// The result of solving one increment, not yet committed.
#[derive(Debug, Clone)]
pub struct Trial {
    /// The load point the increment ends at.
    pub load: LoadPoint,
    /// `dg` at every node.
    pub slip_increment: Vec<f64>,
    /// `p` at every node at the end of the increment.
    pub pressure: Vec<f64>,
    /// `q` at every node at the end of the increment.
    pub shear: Vec<f64>,
    /// How each node slipped during the increment.
    pub directions: Vec<SlipDirection>,
    /// `1/2 int q dg dtheta` over this increment (>= 0).
    pub dissipation: f64,
    /// Active-set iterations taken.
    pub iterations: usize,
    /// Factorisations computed (the rest reused the cached one).
    pub factorisations: usize,
}

impl Trial {
    /// Nodes that slipped before this increment and stick after it.
    pub fn advancing_stick(&self, before: &[SlipDirection]) -> Vec<usize> {
        before
            .iter()
            .zip(&self.directions)
            .enumerate()
            .filter(|(_, (b, a))| b.is_slipping() && !a.is_slipping())
            .map(|(j, _)| j)
            .collect()
    }
}
