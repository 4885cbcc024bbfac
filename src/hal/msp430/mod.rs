//! Drivers for the MSP430FG4619's peripherals (and the MSP430F2619's, whose USCI, Timer_A,
//! Timer_B, ports and flash controller have the same registers at the same addresses), each
//! generic over [`Registers`]: the firmware implements it with volatile accesses
//! (`firmware/src/mmio.rs`), the host tests with models of the registers
//! (`tests/msp430_drivers.rs`), so every driver runs on the host against its peripheral's
//! documented behaviour before it runs on the part. mspdebug's simulator models none of these
//! peripherals.
//!
//! | module | peripheral | what | traits |
//! |---|---|---|---|
//! | [`usci_i2c`] | USCI_B0, I²C master | the tile sensors' bus, 100 kHz | `embedded_hal::i2c::I2c` |
//! | [`usci_uart`] | USCI_A0, UART | the inter-node link, 115 200 Bd 8N1 | byte stream (`write_bytes`/`read_bytes`) |
//! | [`timer_a`] | Timer_A3 from ACLK | the 1 s control period, LPM3 between periods | — |
//! | [`pwm`] | Timer_B7, reset/set outputs | the coils' PWM, 20 kHz | `embedded_hal::pwm::SetDutyCycle` |
//! | [`gpio`] | ports P1–P10 | the bridges' direction pins | `embedded_hal::digital::OutputPin` |
//! | [`flash`] | flash controller | segment erase, word write | — |
//! | [`element_store`] | two main-flash segments | the uplinked SGP4 element set, kept across resets | — |
//! | [`tile_bus`] | USCI_B0 + Timer_B + P5 | the attitude node's tile bus: the drivers at the tiles' I²C address map, the coils | `TileBus` (a `DeviceBus`) |
//!
//! So the reference drivers of [`super::drivers`] (`I2cMagnetometer`, `I2cGyro`,
//! `I2cSunSensor`, `PwmMagnetorquer`, `PwmReactionWheel`) and [`super::bus::DeviceBus`] run on
//! the part unchanged: `tests/msp430_drivers.rs` reads a modelled magnetometer, gyro and sun
//! sensor through [`usci_i2c::UsciI2c`] and commands coils through [`pwm::PwmChannel`] and
//! [`gpio::OutputPin`], all behind a `DeviceBus`.
//!
//! # Sources
//! - **SLAU056L**: TI, *MSP430x4xx Family User's Guide* (April 2013). Chapters cited by title:
//!   "FLL+ Clock Module", "Flash Memory Controller", "Digital I/O", "Timer_A", "Timer_B",
//!   "Universal Serial Communication Interface, UART Mode" and "…, I2C Mode"; each module names
//!   its sections and register tables.
//! - **SLAS508K**: TI, *MSP430FG461x mixed signal microcontroller* data sheet (May 2020): the
//!   peripheral file map (the register addresses; they agree with TI's device file
//!   `msp430fg4619_symbols.ld` of the msp430-gcc support files), the pin function tables
//!   ("Port P2, P2.4 to P2.5", "Port P3, P3.0 to P3.3", "Port P3, P3.4 to P3.7"), §6.8 "Flash
//!   Memory" and the electrical characteristics table "Flash Memory (FG461x devices only)".
//!
//! # Clocks
//! Every figure below assumes the clocks the flight image's cycle budget assumes (8 MHz):
//! ACLK = 32 768 Hz from the watch crystal (LFXT1), and MCLK = SMCLK = [`SMCLK_HZ`] =
//! 7 995 392 Hz from the FLL+ with N = 121, D = 2, DCOPLUS = 1 (SLAU056 "FLL+ Clock Module":
//! f_DCOCLK = D · (N + 1) · f_crystal = 2 · 122 · 32 768 Hz). Each driver's configuration takes
//! its clock as a parameter, so another clock changes a `const`, not a driver.
//!
//! # Safety of register access
//! The drivers are safe code ([`Registers`] is a safe trait); the `unsafe` volatile accesses are
//! in the firmware's implementation of it, whose contract is stated there. The drivers only touch
//! the registers of their own peripheral, with 16-bit accesses at even addresses, and never
//! address 0x0000. Read-modify-write updates of a register (a port's `PxOUT`, `UCB0CTL1`) are
//! two accesses: no interrupt handler may write the same register (the flight image has none;
//! the period timer's handler only clears the low-power bits on the stack).
//!
//! # Every wait is bounded
//! Each driver polls a flag at most a configured number of times and returns a timeout error
//! beyond it (a stuck bus, a stopped crystal, a peripheral that never answers): no driver can
//! hang the loop, and the watchdog (1 s) stays the last resort, not the first.
//!
//! # Measured figures
//! **Flash bytes** on the MSP430 (release, opt-level "s", LTO, the firmware's inline threshold):
//! `firmware/src/bin/drivers.rs` links every driver over the firmware's `Mmio`, each from a
//! `measure_*` function of its own; a driver's bytes are that function (the driver inlined into
//! it, with its configuration and a few bytes of call glue) plus the driver's functions LLVM
//! kept out of line (`llvm-nm --size-sort -S -C` on the image, built with `cd firmware && cargo
//! build --release --bin drivers --features fg4619-map`). The image links with no panic path
//! (its panic handler calls an undefined symbol).
//!
//! **Cycles**: the same image in `mspdebug -n sim` (tracer MCLK counts between the image's
//! marks). The simulator has none of these peripherals, so the image gives the drivers a
//! register access that answers at once (every flag set) or never (no flag ever set): the first
//! measures a driver's own cycles, the second the cost of its bounded waits. The bus time (the
//! bits at the stated rate) comes on top, and the CPU polls through it.
//!
//! | driver | flash bytes | hot path | driver's own cycles | bus time | of a 1 s period |
//! |---|---|---|---|---|---|
//! | [`usci_i2c`] | 1 012 | 4-byte register read (`write_read`: address, register, repeated START, 4 bytes) | 540 (68 µs) | 660 µs: 63 bits and START, repeated START, STOP at 99 942 Hz | 0.066 % |
//! | [`usci_uart`] | 256 | 100-byte frame out (`write_bytes`) | 2 129 (266 µs) | 8 677 µs: 1 000 bits at 115 249 Bd | 0.87 % |
//! | [`usci_uart`] | (same) | 16 bytes in (`read_bytes`) | 530 | — | — |
//! | [`timer_a`] | 152 | `period_elapsed` poll | 44 a poll | — | — |
//! | [`pwm`] + [`gpio`] | 324 (3 channels, 3 pins) | Timer_B started, three channels and their pins set up and commanded once | 1 518 | — | — |
//! | [`flash`] + [`element_store`] | 1 048 | `load` of a valid record (at reset) | 68 002 (8.5 ms) | — | — |
//! | (same) | (same) | `store` (an uplinked element set) | 149 476 (18.7 ms) | + 23.1 ms of flash operations (CPU held): 13.3 ms erase, 119 × 82.5 µs writes | once per uplink |
//!
//! The bounded waits: an I²C wait is 11 cycles a poll, its 1 000 polls 1.4 ms (15 byte times
//! at 100 kHz); a UART byte's wait 8 cycles a poll, its 200 polls 203 µs (2.3 byte times at
//! 115 200 Bd); the period timer's 44 cycles a poll (a 1 s wait is about 182 000 polls).
//!
//! With the flight image's I²C traffic (6 tiles × 3 sensors, a register read of 2–6 bytes
//! each) the bus takes about 18 × 0.6 ms ≈ 11 ms of each 1 s period, and the attitude node's
//! step (342 800 cycles at most with the multiplier, 42.9 ms at [`SMCLK_HZ`], `firmware/pil`)
//! most of the rest of the active time: the CPU is in LPM3 for about 94 % of each period
//! ([`timer_a`], "Duty cycle").

