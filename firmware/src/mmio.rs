//! The part's registers for the drivers of [`acs::hal::msp430`]: [`Mmio`], volatile loads and
//! stores of the addresses they name; and the two pieces of assembly of the low-power period
//! ([`sleep_lpm3`], the Timer_A0 handler `TIMERA0_ISR`).
//!
//! The flight node images (feature `pil` off) run their peripherals' drivers over [`Mmio`]
//! ([`crate::periph`], `acs::hal::msp430::tile_bus`); `src/bin/drivers.rs` links every driver
//! over it to measure them. The flight images' Timer_A0 handler is `TIMERA0_VECTOR`
//! ([`crate::periph`], the same two instructions as `TIMERA0_ISR` below, which no image links:
//! the linker drops it).

use acs::hal::msp430::Registers;

/// Volatile access to the MSP430's address space: the drivers' [`Registers`]. Zero-sized and
/// `Copy`: every driver holds its own.
///
/// # Contract (why the `unsafe` below is sound)
/// The drivers of [`acs::hal::msp430`] pass only the addresses of their own peripheral's
/// registers (the SLAS508K peripheral file map, 0x0001–0x01FF) and, for the flash controller,
/// the flash words of the element store's segments (outside the image, per the memory map);
/// never 0x0000 (a null pointer in Rust), word accesses only at even addresses. Those addresses
/// are always mapped on the MSP430FG4619/F2619 (an access cannot fault), and no Rust object lives
/// there, so the accesses alias no reference. The firmware is single-threaded and no interrupt
/// handler touches the drivers' registers.
#[derive(Copy, Clone, Debug, Default)]
pub struct Mmio;

impl Registers for Mmio {
    #[inline(always)]
    fn read8(&mut self, addr: u16) -> u8 {
        // SAFETY: see the type's contract.
        unsafe { core::ptr::read_volatile(usize::from(addr) as *const u8) }
    }

    #[inline(always)]
    fn write8(&mut self, addr: u16, value: u8) {
        // SAFETY: see the type's contract.
        unsafe { core::ptr::write_volatile(usize::from(addr) as *mut u8, value) }
    }

    #[inline(always)]
    fn read16(&mut self, addr: u16) -> u16 {
        // SAFETY: see the type's contract (`addr` even).
        unsafe { core::ptr::read_volatile(usize::from(addr) as *const u16) }
    }

    #[inline(always)]
    fn write16(&mut self, addr: u16, value: u16) {
        // SAFETY: see the type's contract (`addr` even).
        unsafe { core::ptr::write_volatile(usize::from(addr) as *mut u16, value) }
    }
}

/// Sleeps in LPM3 until an interrupt handler clears the low-power bits of the status register
/// it saved (`TIMERA0_ISR` does, at the end of the control period; `acs::hal::msp430::timer_a`,
/// "Sleeping between periods"). Sets GIE | CPUOFF | SCG0 | SCG1 (0x00D8) in SR (SLAU056
/// "Operating Modes"); the `nop` after is the one SLAU056 asks after an instruction that sets
/// GIE. Returns with interrupts enabled.
#[inline(always)]
pub fn sleep_lpm3() {
    // SAFETY: only SR's low-power and GIE bits change; the interrupts that can then run are the
    // firmware's handlers (the vector table, `crate::rt`). Not `nomem`: a handler may write
    // memory while the CPU sleeps.
    unsafe { core::arch::asm!("bis #0x00D8, r2", "nop") };
}

// The Timer_A CCR0 handler (vector 0xFFEC, SLAS508K interrupt vector table): clears CPUOFF,
// OSCOFF, SCG0 and SCG1 in the status register saved on the stack, so `reti` returns to the
// loop awake (the interrupt's acceptance has cleared TACCR0 CCIFG). Not in a vector table: the
// flight node images define `TIMERA0_VECTOR` (`crate::periph::flight_vectors!`), which
// `crate::rt`'s table names at 0xFFEC.
core::arch::global_asm!(
    r#"
    .section .text.TIMERA0_ISR,"ax",@progbits
    .global TIMERA0_ISR
    .type TIMERA0_ISR,@function
TIMERA0_ISR:
    bic #0x00F0, 0(r1)
    reti
"#
);
