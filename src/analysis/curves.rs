//! `lambda_2` for a sweep's model, as the explorer's views need it: at one
//! phase (the sweep view's vertical line), along the phases of a map (the
//! regime map's curve), and the optimal initial slip a run opened from a
//! map starts with (model.md sections 7.3 and 7.4).
//!
//! Headless and blocking: a front end calls these on a thread of its own.
//! The curve here is solved one phase after another, not on rayon's pool
//! as [`crate::analysis::limit_curve`] is, because a front end runs it
//! beside a sweep whose runs fill that pool: queued behind them, the
//! curve would arrive only after the map.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crate::analysis::limit::{cycle_limit, shakedown_limit, Limit, LimitError, DEFAULT_SAMPLES};
use crate::analysis::sweep::SweepSpec;
use crate::model::path::Initial;
use crate::model::{Cycle, Discretisation, Material};

/// `lambda_2` and its optimal slip for the cycles of `spec` (its model,
/// centre and slope) at `phase`, with `samples` points on an elliptical
/// cycle.
///
/// # Errors
///
/// As [`shakedown_limit`].
pub fn limit_at(spec: &SweepSpec, phase: f64, samples: usize) -> Result<Limit, LimitError> {
    if spec.polyline().is_some() {
        // A polyline's own vertices, exactly (model.md section 5.4).
        let job = crate::analysis::sweep::Job {
            index: 0,
            load_factor: 0.0,
            phase,
            initial: 0,
        };
        return cycle_limit(&spec.material(), &spec.cycle(&job)?, &spec.disc(), samples);
    }
    shakedown_limit(
        &spec.material(),
        spec.center(),
        spec.slope(),
        phase,
        &spec.disc(),
        samples,
    )
}

/// `lambda_2` at each of `phases` for the cycles of `spec`, in order, one
/// programme after another; `None` where a programme failed. Once
/// `cancel` is raised the phases left are not solved and the curve comes
/// back short, which a caller that cancelled does not read.
pub fn lambda2_curve(
    spec: &SweepSpec,
    phases: &[f64],
    samples: usize,
    cancel: &AtomicBool,
) -> Vec<Option<f64>> {
    let mut curve = Vec::with_capacity(phases.len());
    lambda2_points(spec, phases, samples, cancel, |_, l| {
        curve.push(l);
        true
    });
    curve
}

/// [`lambda2_curve`] point by point: `point(i, lambda_2)` is called as
/// soon as the programme at `phases[i]` is solved, so a front end draws
/// the curve as it arrives. It stops before the next phase once `cancel`
/// is raised or `point` returns false (its receiver is gone).
pub fn lambda2_points(
    spec: &SweepSpec,
    phases: &[f64],
    samples: usize,
    cancel: &AtomicBool,
    mut point: impl FnMut(usize, Option<f64>) -> bool,
) {
    for (i, &phase) in phases.iter().enumerate() {
        if cancel.load(Ordering::Relaxed) {
            return;
        }
        let l2 = limit_at(spec, phase, samples).ok().map(|l| l.load_factor);
        if !point(i, l2) {
            return;
        }
    }
}

/// The optimal slip of `limit` as an initial condition: the run starts at
/// the centre `A` with this slip and no transient (model.md section 7.4).
pub fn optimal_from(limit: &Limit) -> Initial {
    Initial::Slip {
        name: "optimal".into(),
        slip: Arc::new(limit.slip.clone()),
    }
}

