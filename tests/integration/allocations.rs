//! No allocation per increment (issue 9): an increment whose slip set does
//! not change, and a stick-only one, run on the buffers the contact keeps.
//! A counting allocator counts the allocations of the calling thread only,
//! so the other tests running beside these do not disturb the count.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use shakedown::stepping::operators;
use shakedown::{Advanced, Contact, Discretisation, LoadPoint, Material};

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

/// Allocations made by `k` increments of `span / k` from `c` towards `to`
/// (after one untimed increment that sets up the responses).
fn count(mut c: Contact, to: LoadPoint, k: usize) -> usize {
    let from = c.load();
    assert_eq!(
        c.advance(from.lerp(to, 1.0 / k as f64)),
        Ok(Advanced::Reached)
    );
    let before = allocations();
    for i in 2..=k {
        assert_eq!(
            c.advance(from.lerp(to, i as f64 / k as f64)),
            Ok(Advanced::Reached)
        );
        let inc = c.last_increment();
        assert!(inc.events.is_empty() && inc.segments == 1 && !inc.set_changed);
    }
    allocations() - before
}

#[test]
fn increments_without_events_allocate_nothing() {
    // The counter sees this thread's allocations.
    let before = allocations();
    std::hint::black_box(Vec::<u8>::with_capacity(8));
    assert_eq!(allocations(), before + 1);
    let disc = Discretisation::default();
    let fresh = || Contact::new(Material::paper(), operators(&disc));
    // Stick only, inside the diamond.
    assert_eq!(count(fresh(), LoadPoint::new(0.5, 0.5), 100), 0);
    // A partial slip set that holds: load to (2, 5.5), then a short step on
    // that no node reaches an event.
    let mut c = fresh();
    let target = LoadPoint::new(2.0, 5.5);
    for i in 1..=100 {
        c.advance(LoadPoint::ORIGIN.lerp(target, i as f64 / 100.0))
            .unwrap();
    }
    assert!(c.directions().iter().any(|d| d.is_slipping()));
    let mut dy = 0.02;
    let next = loop {
        let next = LoadPoint::new(2.0, 5.5 + dy);
        let mut probe = c.clone();
        assert_eq!(probe.advance(next), Ok(Advanced::Reached));
        let inc = probe.last_increment();
        if inc.events.is_empty() && inc.segments == 1 && !inc.set_changed {
            break next;
        }
        dy *= 0.5;
        assert!(dy > 1e-9, "no increment without an event");
    };
    assert_eq!(count(c, next, 100), 0);
}

/// A batch run driven with one report handed back each step (as `drive`
/// does) allocates nothing in the steps of a cycle whose slip sets it has
/// met before: the events' node lists and the report's buffers are reused.
#[test]
fn steps_of_a_repeating_cycle_allocate_nothing() {
    use shakedown::{Cycle, Initial, StepOptions, StepReport, Stepper};
    let mut s = Stepper::new(
        Material::paper(),
        Discretisation::new(64, 200).unwrap(),
        &Initial::Direct,
        Cycle::paper(5.5, 0.5 * std::f64::consts::PI).unwrap(),
        StepOptions::default(),
    );
    // As a batch run: the slip-zone topology of `SlipSetChanged` (for a
    // viewer) is a pass that builds new zone lists.
    s.set_zone_events(false);
    let mut report = StepReport::default();
    // Some cycles first: the slip sets of the cycle are then all known.
    while s.history().len() < 6 {
        s.step_into(&mut report).unwrap();
    }
    let cycles = s.history().len();
    let (mut steps, mut events, mut allocated) = (0, 0, 0);
    while s.history().len() == cycles {
        let before = allocations();
        s.step_into(&mut report).unwrap();
        // The step that closes the cycle records it (one allocation per
        // cycle, not per step).
        if s.history().len() == cycles {
            allocated += allocations() - before;
            steps += 1;
            events += report.events.len();
        }
    }
    assert!(steps > 100 && events > 10, "{steps} steps, {events} events");
    assert_eq!(allocated, 0, "over {steps} steps with {events} events");
}
