//! The part's peripherals as the flight node images use them (feature `pil` off): the clocks,
//! the control period, the link between the nodes over USCI_A0, and the vectors of the two
//! interrupt handlers. The processor-in-the-loop images (feature `pil`) use none of this (their
//! tiles, link and period are RAM mailboxes: [`crate::tiles`], [`crate::node_link`]).
//!
//! # Clocks ([`init_clocks`])
//! ACLK = 32 768 Hz from the watch crystal on LFXT1; MCLK = SMCLK = DCOCLK = 7 995 392 Hz, the
//! clocks every driver of [`acs::hal::msp430`] assumes (its "Clocks"): SLAU056L "FLL+ Clock
//! Module", f_DCOCLK = D · (N + 1) · f_crystal with DCOPLUS = 1, D = 2 (FLLDx = 01, SCFI0's
//! reset value), N = 121 (SCFQCTL), the DCO range FN_4 (SCFI0; SLAS508K "DCO" table: 3.2 …
//! 25 MHz at FN_4, nominal 8 MHz), and the crystal's load capacitors XCAP18PF (FLL_CTL0, the
//! setting of TI's FG4619 experimenter board; a board with another crystal load changes that
//! constant). MCLK and SMCLK are DCOCLK out of reset (FLL_CTL1: SELMx = 00, SELS = 0).
//!
//! Settling, bounded: first the crystal (LFOF in FLL_CTL0 clear: a 32 kHz crystal starts in a
//! few hundred ms, [`CRYSTAL_POLLS`] bounds the wait at about 2 s at the slowest MCLK), then the
//! FLL+: its frequency integrator moves the DCO by one modulation step per ACLK cycle, so the
//! whole range (28 DCO taps of 32 steps, SLAU056 "FLL+ Clock Module": "DCO Modulator") takes at
//! most 896 ACLK cycles, 27.3 ms; the loop waits [`FLL_SETTLE_ACLK`] = 1 024 ACLK cycles
//! (31.25 ms) counted by Timer_A, then reads DCOF (the DCO at the end of its range: the
//! frequency not reached). The outcome is in `CLOCK_STATUS` ([`clock_status`]) for a debugger;
//! the images run either way (a stopped crystal also stops the period and the watchdog's
//! clock, both on ACLK: the failure is visible as a node that does not step).
//!
//! # The control period ([`start_period`], [`wait_period`], [`Events`])
//! Timer_A in up mode from ACLK, 32 768 counts: one TACCR0 match a second
//! ([`acs::hal::msp430::timer_a`]), its interrupt (CCIE) enabled. The loop sleeps in LPM3
//! ([`crate::mmio::sleep_lpm3`]) at the start of each period; the TACCR0 handler
//! (`TIMERA0_VECTOR`, vector 0xFFEC) clears the low-power bits of the saved status register, so
//! the loop wakes and steps once a second. Between periods only ACLK (crystal, Timer_A, the
//! watchdog) runs. The handler also counts the periods (`PERIOD_TICKS`): the attitude node
//! waits for the next count ([`wait_period`]; the wake-ups of the link's frames sleep again),
//! the reference node for the next count or the next frame ([`Events`]). A step longer than
//! its period (none is) would be followed at once by the next, the periods it overran lost,
//! not queued.
//!
//! # Duty cycle (estimated; the simulator has no Timer_A, no USCI)
//! Active per second, at MCLK = 7 995 392 Hz with the multiplier:
//! - reference node: its step (SGP4, Sun, IGRF, guidance) 543 603 cycles, 68.0 ms (measured:
//!   the PIL image in `mspdebug -n sim` with the clock set, a steady step), plus the REF frame
//!   out, 118 bytes polled, 10.2 ms, and 80 received bytes in the handler, 0.4 ms: 78.6 ms,
//!   a duty cycle of 7.9 %, LPM3 92 % of the time;
//! - attitude node: its step, at most 342 800 cycles, 42.9 ms (measured: the PIL image's worst
//!   period, `firmware/pil`; it includes the 5 ms busy wait for the coils' decay, which
//!   mspdebug counts as 60 002 cycles and the part runs in 40 000), plus the tile bus (15
//!   sensor reads of 2–6 bytes, about 9.9 ms at 100 kHz; 5 wheel set-points and directions,
//!   4.0 ms), the STATUS frame out (68 bytes, 5.9 ms) and 120 received bytes (0.6 ms): at
//!   most 63.3 ms, a duty cycle of 6.3 %; LPM3 the rest.
//!
//! # The link ([`Link`], [`link`], [`send`], [`receive_last`])
//! [`acs::hal::link::FramedLink`] (COBS frames) over [`UartStream`]: USCI_A0 at 115 200 Bd
//! ([`acs::hal::msp430::usci_uart`]; TXD P2.4, RXD P2.5; the two nodes' UARTs crossed). Bytes
//! out are written polled (a 116-byte frame: 10 ms). Bytes in are taken by the USCIAB0RX
//! handler (`USCIAB0RX_VECTOR`, vector 0xFFF2; UCA0RXIE) into a 128-byte RAM ring,
//! `UART_RX_RING`, counted by `UART_RX_COUNT`, whatever the CPU is doing (stepping, or in LPM3:
//! the USCI requests SMCLK for a character it receives, SLAU056 "USCI Operation in Low-Power
//! Modes"), and read by the loop through [`acs::hal::msp430::usci_uart::RxRing`]. The handler
//! is 10 instructions, about 37 cycles a byte (44 on a delimiter, which also wakes the loop:
//! [`Events`]; the reference node answers a STATUS as soon as its frame ends). Each frame is
//! preceded by one more 0x00 (an empty frame, ignored): the byte that wakes the far end's
//! clock, whose corruption costs no frame.
//!
//! While the element store writes flash (about 23 ms once per accepted ELEMENTS uplink, the
//! interrupts disabled as SLAU056 requires), bytes arriving are lost (UCOE): the frame in
//! flight then, if any, is dropped by its CRC or its framing and the step runs without it.
//!
//! # Measured figures (flight build, `cargo build --release --features fg4619-map --bin
//! acs-reference --bin acs-attitude`, on `memory-fg4619-node.x`; no reachable panic)
//! | image | flash | static RAM | stack bound (`tools/stack_depth.py ELF main`) | RAM, % of 4 096 B |
//! |---|---|---|---|---|
//! | `acs-reference` | 42 050 B (73.7 % of 57 024 B) | 392 B | 2 318 B (+ 6 B of a handler) | 2 716 B, 66.3 % |
//! | `acs-attitude` | 41 296 B (72.4 %) | 388 B | 2 442 B (+ 6 B) | 2 836 B, 69.2 % |
//!
//! What each peripheral adds (flash of the image without it, the mailbox in its place, taken
//! from the image's; the PIL images: reference 39 126 B, 512 + 2 196 B; attitude 36 126 B,
//! 604 + 1 972 B):
//! | peripheral | reference | attitude |
//! |---|---|---|
//! | tile bus ([`acs::hal::msp430::tile_bus`]: USCI_B0 I²C, the drivers, wheel set-points, Timer_B coils) | — | 3 814 B flash, +480 B stack (the drivers live in the loop's frame), −92 B static (no tile mailboxes) |
//! | link (USCI_A0, ring and handler, `FramedLink`, COBS) | 1 268 B flash; −260 B static, the link mailboxes' (the ring's 128 B and the handlers' counters, in the images either way, stay) | 1 078 B, −260 B static |
//! | element store ([`crate::element_flash`]: flash controller, store, load at reset) | 1 200 B flash, −126 B stack (the words out of the loop's frame) | — |
//! | clocks (FLL+ set-up and settling) | 188 B | 188 B |
//! | period, LPM3, vectors, the reference's event loop, coils in `safe_state` | 268 B | 90 B |
//!
//! # Interrupt vectors
//! [`flight_vectors!`] defines `TIMERA0_VECTOR` and `USCIAB0RX_VECTOR`, which `crate::rt`'s
//! vector table names (and `link.x` points to `DefaultHandler` where an image does not define
//! them): the two flight node binaries invoke it, no other image does.

