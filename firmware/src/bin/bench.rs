//! Cycle benchmark firmware, run in `mspdebug`'s simulator by `firmware/msp430-bench`.
//!
//! Every case of `cases.rs` is bracketed by calls to [`bench_mark`] (a break point for the
//! driver, which reads the tracer's MCLK-cycle and instruction counters there); results go to
//! [`BENCH_RESULTS`] (read back with `md` and compared with the host's); the run ends in
//! [`bench_done`].
#![no_std]
#![no_main]

use acs_firmware as _;
use acs_firmware::elements;
#[cfg(feature = "group-step")]
use acs_firmware::{flight, tiles};

#[path = "../cases.rs"]
#[allow(dead_code)]
mod cases;

/// Capacity of [`BENCH_RESULTS`] in f32 words.
const MAX_RESULTS: usize = 64;

/// Results of every case, as f32 bit patterns, in order.
#[no_mangle]
static mut BENCH_RESULTS: [u32; MAX_RESULTS] = [0; MAX_RESULTS];
/// Number of results written.
#[no_mangle]
static mut BENCH_COUNT: u16 = 0;
/// Id of the current mark (even: begin of case id/2, odd: end).
#[no_mangle]
static mut BENCH_ID: u16 = 0;

/// Break point at the start and end of every measured section.
#[no_mangle]
#[inline(never)]
pub extern "C" fn bench_mark(id: u16) {
    // SAFETY: single-threaded; volatile so the call cannot be removed.
    unsafe { core::ptr::write_volatile(&raw mut BENCH_ID, id) }
}

/// Break point at the end of the run.
#[no_mangle]
#[inline(never)]
pub extern "C" fn bench_done() {
    // SAFETY: as above.
    unsafe { core::ptr::write_volatile(&raw mut BENCH_ID, 0xFFFF) }
}

struct Target {
    mark: u16,
}

impl cases::Sink for Target {
    #[inline(always)]
    fn input(&mut self, x: f32) -> f32 {
        core::hint::black_box(x)
    }
    #[inline(always)]
    fn keep(&mut self, x: f32) -> f32 {
        core::hint::black_box(x)
    }
    #[inline(always)]
    fn begin(&mut self, _name: &'static str) {
        bench_mark(self.mark);
        self.mark += 1;
    }
    #[inline(always)]
    fn end(&mut self) {
        bench_mark(self.mark);
        self.mark += 1;
    }
    #[inline(always)]
    fn out(&mut self, x: f32) {
        // SAFETY: single-threaded; index checked.
        unsafe {
            let n = core::ptr::read_volatile(&raw const BENCH_COUNT);
            if let Some(slot) = (*(&raw mut BENCH_RESULTS)).get_mut(usize::from(n)) {
                core::ptr::write_volatile(slot, x.to_bits());
            }
            core::ptr::write_volatile(&raw mut BENCH_COUNT, n + 1);
        }
    }
}

/// Entry point, called by the reset handler.
#[no_mangle]
pub extern "C" fn main() -> ! {
    // the benchmark's cases run far longer than the watchdog's interval: hold it (WDTPW |
    // WDTHOLD; the simulator runs without the watchdog device anyway)
    // SAFETY: 0x0120 is WDTCTL (see `acs_firmware::kick_watchdog`).
    unsafe { core::ptr::write_volatile(0x0120 as *mut u16, 0x5A80) };
    let mut t = Target { mark: 0 };
    cases::run(&mut t);
    bench_done();
    acs_firmware::fw_halt()
}

/// Panic handler of the benchmark image: coils off, then halt (the driver then finds fewer
/// marks than cases and fails). The flight image proves instead that it has no panic path
/// (`src/main.rs`).
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    acs_firmware::safe_state();
    acs_firmware::fw_halt()
}
