//! The granular step allocates nothing on one thread ("no allocation in the step
//! loop"): a counting global allocator around 1000 steps of a breaking-grain SHPB sample that
//! is quiet enough (a strain rate of 1/s, no output rows) for no neighbour-list rebuild, split
//! or series row to happen in the window, which are the events that may allocate. The only
//! test of this binary, so that no other test's allocations are counted.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use fractum::Run;
use fractum::Scene;
use fractum::models::granular::Simulation;

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

// SAFETY: forwards to the system allocator, counting.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

#[test]
fn a_granular_step_with_fracture_allocates_nothing_on_one_thread() {
    let set: Vec<String> = [
        "sample.box=[3e-3,3e-3,3e-3]",
        "sample.solid_fraction=0.45",
        "loading.strain_rate=1",
        "loading.end_strain=0.01",
        "output.every=1000000000",
        "output.vtk=0",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let scene = Scene::load(Path::new("scenes/shpb_sand.toml"), &set).unwrap();
    let mut sim = Simulation::new(scene, 1, &mut |_| {}).unwrap();
    // Past the first steps (the first neighbour build, the first grains that break).
    sim.advance(6000).unwrap();
    let bodies = sim.model.state.bodies.len();
    let broken = sim.model.broken_particles();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    sim.advance(1000).unwrap();
    let allocations = ALLOCATIONS.load(Ordering::Relaxed) - before;
    assert_eq!(sim.step(), 7000);
    assert_eq!(
        (sim.model.state.bodies.len(), sim.model.broken_particles()),
        (bodies, broken)
    );
    assert_eq!(allocations, 0, "{allocations} allocations in 1000 steps");
}
