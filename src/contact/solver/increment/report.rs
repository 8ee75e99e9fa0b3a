//! What an increment did ([`Increment`]): its events, the slip of each
//! node and its counters.

use crate::model::LoadPoint;

/// What happened at an event inside an increment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactEventKind {
    /// Stick nodes reached `|q| = f p` and started to slip.
    SlipEntry,
    /// Slipping nodes stuck again (their slip rate reached zero).
    AdvancingStick,
}

/// An event located exactly within an increment.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactEvent {
    /// What happened.
    pub kind: ContactEventKind,
    /// Parameter in `[0, 1]` of the increment's straight segment.
    pub fraction: f64,
    /// The load point of the event.
    pub load: LoadPoint,
    /// The nodes involved, in increasing order.
    pub nodes: Vec<usize>,
}

/// What the last [`Contact::advance`] did.
#[derive(Debug, Clone)]
pub struct Increment {
    /// The segment's start point.
    pub from: LoadPoint,
    /// The segment's end point.
    pub to: LoadPoint,
    /// How far along the segment the contact got: 1 unless the run ended
    /// (gross slip, separation) or the rate problem failed.
    pub reached: f64,
    /// `1/2 int q dg dtheta = f/2 int p |dg| dtheta` over the increment.
    pub dissipation: f64,
    /// Straight sub-segments with a fixed slip set.
    pub segments: usize,
    /// Entries into slip and advancing stick, in order.
    pub events: Vec<ContactEvent>,
    /// Positive slip of each node over the increment.
    pub forward: Vec<f64>,
    /// Negative slip of each node over the increment, as a positive number.
    pub backward: Vec<f64>,
    /// Whether any node slipped (`forward` and `backward` are zero if not).
    pub slipped: bool,
    /// Whether the slip set or a direction changed.
    pub set_changed: bool,
    /// Rate problems solved.
    pub rate_solves: usize,
    /// LU factorisations computed.
    pub factorisations: usize,
    /// The increment (or its rest) was solved by the finite-step active-set
    /// iteration because the rate problem did not settle.
    pub fallback: bool,
    /// `forward` and `backward` still hold the last increment's slip: the
    /// first move of this one that slips sets them (in its pass over the
    /// nodes) instead of a pass that clears them first; [`Contact::advance`]
    /// clears them if none does.
    pub(super) stale: bool,
    /// Node lists of earlier increments' events, emptied, for the next
    /// events to reuse: an event then allocates nothing once a run is under
    /// way.
    pub(super) spare: Vec<Vec<usize>>,
}

impl Increment {
    pub(in crate::contact) fn new(n: usize) -> Self {
        Self {
            from: LoadPoint::ORIGIN,
            to: LoadPoint::ORIGIN,
            reached: 0.0,
            dissipation: 0.0,
            segments: 0,
            events: Vec::new(),
            forward: vec![0.0; n],
            backward: vec![0.0; n],
            slipped: false,
            set_changed: false,
            rate_solves: 0,
            factorisations: 0,
            fallback: false,
            stale: false,
            spare: Vec::new(),
        }
    }

    /// An empty node list, reusing one of an earlier event if there is one.
    /// A new one has room for every node, so that no list grows later.
    pub(super) fn node_list(&mut self) -> Vec<usize> {
        let n = self.forward.len();
        self.spare.pop().unwrap_or_else(|| Vec::with_capacity(n))
    }

    /// Clear `forward` and `backward` if they hold an earlier increment's
    /// slip.
    pub(super) fn clear_stale(&mut self) {
        if std::mem::take(&mut self.stale) {
            self.forward.fill(0.0);
            self.backward.fill(0.0);
        }
    }

    /// Add slip `dg` of node `j` to `forward` / `backward`.
    pub(super) fn add_slip(&mut self, j: usize, dg: f64) {
        self.clear_stale();
        if dg > 0.0 {
            self.forward[j] += dg;
            self.slipped = true;
        } else if dg < 0.0 {
            self.backward[j] -= dg;
            self.slipped = true;
        }
    }

    pub(super) fn reset(&mut self, from: LoadPoint, to: LoadPoint) {
        self.from = from;
        self.to = to;
        self.reached = 0.0;
        self.dissipation = 0.0;
        self.segments = 0;
        for event in self.events.drain(..) {
            let mut nodes = event.nodes;
            nodes.clear();
            self.spare.push(nodes);
        }
        self.stale |= self.slipped;
        self.slipped = false;
        self.set_changed = false;
        self.rate_solves = 0;
        self.factorisations = 0;
        self.fallback = false;
    }
}
