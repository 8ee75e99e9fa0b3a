//! Building a stepper: from the unloaded state or an initial slip, from a
//! contact and waypoints, and from the contact at the cycle centre.

use super::*;

impl Stepper {
    /// A run from the unloaded state (or the initial slip at `A`) along
    /// `initial`, then the cycle.
    pub fn new(
        material: Material,
        disc: Discretisation,
        initial: &Initial,
        cycle: Cycle,
        options: StepOptions,
    ) -> Self {
        Self::with_operators(operators(&disc), material, disc, initial, cycle, options)
    }

    /// As [`Stepper::new`], with operators `H` and `|D|` already built by
    /// [`operators`] for the same number of nodes, so that runs can share
    /// them.
    ///
    /// An [`Initial::Optimal`] that was not resolved is not an error here:
    /// the first [`Stepper::step`] reports [`StepError::UnresolvedOptimal`].
    pub fn with_operators(
        ops: Arc<Operators>,
        material: Material,
        disc: Discretisation,
        initial: &Initial,
        cycle: Cycle,
        options: StepOptions,
    ) -> Self {
        let mut contact = Contact::new(material, ops);
        let mut unresolved = None;
        let slip = match initial {
            Initial::Slip { slip, .. } => Some(Arc::clone(slip)),
            Initial::Optimal => {
                unresolved = Some(StepError::UnresolvedOptimal);
                None
            }
            _ => None,
        };
        if let Some(slip) = slip {
            contact.set_slip(&slip);
            contact.set_load_elastic(cycle.center());
        }
        let mut waypoints = initial.waypoints_to(cycle.center());
        waypoints.push(cycle.start());
        let mut stepper = Self::from_contact(contact, &waypoints, cycle, disc, options);
        stepper.unresolved = unresolved;
        stepper
    }

    /// Continue from a prepared contact (e.g. the state at `A`, which does
    /// not depend on `lambda`) through `waypoints` into the cycle.
    pub fn from_contact(
        contact: Contact,
        waypoints: &[LoadPoint],
        cycle: Cycle,
        disc: Discretisation,
        options: StepOptions,
    ) -> Self {
        let mut w = vec![contact.load()];
        w.extend_from_slice(waypoints);
        let transient = segments(&w, disc.transient_step());
        let nodes = contact.nodes();
        let rotation = contact.rotation();
        let contact_dirs = contact.directions().to_vec();
        let phase = if transient.is_empty() {
            Phase::Cycle {
                cycle: 1,
                increment: 0,
            }
        } else {
            Phase::Transient {
                segment: 0,
                increment: 0,
            }
        };
        let steps = disc.steps_per_cycle();
        let cycle_points = (0..=steps)
            .map(|i| cycle.at(cycle_angle(i as f64, steps)))
            .collect();
        Self {
            contact,
            transient,
            cycle,
            cycle_points,
            disc,
            options,
            phase,
            current: CycleRecord::new(1, nodes),
            rotation_at_cycle_start: rotation,
            history: Vec::new(),
            status: Status::Running,
            increments: 0,
            unresolved: None,
            zones: slip_zones(&contact_dirs),
            zone_dirs: contact_dirs,
            zone_events: true,
            event_reports: true,
            resume: None,
            spare_nodes: Vec::new(),
            safe_state: None,
            safe_state_setup: None,
            runs: StraightRuns::new(steps),
        }
    }

    /// The contact after the transient up to the cycle centre `A` (the
    /// `A -> C` entry not included): it depends on the initial path only.
    ///
    /// It is [`AtCenter::Ready`] with the contact at `A`, or
    /// [`AtCenter::Ended`] when the transient itself ended the run (gross
    /// slip or separation before `A`).
    ///
    /// # Errors
    ///
    /// [`StepError::NotSettled`] when an increment of the transient fails
    /// numerically; [`StepError::UnresolvedOptimal`] for an
    /// [`Initial::Optimal`] that was not resolved; [`StepError::Param`] for
    /// a centre out of range.
    pub fn prepare_at_center(
        ops: Arc<Operators>,
        material: Material,
        disc: Discretisation,
        initial: &Initial,
        center: LoadPoint,
        options: StepOptions,
    ) -> Result<AtCenter, StepError> {
        let dummy = Cycle::new(center, 0.0, 0.0, 0.0)?;
        let mut s = Self::with_operators(ops, material, disc, initial, dummy, options);
        s.zone_events = false;
        s.event_reports = false;
        s.runs.on = true;
        // The dummy cycle starts at A, so the transient ends exactly there.
        drive(&mut s, Goal::TransientEnd, &mut Silent)?;
        if let Status::Ended(outcome) = s.status {
            return Ok(AtCenter::Ended(outcome));
        }
        Ok(AtCenter::Ready(Box::new(s.contact)))
    }

    /// Start the cycle from a contact prepared at the centre `A`.
    pub fn from_center(
        contact: Contact,
        cycle: Cycle,
        disc: Discretisation,
        options: StepOptions,
    ) -> Self {
        Self::from_contact(contact, &entry_waypoints(&cycle), cycle, disc, options)
    }
}
