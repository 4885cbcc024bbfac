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
//! - [`CycleDelay`]: the busy wait of [`acs::hal::TileBus::delay_us`] (the coils' decay before
//!   the attitude node reads its tiles).
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
pub mod mmio;
pub mod node_link;
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

/// The resets since power-on: the count and its complement, in RAM that the reset handler
/// neither loads nor zeroes nor paints (`.noinit`, `link.x`), so that it survives a watchdog or
/// software reset (the RAM keeps its contents through a PUC) and not a power-on reset (RAM
/// undefined: a pair that is not a count and its complement, which leaves 1 chance in 65 536 of
/// taking noise for a count).
#[no_mangle]
#[link_section = ".noinit"]
static mut BOOTS: core::mem::MaybeUninit<[u16; 2]> = core::mem::MaybeUninit::uninit();

/// Counts this start: 0 after a power-on reset, one more than the last start's after any other
/// reset ([`BOOTS`]); the attitude node reports it in STATUS
/// (`acs::attitude_node::AttitudeNode::set_boot_count`).
#[inline(never)]
pub fn boot_count() -> u16 {
    let boots = (&raw mut BOOTS).cast::<[u16; 2]>();
    // SAFETY: `BOOTS` is this function's alone, aligned, 4 bytes of RAM; volatile, so that its
    // contents are read as the RAM holds them (any bit pattern is a valid `[u16; 2]`).
    let [count, check] = unsafe { core::ptr::read_volatile(boots) };
    let now = if check == !count {
        count.wrapping_add(1)
    } else {
        0
    };
    // SAFETY: as above.
    unsafe { core::ptr::write_volatile(boots, [now, !now]) };
    now
}

/// The images' timer for short waits ([`acs::hal::TileBus::delay_us`]: the attitude node's wait
/// between switching the coils off and reading the tiles): a busy loop of 4 MCLK cycles an
/// iteration, 2 iterations a microsecond, so 8 cycles a µs, 1.00058 µs at MCLK = 7 995 392 Hz
/// (the FLL+ locked to the crystal, [`periph`]): never shorter than asked (up to 2³¹ µs, 36
/// minutes; a longer wait saturates there). The 5 ms wait is
/// 10 000 iterations, 40 000 cycles on the part (SLAU056 "Instruction Cycles and Lengths":
/// `sub #1, Rn` and `nop`, constant-generator sources to a register, 1 cycle each; a jump 2).
/// mspdebug's simulator counts 6 cycles an iteration (60 002 for the call, 30 001 instructions:
/// it charges the constant generator's `#1` and `nop` 2 cycles each), so the processor-in-the-
/// loop periods overstate the wait by 20 000 cycles. If the FLL+ did not lock (`CLOCK_STATUS`
/// bit 1) MCLK may be anywhere in the DCO's range and so may the wait. The same loop runs in
/// the processor-in-the-loop image.
pub struct CycleDelay;

impl CycleDelay {
    /// Busy-waits `n` iterations of 4 cycles.
    #[inline(never)]
    fn spin(mut n: u32) {
        while n > 0 {
            let chunk = n.min(0xFFFF) as u16;
            n -= u32::from(chunk);
            // SAFETY: register arithmetic and a branch on the operand register only:
            // `sub #1` (1 cycle, the constant generator), `nop` (1), `jnz` (2).
            unsafe {
                core::arch::asm!(
                    "2:",
                    "sub #1, {0}",
                    "nop",
                    "jnz 2b",
                    inout(reg) chunk => _,
                    options(nomem, nostack)
                )
            };
        }
    }
}

impl embedded_hal::delay::DelayNs for CycleDelay {
    /// At least `ns`: 500 ns an iteration, `ns / 256 + 1` of them (so up to twice `ns`; the
    /// images ask microseconds).
    fn delay_ns(&mut self, ns: u32) {
        Self::spin((ns >> 8) + 1);
    }

    fn delay_us(&mut self, us: u32) {
        Self::spin(us.saturating_mul(2));
    }
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
