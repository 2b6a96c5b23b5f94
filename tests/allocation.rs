//! A step allocates nothing once its buffers have grown: counted by a
//! global allocator over whole runs, step by step (the run's observer
//! reads the count after each step). A step may allocate only where it
//! records a contact (the result's list grows, the contact's result is
//! kept); every other step after the warm-up must allocate nothing.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use nearmiss::run::{run_with, RunOptions, RunResult};
use nearmiss::scene::Scene;

/// The system allocator, counting each thread's allocations and
/// reallocations (a run here stays on its thread; rayon's workers, started
/// on the side as the pool comes up, allocate on theirs).
struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

/// This thread's allocations so far.
fn allocations() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

fn count() {
    // A thread being torn down has no count to keep.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

// SAFETY: every call is forwarded to the system allocator unchanged.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Runs `scene` on one thread (rayon's pool allocates to hand out work),
/// and returns its result and the allocations of each step.
fn allocations_per_step(scene: &Scene, steps: usize) -> (RunResult, Vec<u64>) {
    let mut counts = Vec::with_capacity(steps + 1);
    let mut last = allocations();
    let options = RunOptions { parallel: false, ..RunOptions::default() };
    let result = run_with(scene, options, &mut |_| {
        let now = allocations();
        counts.push(now - last);
        last = allocations();
    });
    (result, counts)
}

/// The steps (0-based) that hold a contact of `result`, a step of `dt`
/// covering `(s dt, (s + 1) dt]` (with a rounding's slack at each end).
fn contact_steps(result: &RunResult, dt: f64) -> Vec<usize> {
    let mut steps: Vec<usize> = result
        .contacts
        .iter()
        .flat_map(|c| {
            let s = c.time / dt;
            [(s - 1e-6).ceil() as usize, (s + 1e-6).ceil() as usize].map(|k| k.saturating_sub(1))
        })
        .collect();
    steps.sort_unstable();
    steps.dedup();
    steps
}

/// Every step after `warm_up` that allocates holds a contact; and there
/// are such steps without a contact (the check has something to check).
fn assert_only_contact_steps_allocate(scene: &Scene, dt: f64, steps: usize, warm_up: usize) {
    let (result, counts) = allocations_per_step(scene, steps);
    assert_eq!(counts.len(), steps, "{:?}", result.termination);
    let contacts = contact_steps(&result, dt);
    assert!(contacts.len() >= 4, "the scene should bounce: {} contacts", result.contacts.len());
    let quiet: Vec<usize> = (warm_up..steps).filter(|s| contacts.binary_search(s).is_err()).collect();
    assert!(quiet.len() > steps / 2, "{} steps without a contact", quiet.len());
    let allocating: Vec<(usize, u64)> =
        quiet.iter().map(|&s| (s, counts[s])).filter(|&(_, n)| n > 0).collect();
    assert!(
        allocating.is_empty(),
        "steps without a contact that allocate (step, allocations): {allocating:?}"
    );
}

#[test]
fn steps_allocate_nothing_after_warm_up() {
    bounce_steps_allocate_nothing_after_warm_up();
    #[cfg(feature = "rapier")]
    guard_steps_allocate_nothing_after_warm_up();
}

fn bounce_steps_allocate_nothing_after_warm_up() {
    // Six balls between two walls and a floor and ceiling, bouncing
    // elastically off them and each other: more than two bodies, so the
    // broad phase runs, and contacts stop bodies in time order.
    let balls: String = (0..6)
        .map(|i| {
            let (x, y) = (-1.2 + 0.5 * i as f64, 0.3 * ((i % 3) as f64 - 1.0));
            format!(
                r#"(name: "ball{i}", mesh: Icosphere(radius: 0.2, subdivisions: 1), density: 1.0, position: ({x}, {y}, 0.0), velocity: ({}, {}, 0.0)),"#,
                1.0 - 0.35 * i as f64,
                0.7 - 0.25 * i as f64
            )
        })
        .collect();
    let scene = Scene::from_ron_str(&format!(
        r#"Scene(name: "balls", dt: 0.01, steps: 1500, on_contact: Bounce(restitution: 1.0), bodies: [
            {balls}
            (name: "left", mesh: Box(half_extents: (0.5, 2.0, 2.0)), position: (-2.5, 0.0, 0.0), fixed: true),
            (name: "right", mesh: Box(half_extents: (0.5, 2.0, 2.0)), position: (2.5, 0.0, 0.0), fixed: true),
            (name: "floor", mesh: Box(half_extents: (2.0, 0.5, 2.0)), position: (0.0, -2.5, 0.0), fixed: true),
            (name: "ceiling", mesh: Box(half_extents: (2.0, 0.5, 2.0)), position: (0.0, 2.5, 0.0), fixed: true),
        ])"#
    ))
    .unwrap();
    assert_only_contact_steps_allocate(&scene, 0.01, 1500, 100);
}

#[cfg(feature = "rapier")]
#[path = "support/rapier_app.rs"]
mod rapier_app;
#[cfg(feature = "rapier")]
rapier_app!(rapier3d_f64);

#[cfg(feature = "rapier")]
fn guard_steps_allocate_nothing_after_warm_up() {
    use rapier3d_f64::prelude::*;
    // A rapier application (`Simulate` is the same guard on rapier's
    // step): a crate resting on a floor, which rapier solves every step
    // and the guard sweeps every step, and a kinematic wall arriving to
    // push it. What rapier's own step allocates is counted apart (inside
    // the closure the guard calls) and taken out.
    let parameters = IntegrationParameters { dt: 1.0 / 60.0, ..Default::default() };
    let (mut bodies, mut colliders, handles) = sleeping_crate_and_wall();
    // On this thread only (rayon's pool allocates to hand out work).
    let options = nearmiss::guard::GuardOptions { parallel: false, ..Default::default() };
    let mut guard = nearmiss::guard::Guard::new(&bodies, &mut colliders, &handles, &parameters, options)
        .expect("cuboids");
    let mut rapier = Rapier::new();
    let (mut quiet, mut acted) = (Vec::new(), 0);
    for step in 0..120 {
        let mut in_rapier = 0;
        let before = allocations();
        let events = guard
            .step(&mut bodies, |bodies, dt| {
                let start = allocations();
                rapier.step(bodies, &mut colliders, Vector::new(0.0, 0.0, -9.81), &parameters, dt);
                in_rapier += allocations() - start;
            })
            .expect("decided");
        let by_guard = allocations() - before - in_rapier;
        // The events the guard reports are its answer (a list, when it acts).
        if !events.is_empty() {
            acted += 1;
        } else if step >= 10 {
            quiet.push((step, by_guard));
        }
    }
    assert!(quiet.len() > 60, "{} quiet steps", quiet.len());
    let allocating: Vec<_> = quiet.iter().filter(|&&(_, n)| n > 0).collect();
    assert!(
        allocating.is_empty(),
        "guard steps without an event that allocate (step, allocations): {allocating:?}; {acted} steps acted"
    );
}
