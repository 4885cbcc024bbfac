//! # acs-firmware: the acs flight code on an MSP430 (msp430-none-elf)
//!
//! - [`rt`]: reset handler (stack pointer, watchdog started, `.data` copy, `.bss` zero, stack
//!   painting for the high-water mark) and the interrupt vector table.
//! - [`tiles`]: the tile bus in the HAL's raw formats over RAM mailboxes that the simulator, the
//!   processor-in-the-loop host or a debugger read and write.
//! - [`flight`]: the flight loop's set-up, the ground uplink and the published step results.
//! - [`mmio`]: volatile register access for the MSP430 peripheral drivers of
//!   [`acs::hal::msp430`], and the LPM3 sleep of the control period.
//! - [`periph`]: the part's clocks, control period (Timer_A, LPM3) and inter-node link (USCI_A0)
//!   of the flight node images (feature `pil` off), and their interrupt vectors.
//! - [`element_flash`]: the reference node's uplinked element set kept in two flash segments
//!   (flight build).
//! - [`safe_state`]: the hook that puts every actuator in its safe state; unexpected interrupts
//!   call it and then halt, and the watchdog resets the part ([`kick_watchdog`]).
//!
//! The binaries: `acs-firmware` (the flight loop, `src/main.rs`) and `bench` (the cycle benchmark
//! driven by `firmware/msp430-bench` in `mspdebug`'s simulator).
#![no_std]
#![feature(asm_experimental_arch)]
#![feature(optimize_attribute)]

pub mod element_flash;
pub mod elements;
pub mod flight;
pub mod flight_elements;
pub mod node_link;
pub mod mmio;
pub mod periph;
pub mod rt;
pub mod tiles;

// The EABI helper functions (`__mspabi_*`, soft-float and integer), linked in by reference.
use msp430_eabi as _;

/// Puts every actuator in its safe state: magnetorquers off, reaction wheels holding the
/// momentum last commanded (a wheel stopped while it carries the satellite's momentum would spin
/// the satellite).
///
/// This is the hook the unexpected-interrupt handler calls before halting. It must not fail and
/// must not depend on any state that a fault may have corrupted: it writes constant commands
/// straight to the coil drivers ([`tiles::coils_off`]; in the flight build, feature `pil` off,
/// also Timer_B's coil channels off, [`acs::hal::msp430::tile_bus::coils_off`]).
#[inline(never)]
pub fn safe_state() {
    tiles::coils_off();
    #[cfg(not(feature = "pil"))]
    acs::hal::msp430::tile_bus::coils_off(&mut mmio::Mmio);
}

/// The start of a control period: on the part, where the loop waits for the period timer; the
/// benchmark and the processor-in-the-loop host stop here (breakpoint on the symbol) to write
/// the next readings and uplink and read the last commands.
#[no_mangle]
#[inline(never)]
pub extern "C" fn fw_period_start() {
    // SAFETY: `nop` has no effect; it keeps the function's body (and its symbol) in the image.
    unsafe { core::arch::asm!("nop") };
}

/// Stops the core: interrupts off, then an endless loop without kicking the watchdog, which
/// resets the part within its interval (1 s, [`rt::WDT_KICK`]): the flight image starts again
/// (reset, element set, the loop in detumble). The benchmark and the simulator stop on the
/// symbol `fw_halt`.
#[no_mangle]
#[inline(never)]
pub extern "C" fn fw_halt() -> ! {
    // SAFETY: `dint` only clears the general interrupt enable bit.
    unsafe { core::arch::asm!("dint", "nop") };
    loop {
        core::hint::spin_loop();
    }
}

/// Restarts the watchdog's interval ([`rt::WDT_KICK`]): the flight loop calls it before and
/// after every step, so that the part is reset only if the loop stops stepping.
#[inline(always)]
pub fn kick_watchdog() {
    // SAFETY: 0x0120 is the MSP430x4xx's WDTCTL register (SLAU056); a 16-bit volatile write
    // with the password restarts the counter and changes nothing else.
    unsafe { core::ptr::write_volatile(0x0120 as *mut u16, rt::WDT_KICK) };
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
