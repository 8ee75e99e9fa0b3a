//! Slip zones: contiguous runs of slipping nodes round the interface, and
//! how they change between two instants (appear, split, merge, vanish).
//! The paper reads its slip maps (Figs. 5 and 7) in these terms.

use serde::Serialize;

use crate::contact::SlipDirection;

/// One slip zone: `len` neighbouring nodes from `first` (wrapping through
/// node 0), all slipping in `direction`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct SlipZone {
    /// The first node of the zone, counting counter-clockwise.
    pub first: usize,
    /// How many nodes the zone holds (at least 1).
    pub len: usize,
    /// The direction every node of the zone slips in.
    pub direction: SlipDirection,
}

impl SlipZone {
    /// The nodes of the zone in order, wrapping round `nodes`.
    pub fn nodes(&self, nodes: usize) -> impl Iterator<Item = usize> + '_ {
        // A counter that wraps, not a remainder per node: this runs at
        // every change of the slip set.
        let start = self.first.checked_rem(nodes).unwrap_or(0);
        (0..self.len).scan(start, move |j, _| {
            let node = *j;
            *j += 1;
            if *j == nodes {
                *j = 0;
            }
            Some(node)
        })
    }
}

/// What happened to the slip zones of one direction between two instants.
/// Zones of the same direction that share a node are the same zone,
/// continued.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "change", content = "direction", rename_all = "kebab-case")]
pub enum ZoneChange {
    /// A zone with no predecessor.
    Appeared(SlipDirection),
    /// One zone became two or more.
    Split(SlipDirection),
    /// Two or more zones became one.
    Merged(SlipDirection),
    /// A zone with no successor.
    Vanished(SlipDirection),
}

impl ZoneChange {
    /// The direction of the zones concerned.
    pub fn direction(self) -> SlipDirection {
        match self {
            ZoneChange::Appeared(d)
            | ZoneChange::Split(d)
            | ZoneChange::Merged(d)
            | ZoneChange::Vanished(d) => d,
        }
    }
}

impl std::fmt::Display for ZoneChange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let word = match self.direction() {
            SlipDirection::Backward => "backward",
            _ => "forward",
        };
        match self {
            ZoneChange::Appeared(_) => write!(f, "{word} slip zone appeared"),
            ZoneChange::Split(_) => write!(f, "{word} slip zone split"),
            ZoneChange::Merged(_) => write!(f, "{word} slip zones merged"),
            ZoneChange::Vanished(_) => write!(f, "{word} slip zone vanished"),
        }
    }
}

/// Contiguous runs of slipping nodes round the circle; a run may wrap
/// through node 0. A change of direction starts a new zone.
///
/// ```
/// use shakedown::SlipDirection::{Backward, Forward, Stick};
/// use shakedown::stepping::slip_zones;
///
/// // One zone through node 0: nodes 3, 4 and 0.
/// let zones = slip_zones(&[Forward, Stick, Stick, Forward, Forward]);
/// assert_eq!(zones.len(), 1);
/// assert_eq!((zones[0].first, zones[0].len), (3, 3));
/// // A change of direction starts a new zone.
/// assert_eq!(slip_zones(&[Forward, Backward, Stick, Stick]).len(), 2);
/// ```
pub fn slip_zones(dirs: &[SlipDirection]) -> Vec<SlipZone> {
    let n = dirs.len();
    if n == 0 {
        return Vec::new();
    }
    if dirs.iter().all(|d| *d == dirs[0]) {
        return if dirs[0].is_slipping() {
            vec![SlipZone {
                first: 0,
                len: n,
                direction: dirs[0],
            }]
        } else {
            Vec::new()
        };
    }
    // Start scanning just after a boundary so no zone is split by wrap-around.
    let Some(start) = (0..n).find(|&j| dirs[j] != dirs[(j + n - 1) % n]) else {
        return Vec::new();
    };
    let mut zones = Vec::new();
    // Node `start + j` round the circle (`start < n`, `j < n`).
    let at = |j: usize| {
        if start + j < n {
            start + j
        } else {
            start + j - n
        }
    };
    let mut j = 0;
    while j < n {
        let idx = at(j);
        let d = dirs[idx];
        let mut len = 1;
        while j + len < n && dirs[at(j + len)] == d {
            len += 1;
        }
        if d.is_slipping() {
            zones.push(SlipZone {
                first: idx,
                len,
                direction: d,
            });
        }
        j += len;
    }
    zones
}

