//! Running out of memory (an address-space limit such as `prlimit --as`, or a full
//! machine) ends the process with one line on standard error and exit status 1, like any
//! other error, instead of the allocator's abort (SIGABRT, a core dump). The allocator is
//! the system's; only a failed allocation is handled here, without allocating.

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write;

/// The system allocator, ending the process cleanly when an allocation fails.
pub struct CleanOom;

/// Writes the message and exits: an allocation of `size` bytes failed.
fn out_of_memory(size: usize) -> ! {
    let mut digits = [0u8; 20];
    let mut i = digits.len();
    let mut n = size;
    loop {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    let mut err = std::io::stderr().lock();
    let _ = err.write_all(b"error: out of memory: an allocation of ");
    let _ = err.write_all(&digits[i..]);
    let _ = err.write_all(
        b" bytes failed (the memory this process may use is exhausted: the input is too large for it); nothing new was written\n",
    );
    std::process::exit(1)
}

// SAFETY: forwards every call to the system allocator; a null result (failure) never
// returns.
unsafe impl GlobalAlloc for CleanOom {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            out_of_memory(new_size);
        }
        p
    }
}