pub mod element_store;
pub mod flash;
pub mod gpio;
pub mod pwm;
pub mod tile_bus;
pub mod timer_a;
pub mod usci_i2c;
pub mod usci_uart;

/// MCLK = SMCLK of the flight configuration, Hz: the FLL+ at D · (N + 1) · 32 768 with D = 2,
/// N = 121, DCOPLUS = 1 (see the [module docs](self), "Clocks").
pub const SMCLK_HZ: u32 = 7_995_392;

/// ACLK, Hz: the 32 768 Hz watch crystal on LFXT1.
pub const ACLK_HZ: u32 = 32_768;

/// Access to the part's memory-mapped registers (and, for the flash controller, to flash
/// memory itself): the only thing a driver of this module needs from its platform.
///
/// The firmware implements it with volatile reads and writes of the address; the host tests
/// with register models. Every method is a single bus access, in the order called: an
/// implementation must neither cache, merge nor reorder them.
pub trait Registers {
    /// Reads the byte register at `addr`.
    fn read8(&mut self, addr: u16) -> u8;
    /// Writes the byte register at `addr`.
    fn write8(&mut self, addr: u16, value: u8);
    /// Reads the word register (or flash word) at the even address `addr`.
    fn read16(&mut self, addr: u16) -> u16;
    /// Writes the word register (or flash word) at the even address `addr`.
    fn write16(&mut self, addr: u16, value: u16);

    /// Sets the bits `mask` of the byte register at `addr` (a read, then a write).
    fn set_bits8(&mut self, addr: u16, mask: u8) {
        let v = self.read8(addr);
        self.write8(addr, v | mask);
    }

    /// Clears the bits `mask` of the byte register at `addr` (a read, then a write).
    fn clear_bits8(&mut self, addr: u16, mask: u8) {
        let v = self.read8(addr);
        self.write8(addr, v & !mask);
    }
}

impl<R: Registers + ?Sized> Registers for &mut R {
    fn read8(&mut self, addr: u16) -> u8 {
        R::read8(self, addr)
    }
    fn write8(&mut self, addr: u16, value: u8) {
        R::write8(self, addr, value)
    }
    fn read16(&mut self, addr: u16) -> u16 {
        R::read16(self, addr)
    }
    fn write16(&mut self, addr: u16, value: u16) {
        R::write16(self, addr, value)
    }
    fn set_bits8(&mut self, addr: u16, mask: u8) {
        R::set_bits8(self, addr, mask)
    }
    fn clear_bits8(&mut self, addr: u16, mask: u8) {
        R::clear_bits8(self, addr, mask)
    }
}

/// The interrupt flag register 2 (SLAS508K peripheral file map, "special function registers";
/// SLAU056 "USCI Registers"), shared by USCI_A0 and USCI_B0: the drivers only read it (each
/// flag is cleared by the buffer access it signals), so neither disturbs the other's flags.
pub const IFG2: u16 = 0x0003;
