//! The event log of one run as CSV (`shakedown events`): one row per event,
//! under the metadata header of every output ([`super::csv::Metadata`]).
//!
//! Columns ([`EVENTS_HEADER`]): `cycle` (0 in the initial transient),
//! `omega_t` (in `[0, 2 pi)`, empty in the transient), the load point `x`,
//! `y` (exact for advancing stick, slip start and the terminal events; the
//! end of the increment otherwise), `kind` ([`EventKind`]), `nodes`,
//! `theta_from`, `theta_to` (the shortest arc holding the nodes, `from >
//! to` when it wraps through `theta = pi`), and for advancing stick
//! `locked_slip_max`, `locked_slip_mean`: the slip the nodes that just
//! stuck gathered in the slip episode that ends there (model.md section
//! 3.3; signed, positive forward in `g`).

use std::fmt;
use std::str::FromStr;

use super::csv::Metadata;

/// The columns of the events CSV.
pub const EVENTS_HEADER: &str =
    "cycle,omega_t,x,y,kind,nodes,theta_from,theta_to,locked_slip_max,locked_slip_mean";

/// What happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// Slipping nodes stuck again (model.md section 3.3).
    AdvancingStick,
    /// Stick nodes reached the friction limit and started to slip.
    SlipStart,
    /// A slip zone with no predecessor.
    ZoneAppeared,
    /// One slip zone became two or more.
    ZoneSplit,
    /// Two or more slip zones became one.
    ZoneMerged,
    /// A slip zone with no successor.
    ZoneVanished,
    /// A cycle ended (its `W` is not a column: see `shakedown run`).
    CycleEnd,
    /// The steady state was reached and classified.
    State,
    /// The whole interface slides: the run ends.
    GrossSlip,
    /// The pressure reached zero: the run ends.
    Separation,
}

impl EventKind {
    /// Every kind, in the order of the docs.
    pub const ALL: [EventKind; 10] = [
        EventKind::AdvancingStick,
        EventKind::SlipStart,
        EventKind::ZoneAppeared,
        EventKind::ZoneSplit,
        EventKind::ZoneMerged,
        EventKind::ZoneVanished,
        EventKind::CycleEnd,
        EventKind::State,
        EventKind::GrossSlip,
        EventKind::Separation,
    ];

    /// The name in the CSV and on the command line.
    pub fn as_str(self) -> &'static str {
        match self {
            EventKind::AdvancingStick => "advancing-stick",
            EventKind::SlipStart => "slip-start",
            EventKind::ZoneAppeared => "zone-appeared",
            EventKind::ZoneSplit => "zone-split",
            EventKind::ZoneMerged => "zone-merged",
            EventKind::ZoneVanished => "zone-vanished",
            EventKind::CycleEnd => "cycle-end",
            EventKind::State => "state",
            EventKind::GrossSlip => "gross-slip",
            EventKind::Separation => "separation",
        }
    }
}

impl fmt::Display for EventKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for EventKind {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        EventKind::ALL
            .into_iter()
            .find(|k| k.as_str() == text.trim())
            .ok_or_else(|| {
                let names: Vec<&str> = EventKind::ALL.iter().map(|k| k.as_str()).collect();
                format!("expected one of {}", names.join(", "))
            })
    }
}

/// One row of the events CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct EventRow {
    /// The cycle, 1-based; 0 in the initial transient.
    pub cycle: usize,
    /// `omega t` in `[0, 2 pi)`; `None` in the transient.
    pub omega_t: Option<f64>,
    /// The load point.
    pub x: f64,
    /// The load point.
    pub y: f64,
    /// What happened.
    pub kind: EventKind,
    /// The nodes concerned (for a zone change, the nodes slipping after
    /// it; for a state, the nodes).
    pub nodes: usize,
    /// The arc of the nodes concerned, when there are nodes to place.
    pub theta: Option<(f64, f64)>,
    /// For advancing stick: the largest (signed) and the mean episode slip
    /// of the nodes that stuck.
    pub locked_slip: Option<(f64, f64)>,
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(String::new, |v| format!("{v}"))
}

/// The rows as CSV under `meta`'s header lines and [`EVENTS_HEADER`].
pub fn events_csv(meta: &Metadata, rows: &[EventRow]) -> String {
    let mut out = meta.render();
    out.push_str(EVENTS_HEADER);
    out.push('\n');
    for r in rows {
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{}\n",
            r.cycle,
            opt(r.omega_t),
            r.x,
            r.y,
            r.kind,
            r.nodes,
            opt(r.theta.map(|t| t.0)),
            opt(r.theta.map(|t| t.1)),
            opt(r.locked_slip.map(|l| l.0)),
            opt(r.locked_slip.map(|l| l.1)),
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_round_trip_and_rows_have_every_column() {
        for k in EventKind::ALL {
            assert_eq!(k.as_str().parse::<EventKind>(), Ok(k));
        }
        assert!("stick".parse::<EventKind>().is_err());
        let row = EventRow {
            cycle: 3,
            omega_t: Some(1.5),
            x: 0.1,
            y: -0.2,
            kind: EventKind::AdvancingStick,
            nodes: 4,
            theta: Some((3.0, -3.0)),
            locked_slip: Some((-1e-3, -5e-4)),
        };
        let text = events_csv(&Metadata::new("events"), &[row]);
        let last = text.lines().last().unwrap();
        assert_eq!(last.split(',').count(), EVENTS_HEADER.split(',').count());
        assert!(last.contains(",advancing-stick,4,3,-3,"));
    }
}
