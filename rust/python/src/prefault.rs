//! Fresh output arrays fault their pages in on another core while this one computes.
//!
//! A new array's memory is not there until it is first written: the kernel then maps and zeroes
//! each page. For the pipeline's three outputs that cost the writing loop about 1.5 ns per
//! sample at 10^7 samples (`benches/compare.py`), a quarter of its time. A helper thread asks the
//! kernel for the pages (`MADV_POPULATE_WRITE`, Linux 5.14) a stretch ahead of the loop, in the
//! order the loop writes them. It never reads or writes the arrays themselves, so it cannot
//! disturb what the loop writes; where the call is not supported it fails and nothing changes.

use std::sync::atomic::{AtomicBool, Ordering};

/// Arrays shorter than this are written before a helper thread would have started.
const MIN_SAMPLES: usize = 1 << 18;

/// How much of each array the helper populates at a time [bytes]: one huge page.
const STRETCH: usize = 2 << 20;

/// The address ranges of some output arrays, as `(start, length in bytes)`.
pub(crate) struct Pages(Vec<(usize, usize)>);

impl Pages {
    /// The pages of `outputs`, to be faulted in while they are written.
    pub(crate) fn of<'a>(outputs: impl Iterator<Item = &'a &'a mut [f64]>) -> Self {
        Pages(
            outputs
                .map(|o| (o.as_ptr() as usize, std::mem::size_of_val(&**o)))
                .collect(),
        )
    }

    /// Runs `work` while a helper thread faults in the pages (see the module doc).
    pub(crate) fn while_faulting_in<R>(&self, work: impl FnOnce() -> R) -> R {
        if !cfg!(target_os = "linux") || self.longest() < MIN_SAMPLES * std::mem::size_of::<f64>() {
            return work();
        }
        // Set once the work returns: pages it never reached (a call stopped by a bad sample or a
        // Ctrl-C) are not worth the wait (1 to 3 s for the rest of three outputs of 10^8 samples).
        let done = AtomicBool::new(false);
        std::thread::scope(|s| {
            // Without a thread (the system refused one) the loop faults the pages in itself.
            let _helper = std::thread::Builder::new().spawn_scoped(s, || self.populate(&done));
            let result = work();
            done.store(true, Ordering::Relaxed);
            result
        })
    }

    /// The length of the longest range [bytes].
    fn longest(&self) -> usize {
        self.0.iter().map(|&(_, len)| len).max().unwrap_or(0)
    }

    /// Populates the ranges stretch by stretch, interleaved, until `done`.
    fn populate(&self, done: &AtomicBool) {
        let Some(page) = page_size() else {
            return;
        };
        for offset in (0..self.longest()).step_by(STRETCH) {
            if done.load(Ordering::Relaxed) {
                return;
            }
            for &(start, len) in &self.0 {
                if offset < len {
                    populate_range(page, start + offset, STRETCH.min(len - offset));
                }
            }
        }
    }
}

/// The system's page size [bytes].
#[cfg(target_os = "linux")]
fn page_size() -> Option<usize> {
    // SAFETY: sysconf only reads a system constant.
    match unsafe { libc::sysconf(libc::_SC_PAGESIZE) } {
        p if p > 0 => Some(p as usize),
        _ => None,
    }
}

#[cfg(not(target_os = "linux"))]
fn page_size() -> Option<usize> {
    None
}

#[cfg(target_os = "linux")]
fn populate_range(page: usize, start: usize, len: usize) {
    // madvise needs a page-aligned start; the page holding the array's first byte is mapped.
    let aligned = start & !(page - 1);
    // SAFETY: MADV_POPULATE_WRITE only maps pages of the range (as a write would) and leaves
    // their contents as they are; an unmapped or unsupported range returns an error, ignored.
    unsafe {
        libc::madvise(
            aligned as *mut libc::c_void,
            len + (start - aligned),
            libc::MADV_POPULATE_WRITE,
        );
    }
}

#[cfg(not(target_os = "linux"))]
fn populate_range(_page: usize, _start: usize, _len: usize) {}