/// `initial` ready for a stepper: [`Initial::Optimal`] becomes the optimal
/// slip of the `lambda_2` problem for `cycle` (solved with
/// [`DEFAULT_SAMPLES`], or taken from `known` when that is the limit of
/// the same cycle direction on the same nodes); every other path is
/// returned as it is.
///
/// # Errors
///
/// As [`shakedown_limit`], when the programme has to be solved.
pub fn resolve_initial(
    initial: &Initial,
    material: &Material,
    cycle: &Cycle,
    disc: &Discretisation,
    known: Option<&Limit>,
) -> Result<Initial, LimitError> {
    if *initial != Initial::Optimal {
        return Ok(initial.clone());
    }
    if let Some(limit) = known.filter(|l| l.slip.len() == disc.nodes()) {
        return Ok(optimal_from(limit));
    }
    let limit = cycle_limit(material, cycle, disc, DEFAULT_SAMPLES)?;
    Ok(optimal_from(&limit))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::analysis::case::{Case, CaseParams};
    use crate::analysis::sweep::SweepLists;

    fn spec(phases: &[f64]) -> SweepSpec {
        let case = Case::from_params(&CaseParams {
            nodes: 32,
            steps: 100,
            ..CaseParams::default()
        })
        .unwrap();
        let lists = SweepLists {
            load_factors: vec![5.0],
            phases: phases.to_vec(),
            initials: vec![Initial::Direct],
        };
        SweepSpec::over(&case, &lists).unwrap()
    }

    /// In phase the cycle is a line through `A`, and model.md section 2.3
    /// gives `lambda_2` of the paper's Fig. 3 case as about 4.90 (the
    /// README's 4.899): the curve's first point is that number, and each
    /// point is the one-phase limit.
    #[test]
    fn the_curve_is_the_limit_at_each_phase() {
        let phases = [0.0, PI / 2.0];
        let s = spec(&phases);
        let curve = lambda2_curve(&s, &phases, 16, &AtomicBool::new(false));
        assert_eq!(curve.len(), 2);
        for (c, &phase) in curve.iter().zip(&phases) {
            let one = limit_at(&s, phase, 16).unwrap().load_factor;
            assert_eq!(c.unwrap().to_bits(), one.to_bits());
        }
        let in_phase = curve[0].unwrap();
        assert!((in_phase - 4.9).abs() < 0.05, "{in_phase}");
    }

    #[test]
    fn a_cancelled_curve_solves_nothing() {
        let s = spec(&[0.0]);
        assert!(lambda2_curve(&s, &[0.0, 0.1], 16, &AtomicBool::new(true)).is_empty());
    }

    /// Each point is handed on as it is solved, with its index, and the
    /// curve stops once its receiver says so.
    #[test]
    fn the_points_arrive_one_by_one_until_refused() {
        let phases = [0.0, PI / 4.0, PI / 2.0];
        let s = spec(&phases);
        let mut seen = Vec::new();
        lambda2_points(&s, &phases, 16, &AtomicBool::new(false), |i, l| {
            seen.push((i, l));
            i < 1
        });
        let curve = lambda2_curve(&s, &phases[..2], 16, &AtomicBool::new(false));
        assert_eq!(seen, vec![(0, curve[0]), (1, curve[1])]);
    }

    /// The optimal initial slip is the limit's slip, mean zero, whether it
    /// is solved or taken from a limit already known; other paths pass.
    #[test]
    fn optimal_resolves_to_the_limits_slip() {
        let s = spec(&[0.0]);
        let case = Case::from_params(&CaseParams {
            nodes: 32,
            steps: 100,
            ..CaseParams::default()
        })
        .unwrap();
        let cycle = Cycle::new(s.center(), 5.0, s.slope(), 0.0).unwrap();
        let limit = limit_at(&s, 0.0, DEFAULT_SAMPLES).unwrap();
        let solved = resolve_initial(
            &Initial::Optimal,
            &case.material(),
            &cycle,
            &case.disc(),
            None,
        )
        .unwrap();
        let known = resolve_initial(
            &Initial::Optimal,
            &case.material(),
            &cycle,
            &case.disc(),
            Some(&limit),
        )
        .unwrap();
        for init in [&solved, &known] {
            let Initial::Slip { name, slip } = init else {
                panic!("not a slip: {init:?}");
            };
            assert_eq!(name, "optimal");
            assert_eq!(slip.len(), 32);
            assert!(slip.iter().sum::<f64>().abs() < 1e-9);
            for (a, b) in slip.iter().zip(&limit.slip) {
                assert!((a - b).abs() < 1e-9);
            }
        }
        let oa = case.initial().clone();
        assert_eq!(
            resolve_initial(&oa, &case.material(), &cycle, &case.disc(), None).unwrap(),
            oa
        );
    }
}
