//! # acs-firmware: the acs flight code on an MSP430 (msp430-none-elf)
//!
//! - [`rt`]: reset handler (stack pointer, watchdog off, `.data` copy, `.bss` zero, stack
//!   painting for the high-water mark) and the interrupt vector table.
//! - [`tiles`]: the tile drivers, stubbed: sensors read from and actuator commands written to RAM
//!   mailboxes that the simulator (or a debugger) can read and write.
//! - [`safe_state`]: the hook that puts every actuator in its safe state; the panic handler and
//!   unexpected interrupts call it and then halt.
//!
//! The binaries: `acs-firmware` (the flight loop, `src/main.rs`) and `bench` (the cycle benchmark
//! driven by `firmware/msp430-bench` in `mspdebug`'s simulator).
#![no_std]
#![feature(asm_experimental_arch)]

pub mod elements;
#[cfg(feature = "acs-loop")]
pub mod flight;
#[cfg(feature = "ground-init")]
pub mod flight_elements;
pub mod rt;
pub mod tiles;

// The EABI helper functions (`__mspabi_*`, soft-float and integer), linked in by reference.
use msp430_eabi as _;

/// Puts every actuator in its safe state: reaction wheels commanded to zero momentum (they spin
/// down), magnetorquers off (zero current).
///
/// This is the hook the panic handler and the unexpected-interrupt handler call before halting.
/// It must not fail and must not depend on any state that a fault may have corrupted: it writes
/// constant commands straight to the actuator drivers ([`tiles::command_safe`]).
#[inline(never)]
pub fn safe_state() {
    tiles::command_safe();
}

/// Halts the core for good: interrupts off, then an endless loop (on the real part the watchdog
/// is off, so this stays here until a power cycle or a ground reset). The benchmark and the
/// simulator stop on the symbol `fw_halt`.
#[no_mangle]
#[inline(never)]
pub extern "C" fn fw_halt() -> ! {
    // SAFETY: `dint` only clears the general interrupt enable bit.
    unsafe { core::arch::asm!("dint", "nop") };
    loop {
        core::hint::spin_loop();
    }
}

/// Entered from an unexpected interrupt vector (see [`rt`]): safe state, then halt.
#[no_mangle]
pub extern "C" fn fw_unexpected_interrupt() -> ! {
    safe_state();
    fw_halt()
}

/// `abort` (called by compiler-inserted traps and some `core` paths; the EABI crate leaves it to
/// the firmware): safe state, then halt.
#[no_mangle]
pub extern "C" fn abort() -> ! {
    safe_state();
    fw_halt()
}

/// Panic handler: actuators to their safe state ([`safe_state`]), then halt ([`fw_halt`]).
/// The flight library is written not to panic (clippy denies every panicking construct there);
/// this is the last line of defence for what the compiler still inserts (bounds checks it could
/// not remove, overflow in debug builds).
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    safe_state();
    fw_halt()
}