use acs::hal::link::{ByteStream, ErrorType, FramedLink, NodeLink};
use acs::hal::msp430::timer_a::{self, Period, PeriodTimer};
use acs::hal::msp430::usci_uart::{RxRing, UartConfig, UartError, UsciUart, RX_RING_BYTES};
use acs::hal::msp430::Registers;

use crate::mmio::Mmio;
use crate::node_link::LINK_BYTES;

/// FLL+ system clock frequency integrator 0 (SLAS508K peripheral file map).
const SCFI0: u16 = 0x0050;
/// FLL+ system clock frequency control (N).
const SCFQCTL: u16 = 0x0052;
/// FLL+ control 0.
const FLL_CTL0: u16 = 0x0053;
/// SCFI0: FLLDx = 01 (D = 2), FN_4 (the DCO range of 8 MHz).
const SCFI0_FLIGHT: u8 = 0x40 | 0x10;
/// SCFQCTL: N = 121.
const SCFQCTL_FLIGHT: u8 = 121;
/// FLL_CTL0: DCOPLUS, XCAP18PF.
const FLL_CTL0_FLIGHT: u8 = 0x80 | 0x30;
/// FLL_CTL0: LFXT1 fault.
const LFOF: u8 = 0x02;
/// FLL_CTL0: DCO fault (at the end of its range).
const DCOF: u8 = 0x01;
/// Interrupt enable 2: UCA0RXIE.
const IE2: u16 = 0x0001;
/// IE2: USCI_A0 receive interrupt enable.
const UCA0RXIE: u8 = 0x01;

