//! Measurement image of the MSP430 peripheral drivers (`acs::hal::msp430`) over the firmware's
//! register access (`acs_firmware::mmio::Mmio`): every driver instantiated, each entry point
//! called once from a `measure_*` function of its own (not inlined), so that each driver's code
//! is in the image once: `llvm-nm --size-sort -S -C` gives each driver's bytes as its
//! `measure_*` function (the driver inlined into it, with a few bytes of glue) plus the driver's
//! functions LLVM kept out of line (named `acs::hal::msp430::<driver>::…`).
//!
//! Build: `cd firmware && cargo build --release --bin drivers --features fg4619-map`. Run in
//! `mspdebug -n sim` (no peripheral is simulated: every register reads as the memory under it),
//! it measures the drivers' own cycles with [`drivers_mark`] as a break point.
#![no_std]
#![no_main]

use acs::hal::msp430::element_store::ElementStore;
use acs::hal::msp430::flash::{FlashConfig, FlashController};
use acs::hal::msp430::gpio::{OutputPin, Pin, P5};
use acs::hal::msp430::pwm::{PwmConfig, TbOutput, TimerBPwm};
use acs::hal::msp430::timer_a::{Period, PeriodTimer};
use acs::hal::msp430::usci_i2c::{I2cConfig, UsciI2c};
use acs::hal::msp430::usci_uart::{UartConfig, UsciUart};
use acs::hal::msp430::Registers;
use acs::orbit::sgp4::ELEMENT_WORDS;
use acs_firmware::mmio::Mmio;
use embedded_hal::digital::OutputPin as _;
use embedded_hal::i2c::I2c;
use embedded_hal::pwm::SetDutyCycle;

/// Id of the last mark (a break point for the simulator).
#[no_mangle]
static mut DRIVERS_ID: u16 = 0;

/// Break point between measured sections.
#[no_mangle]
#[inline(never)]
pub extern "C" fn drivers_mark(id: u16) {
    // SAFETY: single-threaded; volatile so the call cannot be removed.
    unsafe { core::ptr::write_volatile(&raw mut DRIVERS_ID, id) }
}

/// The element store's segments in this image.
const STORE_SEGMENTS: [u16; 2] = [0xF000, 0xF200];

/// Keeps a value alive without a store the optimiser can drop.
fn keep<T>(x: T) -> T {
    core::hint::black_box(x)
}

/// The register access of the cycle counts in mspdebug's simulator, which simulates no
/// peripheral (a register reads as the memory under it): [`Mmio`], except that IFG2 reads with
/// every USCI flag set (`ANSWER` true) or none, UCB0CTL1 with UCTXSTT and UCTXSTP clear, and
/// the USCI status registers with no error flag. With `ANSWER`, a peripheral that answers at
/// once: the cycles measured are the driver's own, the bus time comes on top; without, one that
/// never answers: the cost of a timeout. (The masks fold into the inlined accesses: one
/// instruction more on those reads.)
#[derive(Copy, Clone)]
struct Instant<const ANSWER: bool>;

impl<const ANSWER: bool> Registers for Instant<ANSWER> {
    #[inline(always)]
    fn read8(&mut self, addr: u16) -> u8 {
        let v = Mmio.read8(addr);
        match addr {
            0x0003 if ANSWER => v | 0x0F,
            0x0003 => v & !0x0F,
            0x0069 => v & !0x06,
            0x0065 | 0x006D => v & 0,
            _ => v,
        }
    }
    #[inline(always)]
    fn write8(&mut self, addr: u16, value: u8) {
        Mmio.write8(addr, value)
    }
    #[inline(always)]
    fn read16(&mut self, addr: u16) -> u16 {
        Mmio.read16(addr)
    }
    #[inline(always)]
    fn write16(&mut self, addr: u16, value: u16) {
        Mmio.write16(addr, value)
    }
}