/// The changes between the zones `old` and `new` of an interface of
/// `nodes` nodes, appearances and merges first, then vanishings and
/// splits, without repeats.
pub fn zone_changes(old: &[SlipZone], new: &[SlipZone], nodes: usize) -> Vec<ZoneChange> {
    const NONE: u32 = u32::MAX;
    let owners = |zones: &[SlipZone]| {
        let mut owner = vec![NONE; nodes];
        for (i, z) in zones.iter().enumerate() {
            for j in z.nodes(nodes) {
                owner[j] = i as u32;
            }
        }
        owner
    };
    let old_owner = owners(old);
    let new_owner = owners(new);
    // How many zones of `other` in the same direction `zone` shares a node
    // with: 0, 1, or 2 for "more than one".
    let links = |zone: &SlipZone, other: &[SlipZone], owner: &[u32]| {
        let mut first = NONE;
        for j in zone.nodes(nodes) {
            let i = owner[j];
            if i == NONE || i == first || other[i as usize].direction != zone.direction {
                continue;
            }
            if first != NONE {
                return 2;
            }
            first = i;
        }
        usize::from(first != NONE)
    };
    let mut out = Vec::new();
    for z in new {
        match links(z, old, &old_owner) {
            0 => out.push(ZoneChange::Appeared(z.direction)),
            1 => {}
            _ => out.push(ZoneChange::Merged(z.direction)),
        }
    }
    for z in old {
        match links(z, new, &new_owner) {
            0 => out.push(ZoneChange::Vanished(z.direction)),
            1 => {}
            _ => out.push(ZoneChange::Split(z.direction)),
        }
    }
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use SlipDirection::*;

    fn z(first: usize, len: usize, direction: SlipDirection) -> SlipZone {
        SlipZone {
            first,
            len,
            direction,
        }
    }

    #[test]
    fn zones_wrap_round() {
        let d = [Forward, Stick, Stick, Forward, Forward];
        assert_eq!(slip_zones(&d), vec![z(3, 3, Forward)]);
        let d = [Forward, Backward, Stick, Stick];
        assert_eq!(slip_zones(&d).len(), 2);
        assert!(slip_zones(&[Stick; 4]).is_empty());
        assert_eq!(slip_zones(&[Forward; 4]), vec![z(0, 4, Forward)]);
    }

    #[test]
    fn zone_nodes_wrap_through_node_0() {
        let nodes: Vec<usize> = z(14, 4, Forward).nodes(16).collect();
        assert_eq!(nodes, [14, 15, 0, 1]);
        let whole: Vec<usize> = z(3, 5, Backward).nodes(5).collect();
        assert_eq!(whole, [3, 4, 0, 1, 2]);
        // A zone across node 0 that splits in two, one on each side.
        let one = [z(14, 6, Forward)];
        let two = [z(14, 1, Forward), z(2, 2, Forward)];
        assert_eq!(
            zone_changes(&one, &two, 16),
            vec![ZoneChange::Split(Forward)]
        );
    }

    #[test]
    fn zone_changes_name_what_happened() {
        let one = [z(2, 6, Forward)];
        let two = [z(2, 2, Forward), z(6, 2, Forward)];
        assert_eq!(
            zone_changes(&one, &two, 16),
            vec![ZoneChange::Split(Forward)]
        );
        assert_eq!(
            zone_changes(&two, &one, 16),
            vec![ZoneChange::Merged(Forward)]
        );
        assert_eq!(
            zone_changes(&[], &one, 16),
            vec![ZoneChange::Appeared(Forward)]
        );
        assert_eq!(
            zone_changes(&one, &[], 16),
            vec![ZoneChange::Vanished(Forward)]
        );
        assert!(zone_changes(&one, &[z(3, 6, Forward)], 16).is_empty());
        assert_eq!(
            ZoneChange::Split(Backward).to_string(),
            "backward slip zone split"
        );
    }
}