/// Polls of LFOF before the images go on without the crystal (a poll with its watchdog kick is
/// about 12 cycles: 2 s at the 1 MHz DCO of reset).
pub const CRYSTAL_POLLS: u32 = 160_000;

/// ACLK cycles waited for the FLL+ to settle (more than its 896-cycle worst case).
pub const FLL_SETTLE_ACLK: u16 = 1_024;

/// The outcome of [`init_clocks`]: 0 settled; bit 0 the crystal did not start (LFOF), bit 1
/// the DCO at the end of its range (DCOF) after the settling time.
#[no_mangle]
static mut CLOCK_STATUS: u16 = 0;

/// The receive ring the USCIAB0RX handler fills (see the [module docs](self)).
#[no_mangle]
static mut UART_RX_RING: [u8; RX_RING_BYTES as usize] = [0; RX_RING_BYTES as usize];

/// Bytes the USCIAB0RX handler has put into the ring (free-running, wrapping).
#[no_mangle]
static mut UART_RX_COUNT: u16 = 0;

/// Frame delimiters (0x00) the USCIAB0RX handler has received (free-running, wrapping): each
/// wakes the loop.
#[no_mangle]
static mut UART_RX_DELIMITERS: u16 = 0;

/// Periods ended: the TACCR0 handler's count (free-running, wrapping).
#[no_mangle]
static mut PERIOD_TICKS: u16 = 0;

/// A word the handlers count up (a single word read: atomic on the MSP430).
fn counter(c: *const u16) -> u16 {
    // SAFETY: `c` is one of this module's statics (valid, aligned); volatile: a handler
    // writes it.
    unsafe { core::ptr::read_volatile(c) }
}

/// Sleeps in LPM3 unless `awake()` already holds; returns after an interrupt handler woke the
/// loop, or at once. The test runs with interrupts disabled, and the LPM3 entry enables them in
/// the same instruction (`bis #0x00D8, SR`; an interrupt is taken after it, so it wakes the
/// sleep it interrupts): a handler that runs between the test and the sleep is not missed.
fn sleep_unless(awake: impl Fn() -> bool) {
    // SAFETY: `dint` clears GIE only; the `nop` is the one SLAU056 asks after it.
    unsafe { core::arch::asm!("dint", "nop") };
    if awake() {
        // SAFETY: `eint` sets GIE only.
        unsafe { core::arch::asm!("eint", "nop") };
    } else {
        crate::mmio::sleep_lpm3();
    }
}

/// What the loop has seen of the handlers' counts: the events it waits for.
pub struct Events {
    ticks: u16,
    delimiters: u16,
}

impl Events {
    /// The counts now (nothing pending).
    pub fn now() -> Self {
        Self {
            ticks: counter(&raw const PERIOD_TICKS),
            delimiters: counter(&raw const UART_RX_DELIMITERS),
        }
    }

