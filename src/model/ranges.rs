//! The admissible range of every model parameter, written once: the
//! constructors of this module check against them and the command line
//! quotes them (and parses with them), so a message and its check cannot
//! drift apart.

use super::ParamError;

/// The admissible values of a real parameter: `low ..= high`, with either
/// end open where `*_open` says so.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RealRange {
    /// The parameter as the command line spells it (`lambda`, `nu`, ...).
    pub name: &'static str,
    /// Smallest admissible value (excluded when `low_open`).
    pub low: f64,
    /// Largest admissible value (excluded when `high_open`).
    pub high: f64,
    /// Whether `low` itself is excluded.
    pub low_open: bool,
    /// Whether `high` itself is excluded.
    pub high_open: bool,
    /// The range in words, as error messages quote it.
    pub expected: &'static str,
}

impl RealRange {
    /// Whether `value` is admissible (NaN never is).
    pub fn contains(&self, value: f64) -> bool {
        let above = if self.low_open {
            value > self.low
        } else {
            value >= self.low
        };
        let below = if self.high_open {
            value < self.high
        } else {
            value <= self.high
        };
        above && below
    }

    /// `value` if it is finite and admissible.
    ///
    /// # Errors
    ///
    /// [`ParamError::NotFinite`] or [`ParamError::OutOfRange`], named
    /// [`RealRange::name`].
    pub fn check(&self, value: f64) -> Result<f64, ParamError> {
        let value = super::finite(self.name, value)?;
        if self.contains(value) {
            Ok(value)
        } else {
            Err(ParamError::OutOfRange {
                name: self.name,
                value,
                expected: self.expected,
            })
        }
    }
}

/// The admissible values of a count: `min ..= max`, even numbers only where
/// `even` says so.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CountRange {
    /// The parameter as the command line spells it (`nodes`, `steps`, ...).
    pub name: &'static str,
    /// Smallest admissible count.
    pub min: usize,
    /// Largest admissible count.
    pub max: usize,
    /// Whether only even counts are admissible.
    pub even: bool,
    /// The range in words, as error messages quote it.
    pub expected: &'static str,
}

impl CountRange {
    /// Whether `value` is admissible.
    pub fn contains(&self, value: usize) -> bool {
        (self.min..=self.max).contains(&value) && (!self.even || value.is_multiple_of(2))
    }

    /// `value` if it is admissible.
    ///
    /// # Errors
    ///
    /// [`ParamError::BadCount`], named [`CountRange::name`].
    pub fn check(&self, value: usize) -> Result<usize, ParamError> {
        if self.contains(value) {
            Ok(value)
        } else {
            Err(ParamError::BadCount {
                name: self.name,
                value,
                expected: self.expected,
            })
        }
    }
}

const fn closed(name: &'static str, low: f64, high: f64, expected: &'static str) -> RealRange {
    RealRange {
        name,
        low,
        high,
        low_open: false,
        high_open: false,
        expected,
    }
}

/// `lambda`, the load factor of eq. (12): a sanity cap far above gross slip.
pub const LAMBDA: RealRange = closed("lambda", 0.0, 1e3, "0 <= lambda <= 1000");
/// `phi`, radians.
pub const PHI: RealRange = closed("phi", -1e3, 1e3, "|phi| <= 1000 rad");
/// `psi`, the slope of eq. (13).
pub const PSI: RealRange = closed("psi", -1e6, 1e6, "|psi| <= 1e6");
/// Each coordinate of the centre `A`.
pub const CENTER: RealRange = closed("center", -1e3, 1e3, "|x0|, |y0| <= 1000");
/// The friction coefficient `f`.
pub const FRICTION: RealRange = RealRange {
    low_open: true,
    ..closed("friction", 0.0, 10.0, "0 < f <= 10")
};
/// Poisson's ratio (the incompressible limit `nu = 0.5` excluded).
pub const NU: RealRange = RealRange {
    high_open: true,
    ..closed("nu", 0.0, 0.5, "0 <= nu < 0.5")
};
/// Interface nodes `N`.
pub const NODES: CountRange = CountRange {
    name: "nodes",
    min: 16,
    max: 4096,
    even: true,
    expected: "an even number from 16 to 4096",
};
/// Increments per cycle.
pub const STEPS: CountRange = CountRange {
    name: "steps",
    min: 16,
    max: 100_000,
    even: false,
    expected: "16 to 100000 increments per cycle",
};
/// Cycles run at most before a run is reported not converged.
pub const MAX_CYCLES: CountRange = CountRange {
    name: "max-cycles",
    min: 1,
    max: 100_000,
    even: false,
    expected: "1 to 100000",
};

/// Load points `M` of an elliptical cycle in the `lambda_2` linear
/// programme (model.md section 7.3; a straight cycle uses its two ends).
pub const SAMPLES: CountRange = CountRange {
    name: "samples",
    min: 3,
    max: 4096,
    even: false,
    expected: "3 to 4096 points on the ellipse",
};
/// Vertices `K` of a designed transient `O -> P1 -> ... -> PK -> A`
/// (`analysis::design`).
pub const VERTICES: CountRange = CountRange {
    name: "vertices",
    min: 1,
    max: 16,
    even: false,
    expected: "1 to 16",
};
/// Particles of the design's swarm.
pub const PARTICLES: CountRange = CountRange {
    name: "particles",
    min: 2,
    max: 1000,
    even: false,
    expected: "2 to 1000",
};
/// Swarm generations of a design search after the first.
pub const ITERATIONS: CountRange = CountRange {
    name: "iterations",
    min: 0,
    max: 10_000,
    even: false,
    expected: "0 to 10000",
};
/// How far inside the gross-slip line `|y| = 2 pi` a designed vertex
/// stays (model.md section 10): on the line the whole interface slides at
/// once.
pub const GROSS_GAP: RealRange = closed("gross-gap", 1e-3, 3.0, "a number from 0.001 to 3");
/// Bisections of an increment whose active set does not settle (model.md
/// section 3.3, robustness): each halves the increment, so the cost of a
/// failing increment grows as `2^k`, and 20 already reaches a millionth of
/// an increment.
pub const FAILURE_BISECTIONS: CountRange = CountRange {
    name: "failure-bisections",
    min: 0,
    max: 20,
    even: false,
    expected: "0 to 20",
};
/// The relative change of the cycle dissipation `W` below which a run has
/// settled (model.md section 6.1; the paper's 0.01 % is `1e-4`).
pub const TOLERANCE: RealRange = RealRange {
    low_open: true,
    high_open: true,
    ..closed("tolerance", 0.0, 1.0, "0 < tolerance < 1")
};

/// The range in words of the parameter the command line spells `flag`.
pub fn expected(flag: &str) -> Option<&'static str> {
    Some(match flag {
        "lambda" => LAMBDA.expected,
        "phi" => PHI.expected,
        "psi" => PSI.expected,
        "center" => CENTER.expected,
        "friction" => FRICTION.expected,
        "nu" => NU.expected,
        "nodes" => NODES.expected,
        "steps" => STEPS.expected,
        "max-cycles" => MAX_CYCLES.expected,
        "samples" => SAMPLES.expected,
        "vertices" => VERTICES.expected,
        "particles" => PARTICLES.expected,
        "iterations" => ITERATIONS.expected,
        "gross-gap" => GROSS_GAP.expected,
        "failure-bisections" => FAILURE_BISECTIONS.expected,
        "tolerance" => TOLERANCE.expected,
        _ => return None,
    })
}
