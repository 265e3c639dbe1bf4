//! Resource bounds of the scenario parser (issue #17): memory that grows linearly with
//! the input, measured with a counting allocator (this test binary's only test, so no
//! other test allocates while it measures).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use ellipsoid_core::scenario;

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

const SCENE: &str = "[body]\na = 0.025\nc = 0.0175\nmass = 0.05\ninertia = \"uniform\"\n[contact]\nmodel = \"frictionless\"\n[output]\nt_end = 1.0\n";

/// Peak memory above the baseline while `f` runs [bytes].
fn peak_during(f: impl FnOnce()) -> usize {
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    f();
    PEAK.load(Ordering::Relaxed) - base
}

#[test]
fn a_long_array_given_by_an_override_takes_memory_linear_in_its_length() {
    // Before the fix every element's origin held its own copy of the whole override:
    // 2·10⁴ elements of "1e-5," (120 kB) took 2.4 GB; now about 2 MB.
    let n = 20_000;
    let times: Vec<String> = (0..n).map(|i| format!("{}", i as f64 * 1e-5)).collect();
    let set = format!("output.times=[{}]", times.join(","));
    let peak = peak_during(|| {
        let s = scenario::parse(SCENE, "<limits>", &[set.as_str()]).expect("valid");
        assert_eq!(s.scene.sample_times.len(), n);
    });
    assert!(
        peak < 40 * set.len() + (8 << 20),
        "peak {peak} bytes for an override of {} bytes",
        set.len()
    );
}