    /// Sleeps until a period ends or a frame delimiter arrives; which of the two happened
    /// since the last call: `(period, delimiter)`.
    #[inline(never)]
    pub fn wait(&mut self) -> (bool, bool) {
        let (t0, d0) = (self.ticks, self.delimiters);
        loop {
            sleep_unless(|| {
                counter(&raw const PERIOD_TICKS) != t0
                    || counter(&raw const UART_RX_DELIMITERS) != d0
            });
            self.ticks = counter(&raw const PERIOD_TICKS);
            self.delimiters = counter(&raw const UART_RX_DELIMITERS);
            if self.ticks != t0 || self.delimiters != d0 {
                return (self.ticks != t0, self.delimiters != d0);
            }
        }
    }
}

/// The clocks' state after [`init_clocks`] (see `CLOCK_STATUS`).
pub fn clock_status() -> u16 {
    // SAFETY: single-threaded, no handler touches it.
    unsafe { core::ptr::read_volatile(&raw const CLOCK_STATUS) }
}

/// Sets up the FLL+ for MCLK = SMCLK = 7 995 392 Hz from the crystal, waits (bounded) for the
/// crystal and the FLL+, and starts the control period's Timer_A (see the
/// [module docs](self)); the watchdog is kicked while it waits.
#[inline(never)]
pub fn init_clocks() {
    let mut regs = Mmio;
    regs.write8(SCFI0, SCFI0_FLIGHT);
    regs.write8(SCFQCTL, SCFQCTL_FLIGHT);
    regs.write8(FLL_CTL0, FLL_CTL0_FLIGHT);
    let mut status = 0;
    let mut crystal = false;
    for _ in 0..CRYSTAL_POLLS {
        crate::kick_watchdog();
        if regs.read8(FLL_CTL0) & LFOF == 0 {
            crystal = true;
            break;
        }
    }
    if !crystal {
        status |= 1;
    }
    start_period();
    // TAR counts ACLK from 0 (bounded by the same number of polls)
    for _ in 0..CRYSTAL_POLLS {
        crate::kick_watchdog();
        if regs.read16(timer_a::TAR) >= FLL_SETTLE_ACLK {
            break;
        }
    }
    if regs.read8(FLL_CTL0) & DCOF != 0 {
        status |= 2;
    }
    // SAFETY: single-threaded, no handler touches it.
    unsafe { core::ptr::write_volatile(&raw mut CLOCK_STATUS, status) };
}

/// Starts Timer_A's one-second period with its wake-up interrupt (TACCR0 CCIE); the first
/// period ends one second after.
pub fn start_period() {
    let mut timer = PeriodTimer::start(Mmio, Period::ONE_SECOND, timer_a::FLIGHT_POLL_LIMIT);
    timer.enable_wakeup();
}

/// Sleeps in LPM3 until the end of the current period (the TACCR0 handler counts it and wakes
/// the loop; the wake-ups of frame delimiters sleep again); interrupts are enabled from the
/// first call on.
#[inline(never)]
pub fn wait_period() {
    let t0 = counter(&raw const PERIOD_TICKS);
    while counter(&raw const PERIOD_TICKS) == t0 {
        sleep_unless(|| counter(&raw const PERIOD_TICKS) != t0);
    }
}

/// Runs `f` with interrupts disabled (a flash erase or write: SLAU056 "Flash Memory Access
/// During Write or Erase"), then enables them.
#[inline(never)]
pub fn without_interrupts<T>(f: impl FnOnce() -> T) -> T {
    // SAFETY: `dint` clears GIE only; the `nop` is the one SLAU056 asks after it.
    unsafe { core::arch::asm!("dint", "nop") };
    let r = f();
    // SAFETY: `eint` sets GIE only (the loop runs with interrupts enabled after its first
    // period); the `nop` as after `dint`.
    unsafe { core::arch::asm!("eint", "nop") };
    r
}

/// USCI_A0 as the link's byte stream: bytes out polled through [`UsciUart`], bytes in from
/// the receive ring the USCIAB0RX handler fills ([`RxRing`]).
pub struct UartStream {
    uart: UsciUart<Mmio>,
    ring: RxRing,
}

impl ErrorType for UartStream {
    type Error = UartError;
}

impl ByteStream for UartStream {
    fn write(&mut self, bytes: &[u8]) -> Result<(), UartError> {
        ByteStream::write(&mut self.uart, bytes)
    }

