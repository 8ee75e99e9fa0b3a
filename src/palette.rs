//! The paper's state colours, shared by the front ends: the figures
//! ([`crate::figure`]) and the terminal explorer ([`crate::tui`]) colour a
//! regime map alike. Plain RGB triples, so neither front end depends on
//! the other's drawing library.
//!
//! The colours are the dominant colours of the paper's markers: shakedown
//! a light grey (a black circle on white), cyclic slip red, ratchetting
//! blue (with red when non-monotonic), gross slip a dark grey, separation
//! brown, a run that did not converge amber and one that failed
//! numerically magenta. [`Shading`] darkens a cell with its
//! dissipation `W` on a log scale.

use crate::analysis::regime::{RegimeCell, RegimeMap};
use crate::stepping::steady::SteadyState;

/// A colour as red, green and blue, 0 to 255 each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// Relative luminance in `[0, 1]` (Rec. 709 weights, no gamma): above
    /// one half, dark text reads on it.
    pub fn luminance(self) -> f64 {
        (0.2126 * f64::from(self.0) + 0.7152 * f64::from(self.1) + 0.0722 * f64::from(self.2))
            / 255.0
    }
}

/// The fill colour of a regime-map cell in `state` (`None`: the run failed
/// numerically). Gross slip, separation and a failure each have their own
/// colour: a grey, a brown and a magenta no state uses.
pub fn map_colour(state: Option<SteadyState>) -> Rgb {
    match state {
        Some(SteadyState::Shakedown) => Rgb(235, 235, 235),
        Some(SteadyState::CyclicSlip) => Rgb(240, 130, 110),
        Some(SteadyState::RatchettingMonotonic) => Rgb(110, 160, 240),
        Some(SteadyState::RatchettingNonMonotonic) => Rgb(175, 125, 215),
        Some(SteadyState::GrossSlip) => Rgb(110, 110, 110),
        Some(SteadyState::Separation) => Rgb(175, 135, 80),
        None => Rgb(200, 60, 175),
        Some(SteadyState::NotConverged) => Rgb(250, 210, 120),
    }
}

/// `colour` darkened towards its own deep shade by `t` in `[0, 1]` (at
/// most 45 %, so the state's hue still shows).
pub fn shade(colour: Rgb, t: f64) -> Rgb {
    let t = t.clamp(0.0, 1.0) * 0.45;
    let f = |v: u8| (f64::from(v) * (1.0 - t)).round() as u8;
    Rgb(f(colour.0), f(colour.1), f(colour.2))
}

/// Whether cells in `state` are shaded by `W`: not shakedown (no `W`), nor
/// gross slip, separation or a failure (no steady `W`).
pub fn is_shaded(state: Option<SteadyState>) -> bool {
    !matches!(
        state,
        Some(SteadyState::Shakedown | SteadyState::GrossSlip | SteadyState::Separation) | None
    )
}

/// The log scale of `W` a map's cells are shaded on: from the largest `W`
/// on the map down to its smallest, but at most six decades.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shading {
    /// `log10` of the lightest shade's `W`.
    pub lo: f64,
    /// `log10` of the darkest shade's `W`.
    pub hi: f64,
}

impl Shading {
    /// The scale of `map`'s dissipations ([`RegimeMap::dissipation_range`]).
    pub fn of(map: &RegimeMap) -> Shading {
        let (wlo, whi) = map.dissipation_range().unwrap_or((1.0, 1.0));
        Shading {
            lo: wlo.max(whi * 1e-6).log10(),
            hi: whi.log10(),
        }
    }

    /// How dark `cell` is drawn, in `[0, 1]`: 0 for the states without a
    /// shade ([`is_shaded`]) and for `W <= 0`.
    pub fn of_cell(&self, cell: &RegimeCell) -> f64 {
        let w = cell.dissipation;
        if !is_shaded(cell.state) || w.is_nan() || w <= 0.0 || self.hi <= self.lo {
            0.0
        } else {
            (w.log10().max(self.lo) - self.lo) / (self.hi - self.lo)
        }
    }

    /// The colour of `cell`: its state's, shaded by its `W`.
    pub fn colour(&self, cell: &RegimeCell) -> Rgb {
        shade(map_colour(cell.state), self.of_cell(cell))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shading_darkens_with_w() {
        let cell = |state, w| RegimeCell {
            state: Some(state),
            dissipation: w,
        };
        let map = RegimeMap::from_cells([
            (4.0, 0.0, cell(SteadyState::Shakedown, 0.0)),
            (5.0, 0.0, cell(SteadyState::CyclicSlip, 1e-4)),
            (6.0, 0.0, cell(SteadyState::CyclicSlip, 1e-2)),
        ]);
        let s = Shading::of(&map);
        assert_eq!(s.of_cell(&map.cell(0, 0).unwrap()), 0.0);
        assert_eq!(s.of_cell(&map.cell(1, 0).unwrap()), 0.0);
        assert_eq!(s.of_cell(&map.cell(2, 0).unwrap()), 1.0);
        let dark = s.colour(&map.cell(2, 0).unwrap());
        assert!(dark.luminance() < map_colour(Some(SteadyState::CyclicSlip)).luminance());
        // Gross slip, separation and a failure each have their own look.
        let ends = [
            map_colour(None),
            map_colour(Some(SteadyState::GrossSlip)),
            map_colour(Some(SteadyState::Separation)),
        ];
        assert!(ends[0] != ends[1] && ends[1] != ends[2] && ends[0] != ends[2]);
    }
}
