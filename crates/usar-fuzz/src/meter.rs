//! An allocator that counts, per thread, the bytes a loader holds: the harness reads the peak
//! an input reached, so a small file that makes a loader allocate gigabytes is a finding even
//! when the machine has the memory. Install it in the binary that fuzzes:
//!
//! ```text
//! #[global_allocator]
//! static METER: usar_fuzz::meter::MeteredAllocator = usar_fuzz::meter::MeteredAllocator;
//! ```

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    static CURRENT: Cell<usize> = const { Cell::new(0) };
    static PEAK: Cell<usize> = const { Cell::new(0) };
}

/// The system allocator, counting this thread's live bytes and their peak.
pub struct MeteredAllocator;

fn grow(n: usize) {
    let _ = CURRENT.try_with(|c| {
        let now = c.get().saturating_add(n);
        c.set(now);
        let _ = PEAK.try_with(|p| p.set(p.get().max(now)));
    });
}

fn shrink(n: usize) {
    let _ = CURRENT.try_with(|c| c.set(c.get().saturating_sub(n)));
}

// SAFETY: every call is forwarded to `System` unchanged; the counters only observe sizes.
unsafe impl GlobalAlloc for MeteredAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grow(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grow(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) };
        shrink(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            shrink(layout.size());
            grow(new_size);
        }
        p
    }
}

/// Starts measuring this thread: the peak is reset to what it holds now.
pub fn reset_peak() {
    let now = CURRENT.with(Cell::get);
    PEAK.with(|p| p.set(now));
}

/// Bytes this thread held at its peak since [`reset_peak`], above what it held then.
pub fn peak_since(start: usize) -> usize {
    PEAK.with(Cell::get).saturating_sub(start)
}

/// Bytes this thread holds now.
pub fn current() -> usize {
    CURRENT.with(Cell::get)
}