    fn read(&mut self, buf: &mut [u8]) -> Result<usize, UartError> {
        self.ring.read(
            // SAFETY: a word read of the handler's count (atomic on the MSP430); volatile: the
            // handler writes it.
            || unsafe { core::ptr::read_volatile(&raw const UART_RX_COUNT) },
            |i| {
                if i >= usize::from(RX_RING_BYTES) {
                    return 0;
                }
                // SAFETY: `i` within the ring; the slot was written before the count that
                // covers it (the handler's order), volatile as above.
                unsafe { core::ptr::read_volatile((&raw const UART_RX_RING as *const u8).add(i)) }
            },
            buf,
        )
    }
}

/// The node's link: COBS frames over USCI_A0.
pub type Link = FramedLink<UartStream, LINK_BYTES>;

/// Sets up USCI_A0 (115 200 Bd 8N1 from SMCLK) and its receive interrupt, and returns the
/// link, its ring reader at the handler's count.
#[inline(never)]
pub fn link() -> Link {
    let uart = UsciUart::new(Mmio, UartConfig::FLIGHT);
    let mut ring = RxRing::new();
    // SAFETY: as in `UartStream::read`.
    ring.resync(unsafe { core::ptr::read_volatile(&raw const UART_RX_COUNT) });
    Mmio.set_bits8(IE2, UCA0RXIE);
    FramedLink::new(UartStream { uart, ring })
}

/// Sends `packet`: a wake-up 0x00, then its frame. A transmitter that stopped loses the
/// packet (the far end's step runs without it, as on a lost frame).
#[inline(never)]
pub fn send(link: &mut Link, packet: &[u8]) {
    if ByteStream::write(link.stream_mut(), &[0]).is_ok() {
        let _ = link.send(packet);
    }
}

/// Receives the packets that arrived since the last call and returns the last that `parse`
/// accepts (at most four frames a period; damaged frames are skipped).
#[inline(never)]
pub fn receive_last<T>(
    link: &mut Link,
    buf: &mut [u8; LINK_BYTES],
    mut parse: impl FnMut(&[u8]) -> Option<T>,
) -> Option<T> {
    let mut last = None;
    for _ in 0..4 {
        match link.receive(buf) {
            Ok(Some(n)) => {
                if let Some(t) = buf.get(..n).and_then(&mut parse) {
                    last = Some(t);
                }
            }
            Ok(None) => break,
            Err(_) => {}
        }
    }
    last
}

/// Defines the two interrupt handlers of the flight node images (see the [module docs](self)):
/// `TIMERA0_VECTOR` counts `PERIOD_TICKS` and clears CPUOFF, OSCOFF, SCG0 and SCG1 in the
/// status register saved on the stack, so `reti` returns to the loop awake (as
/// `crate::mmio`'s `TIMERA0_ISR`); `USCIAB0RX_VECTOR` stores UCA0RXBUF (0x0066; reading it
/// clears UCA0RXIFG and the error flags) at `UART_RX_RING[UART_RX_COUNT mod 128]`, increments
/// `UART_RX_COUNT`, and on a frame delimiter (0x00) counts `UART_RX_DELIMITERS` and wakes the
/// loop (the saved status register is at 2(SP) after its push). Invoke once, in a flight node
/// binary.
#[macro_export]
macro_rules! flight_vectors {
    () => {
        core::arch::global_asm!(
            r#"
    .section .text.TIMERA0_VECTOR,"ax",@progbits
    .global TIMERA0_VECTOR
    .type TIMERA0_VECTOR,@function
TIMERA0_VECTOR:
    inc &PERIOD_TICKS
    bic #0x00F0, 0(r1)
    reti

    .section .text.USCIAB0RX_VECTOR,"ax",@progbits
    .global USCIAB0RX_VECTOR
    .type USCIAB0RX_VECTOR,@function
USCIAB0RX_VECTOR:
    push r15
    mov &UART_RX_COUNT, r15
    and #0x007F, r15
    mov.b &0x0066, UART_RX_RING(r15)
    inc &UART_RX_COUNT
    tst.b UART_RX_RING(r15)
    jnz 1f
    inc &UART_RX_DELIMITERS
    bic #0x00F0, 2(r1)
1:  pop r15
    reti
"#
        );
    };
}