/// Cycle counts (between marks 10–19): the I²C 4-byte register read, the 100-byte frame and
/// a 16-byte read of the UART, with a peripheral that answers at once; then the bounded waits
/// that time out: the period timer (1 000 polls), the I²C read (two waits of 1 000 polls) and the
/// UART write (200 polls) with a peripheral that never answers.
#[no_mangle]
#[inline(never)]
fn cycles() {
    let mut bus = UsciI2c::new(Instant::<true>, &I2cConfig::FLIGHT);
    let mut four = [0u8; 4];
    drivers_mark(10);
    keep(bus.write_read(keep(0x1E), &[keep(0x03)], &mut four).is_ok());
    drivers_mark(11);
    keep(four);
    let mut uart = UsciUart::new(Instant::<true>, UartConfig::FLIGHT);
    let frame = keep([0x55u8; 100]);
    drivers_mark(12);
    keep(uart.write_bytes(&frame).ok());
    drivers_mark(13);
    let mut rx = [0u8; 16];
    keep(uart.read_bytes(&mut rx).ok());
    drivers_mark(14);
    keep(rx);
    let mut timer = PeriodTimer::start(Mmio, Period::ONE_SECOND, 1_000);
    keep(timer.wait_period().is_ok());
    drivers_mark(15);
    let mut stuck = UsciI2c::new(Instant::<false>, &I2cConfig::FLIGHT);
    drivers_mark(16);
    keep(
        stuck
            .write_read(keep(0x1E), &[keep(0x03)], &mut four)
            .is_ok(),
    );
    drivers_mark(17);
    let mut stopped = UsciUart::new(Instant::<false>, UartConfig::FLIGHT);
    drivers_mark(18);
    keep(stopped.write_bytes(&frame).ok());
    drivers_mark(19);
}

/// USCI_B0: initialisation and a 4-byte register read (`write_read`, a repeated START).
#[no_mangle]
#[inline(never)]
fn measure_i2c() {
    let mut bus = UsciI2c::new(Mmio, &I2cConfig::FLIGHT);
    let mut four = [0u8; 4];
    keep(bus.write_read(keep(0x1E), &[keep(0x03)], &mut four).is_ok());
    keep(four);
}

/// USCI_A0: initialisation, a 100-byte frame out, a read.
#[no_mangle]
#[inline(never)]
fn measure_uart() {
    let mut uart = UsciUart::new(Mmio, UartConfig::FLIGHT);
    let frame = keep([0x55u8; 100]);
    keep(uart.write_bytes(&frame).ok());
    let mut rx = [0u8; 16];
    keep(uart.read_bytes(&mut rx).ok());
    keep(rx);
}

/// Timer_A: start, the wake-up, a poll and a bounded wait.
#[no_mangle]
#[inline(never)]
fn measure_timer() {
    let mut timer = PeriodTimer::start(Mmio, Period::ONE_SECOND, 1_000);
    timer.enable_wakeup();
    keep(timer.period_elapsed());
    keep(timer.wait_period().is_ok());
}

/// The LPM3 entry of the control period (`acs_firmware::mmio::sleep_lpm3`): assembled and
/// linked, never run here (the simulator has no Timer_A to wake the CPU).
#[no_mangle]
#[inline(never)]
fn measure_lpm3() {
    if keep(false) {
        acs_firmware::mmio::sleep_lpm3();
    }
}

/// Timer_B and the ports: three coil channels with their direction pins, one command each.
#[no_mangle]
#[inline(never)]
fn measure_pwm() {
    let pwm = TimerBPwm::start(Mmio, PwmConfig::FLIGHT);
    for (out, bit) in [(TbOutput::TB3, 0), (TbOutput::TB4, 1), (TbOutput::TB5, 2)] {
        let mut ch = pwm.channel(out);
        let mut dir = OutputPin::new(Mmio, Pin::new(P5, bit));
        keep(ch.set_duty_cycle(keep(200)).is_ok());
        keep(dir.set_high().is_ok());
    }
}

/// The flash controller and the element store: load, store, load (the marks around each).
#[no_mangle]
#[inline(never)]
fn measure_store() {
    let mut words = [0u32; ELEMENT_WORDS];
    let flash = FlashController::new(Mmio, FlashConfig::FLIGHT);
    // two segments above this small image (the flight map's `FLIGHT_SEGMENTS` lie where this
    // image's code is)
    if let Ok(mut store) = ElementStore::new(flash, STORE_SEGMENTS) {
        drivers_mark(6);
        keep(store.load(&mut words));
        drivers_mark(7);
        keep(store.store(keep(&words)).ok());
        drivers_mark(8);
        keep(store.load(&mut words));
    }
    keep(words);
}

/// Entry point, called by the reset handler: each driver between two marks.
#[no_mangle]
pub extern "C" fn main() -> ! {
    drivers_mark(1);
    measure_i2c();
    drivers_mark(2);
    measure_uart();
    drivers_mark(3);
    measure_timer();
    measure_lpm3();
    drivers_mark(4);
    measure_pwm();
    drivers_mark(5);
    measure_store();
    drivers_mark(9);
    cycles();
    acs_firmware::fw_halt()
}

/// No panic path, proven at link time (as in `main.rs`).
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    extern "C" {
        /// Deliberately undefined.
        fn acs_drivers_image_has_a_reachable_panic() -> !;
    }
    // SAFETY: never linked, so never called: a reachable call fails the build.
    unsafe { acs_drivers_image_has_a_reachable_panic() }
}
