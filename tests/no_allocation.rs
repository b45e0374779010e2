//! The README's promise "no allocation per sample", counted: a global allocator that counts the
//! allocations of the calling thread, around `Pipeline::update` over every preset (a rest window
//! measured, rests tracked with and without a speed, a gap, a bad reading) and around a block.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use gyrocore::{Outputs, Pipeline, Preset, StaticBias};

struct Counting;

thread_local! {
    // const-initialised: reading it allocates nothing, so the allocator can use it
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|n| n.set(n.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|n| n.set(n.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

fn allocations_in(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

/// 120 s at 100 Hz: a 20 s rest, then turns, a stop from 60 to 70 s, a 3 s gap at 90 s and a NaN.
fn drive() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..12_000)
        .map(|i| i as f64 * 0.01 + if i >= 9_000 { 3.0 } else { 0.0 })
        .collect();
    let moving = |t: f64| (20.0..60.0).contains(&t) || t >= 70.0;
    let rate = t
        .iter()
        .enumerate()
        .map(|(i, &t)| match (i, moving(t)) {
            (5_000, _) => f64::NAN,
            (_, true) => 0.002 + 0.2 * (t / 4.0).sin(),
            (_, false) => 0.002 + 1e-4 * ((i * 7919) % 13) as f64 / 13.0,
        })
        .collect();
    let speed = t
        .iter()
        .map(|&t| if moving(t) { 8.0 } else { 0.0 })
        .collect();
    (t, rate, speed)
}

#[test]
fn no_sample_allocates_with_any_preset() {
    let (t, rate, speed) = drive();
    for preset in Preset::ALL {
        for with_speed in [false, true] {
            let mut config = preset.config();
            config.correction.bias = StaticBias::Leading { duration: 20.0 };
            let mut pipeline = Pipeline::new(config).unwrap();
            let mut last = 0.0;
            let n = allocations_in(|| {
                for k in 0..t.len() {
                    let s = if with_speed { speed[k] } else { f64::NAN };
                    last = pipeline.update_with_speed(t[k], rate[k], None, s).heading;
                }
            });
            assert!(last.is_finite(), "{}", preset.name());
            assert_eq!(
                n,
                0,
                "{} (speed: {with_speed}) allocated {n} times over {} samples",
                preset.name(),
                t.len()
            );
        }
    }
}

#[test]
fn a_block_allocates_nothing() {
    let (t, mut rate, _) = drive();
    rate[5_000] = 0.0; // a block refuses a NaN
    let mut config = Preset::Tracked.config();
    config.correction.bias = StaticBias::Leading { duration: 20.0 };
    let mut pipeline = Pipeline::new(config).unwrap();
    let (mut h, mut r, mut d) = (vec![0.0; t.len()], vec![0.0; t.len()], vec![0.0; t.len()]);
    let n = allocations_in(|| {
        pipeline
            .process_block(&t, &rate, None, Outputs::all(&mut h, &mut r, &mut d))
            .unwrap();
    });
    assert_eq!(n, 0, "a block of {} samples allocated {n} times", t.len());
}
