//! The search space of a designed transient: the admissible region of the
//! load plane ([`Region`]) and the path families and their parameters
//! ([`Family`], [`Shape`]).

use super::*;

/// The admissible box of the load plane: `|x| <= x_max`, `|y| <= y_max`.
/// Below `|y| = 2 pi` the interface cannot slide as a whole, and below the
/// separation bound on `|x|` it cannot separate without locked-in slip
/// (model.md section 2.3, [`Initial::custom_for`]). The box is convex, so
/// the straight segments between its points stay in it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Region {
    x_max: f64,
    y_max: f64,
}

impl Region {
    /// The box for `material`: `|y| <= 2 pi - GROSS_SLIP_GAP`, and `|x|` at
    /// most 99.9 % of the separation bound `2 pi chi / (f beta)` (12.21 for
    /// the paper's material).
    pub fn for_material(material: &Material) -> Self {
        Self::box_for(material, GROSS_SLIP_GAP)
    }

    /// The box with `|y| <= 2 pi - gap`: a wider `gap` keeps the vertices
    /// further inside the gross-slip line. The frontier's dependence on
    /// `gap` shows how much the gross-slip line limits what a transient can
    /// lock in (model.md section 10).
    ///
    /// # Errors
    ///
    /// [`ParamError`] unless `gap` is in [`crate::model::ranges::GROSS_GAP`].
    pub fn with_gross_gap(material: &Material, gap: f64) -> Result<Self, ParamError> {
        Ok(Self::box_for(
            material,
            crate::model::ranges::GROSS_GAP.check(gap)?,
        ))
    }

    fn box_for(material: &Material, gap: f64) -> Self {
        let separation = 2.0 * PI * material.chi() / (material.friction() * material.beta());
        Self {
            x_max: 0.999 * separation,
            y_max: 2.0 * PI - gap,
        }
    }

    /// Largest `|x|` of a vertex.
    pub fn x_max(&self) -> f64 {
        self.x_max
    }
    /// Largest `|y|` of a vertex.
    pub fn y_max(&self) -> f64 {
        self.y_max
    }

    /// Whether `p` lies in the box.
    pub fn contains(&self, p: LoadPoint) -> bool {
        p.x().abs() <= self.x_max && p.y().abs() <= self.y_max
    }

    fn clamp(&self, x: f64, y: f64) -> LoadPoint {
        LoadPoint::new(
            x.clamp(-self.x_max, self.x_max),
            y.clamp(-self.y_max, self.y_max),
        )
    }
}

/// A family of transients `O -> P1 -> ... -> PK -> A`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    /// `K` free vertices: `2K` parameters, the coordinates.
    Free,
    /// Alternating loads of decreasing amplitude about `A` (Barber 2018): `P1`
    /// free, then `Pk = A + rho^(k-1) R((k-1) alpha) (P1 - A)` with the
    /// decay `rho` in `[0, 1]` and the turn `alpha` in `[-pi, pi]` (`pi`: a
    /// zig-zag through `A`, otherwise a spiral). Four parameters whatever
    /// `K`.
    Decaying,
}

impl Family {
    /// The name used in tables: `free` or `decaying`.
    pub fn as_str(self) -> &'static str {
        match self {
            Family::Free => "free",
            Family::Decaying => "decaying",
        }
    }
}

/// A family with its number of vertices, on a region round a centre: the map
/// from parameters to paths.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Shape {
    family: Family,
    vertices: usize,
    region: Region,
    center: LoadPoint,
}

impl Shape {
    /// The family `family` with `vertices` vertices, on `region` round the
    /// centre `center`.
    ///
    /// # Errors
    ///
    /// [`DesignError::Vertices`] unless `vertices` is in
    /// [`crate::model::ranges::VERTICES`].
    pub fn new(
        family: Family,
        vertices: usize,
        region: Region,
        center: LoadPoint,
    ) -> Result<Self, DesignError> {
        if !crate::model::ranges::VERTICES.contains(vertices) {
            return Err(DesignError::Vertices(vertices));
        }
        Ok(Self {
            family,
            vertices,
            region,
            center,
        })
    }

    /// The family.
    pub fn family(&self) -> Family {
        self.family
    }
    /// `K`, the vertices between `O` and `A`.
    pub fn vertices(&self) -> usize {
        self.vertices
    }
    /// The admissible box.
    pub fn region(&self) -> Region {
        self.region
    }
    /// The cycle centre `A`.
    pub fn center(&self) -> LoadPoint {
        self.center
    }

    /// The number of parameters.
    pub fn dimension(&self) -> usize {
        match self.family {
            Family::Free => 2 * self.vertices,
            Family::Decaying => 4,
        }
    }

    /// The parameter box `(lower, upper)`.
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let (x, y) = (self.region.x_max, self.region.y_max);
        match self.family {
            Family::Free => ([-x, -y].repeat(self.vertices), [x, y].repeat(self.vertices)),
            Family::Decaying => (vec![-x, -y, 0.0, -PI], vec![x, y, 1.0, PI]),
        }
    }

    /// The vertices `P1 ... PK` of the parameters, each clamped to the
    /// region (so that every path this returns is admissible).
    pub fn path(&self, params: &[f64]) -> Vec<LoadPoint> {
        match self.family {
            Family::Free => params
                .chunks_exact(2)
                .map(|c| self.region.clamp(c[0], c[1]))
                .collect(),
            Family::Decaying => {
                let first = self.region.clamp(params[0], params[1]);
                let (rho, alpha) = (params[2].clamp(0.0, 1.0), params[3]);
                let (a, d) = (
                    self.center,
                    (first.x() - self.center.x(), first.y() - self.center.y()),
                );
                (0..self.vertices)
                    .map(|k| {
                        // P1 itself, not A + (P1 - A) with its rounding.
                        if k == 0 {
                            return first;
                        }
                        let (s, c) = (k as f64 * alpha).sin_cos();
                        let scale = rho.powi(k as i32);
                        self.region.clamp(
                            a.x() + scale * (c * d.0 - s * d.1),
                            a.y() + scale * (s * d.0 + c * d.1),
                        )
                    })
                    .collect()
            }
        }
    }

    /// Parameters of this shape whose path starts `O -> I -> ...` with the
    /// single turning point `I` and then stays at `A` (free: the other
    /// vertices at `A`; decaying: no amplitude after `I`). A path of
    /// [`Initial::Via`] thus becomes a member of every family.
    pub fn through(&self, turning: LoadPoint) -> Vec<f64> {
        match self.family {
            Family::Free => {
                let mut p = vec![turning.x(), turning.y()];
                for _ in 1..self.vertices {
                    p.extend([self.center.x(), self.center.y()]);
                }
                p
            }
            Family::Decaying => vec![turning.x(), turning.y(), 0.0, PI],
        }
    }

    /// The free-family parameters of `path` padded to this shape's `K` by
    /// vertices at `A` (`None` for the decaying family or a longer path).
    pub fn padded(&self, path: &[LoadPoint]) -> Option<Vec<f64>> {
        if self.family != Family::Free || path.len() > self.vertices {
            return None;
        }
        let mut p: Vec<f64> = path.iter().flat_map(|v| [v.x(), v.y()]).collect();
        for _ in path.len()..self.vertices {
            p.extend([self.center.x(), self.center.y()]);
        }
        Some(p)
    }
}
