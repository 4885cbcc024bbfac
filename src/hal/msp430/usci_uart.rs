//! USCI_A0 as a UART: the byte stream of the link between the two ACS nodes.
//!
//! Source: SLAU056L, "Universal Serial Communication Interface, UART Mode": "USCI Initialization
//! and Reset", "Character Format" (8 data bits, no parity, one stop bit, LSB first: UCA0CTL0 =
//! 0), "Low-Frequency Baud Rate Generation" (UCOS16 = 0: N = f_BRCLK / baud, UCBRx = INT(N),
//! UCBRSx = round((N − INT(N)) · 8)), "Transmit Bit Timing", "UART Receive Errors" (UCFE, UCPE,
//! UCOE, UCBRK with UCRXERR; with UCRXEIE set an erroneous character still sets UCA0RXIFG, and
//! reading UCA0RXBUF clears the error flags) and the table "USCI_A Control and Status
//! Registers". Addresses: SLAS508K peripheral file map. Pins: SLAS508K "Port P2, P2.4 to P2.5"
//! (UCA0TXD on P2.4, UCA0RXD on P2.5, P2SEL bits set).
//!
//! # Baud rate ([`UartConfig::FLIGHT`])
//! 115 200 Bd from SMCLK = 7 995 392 Hz: N = 69.404, UCBRx = 69, UCBRSx = 3 (UCOS16 = 0). The
//! mean bit time is (69 + 3/8) / f_BRCLK, a rate of 115 249 Bd: +0.042 %. Bit by bit, with
//! UCBRSx = 3's modulation pattern (SLAU056 table "BITCLK Modulation Pattern": bits 1, 3, 5 of
//! each 8 one BRCLK longer, the pattern restarting with each character's start bit), the bit
//! edges of a 10-bit frame lie within −0.92 % … +0.83 % of a bit time of their ideal place (the
//! test `uart_baud_error_of_the_flight_setting` computes them as SLAU056 "Transmit Bit Timing"
//! does), far inside the ±50 % (less the receiver's sampling uncertainty) a receiver sampling
//! mid-bit tolerates.
//!
//! # Byte stream
//! [`UsciUart::write_bytes`] and [`UsciUart::read_bytes`] have the shape of the project's link
//! byte stream (`write(&[u8]) -> Result<usize, E>`, `read(&mut [u8]) -> Result<usize, E>`):
//! - a write puts bytes into UCA0TXBUF as it frees, waiting at most the poll limit for each
//!   (200 polls of 8 cycles, 203 µs: 2.3 byte times, for the flight configuration) and returns
//!   how many it wrote, the last byte still being sent; a 100-byte frame takes the caller through
//!   the frame's 8.7 ms; it fails
//!   with [`UartError::Timeout`] only if not even the first byte could go (a transmitter that
//!   stopped);
//! - a read takes the bytes already received, never waits, and returns how many (0: none yet).
//!   A received byte with an error is reported as the error of the next call that meets it
//!   first (a read that has good bytes returns them and leaves the bad one for the next call);
//!   the bad byte is discarded. The hardware buffers one byte: the link must read at least once
//!   per byte time (87 µs) while a frame arrives, or the overrun is reported.
//!
//! `UsciUart` is a [`ByteStream`] (the link's, [`crate::hal::link`]): `write` takes a whole
//! packet piece or fails ([`UartError::Timeout`] once a byte could not go within the poll
//! limit), `read` is [`UsciUart::read_bytes`]; its errors are of kind
//! [`LinkErrorKind::Transport`]. So `FramedLink<UsciUart<R>, N>` is a node link over polled
//! USCI_A0.
//!
//! # Receiving while the CPU computes or sleeps: [`RxRing`]
//! A node cannot poll the receiver through its 74 ms step or its LPM3 sleep. The flight images
//! therefore take each received byte in the USCIAB0RX interrupt (UCA0RXIE, vector 0xFFF2,
//! SLAS508K interrupt vector table): the handler (`firmware/src/uart_link.rs`, a few
//! instructions of assembly) stores UCA0RXBUF at index `count mod` [`RX_RING_BYTES`] of a RAM
//! ring and increments a free-running 16-bit `count`; the loop takes the bytes with
//! [`RxRing::read`], which detects a ring the handler lapped (more than [`RX_RING_BYTES`] bytes
//! not taken) and reports it as [`UartError::Overrun`] (the bytes in it are dropped; the
//! framing above loses that frame only).

use core::fmt;

use super::{Registers, IFG2};
use crate::hal::link::{ByteStream, Error as LinkError, ErrorKind as LinkErrorKind, ErrorType};

/// USCI_A0 control register 0.
pub const UCA0CTL0: u16 = 0x0060;
/// USCI_A0 control register 1.
pub const UCA0CTL1: u16 = 0x0061;
/// USCI_A0 baud-rate prescaler, low byte.
pub const UCA0BR0: u16 = 0x0062;
/// USCI_A0 baud-rate prescaler, high byte.
pub const UCA0BR1: u16 = 0x0063;
/// USCI_A0 modulation control.
pub const UCA0MCTL: u16 = 0x0064;
/// USCI_A0 status.
pub const UCA0STAT: u16 = 0x0065;
/// USCI_A0 receive buffer.
pub const UCA0RXBUF: u16 = 0x0066;
/// USCI_A0 transmit buffer.
pub const UCA0TXBUF: u16 = 0x0067;
/// P2SEL, the function select of UCA0TXD (P2.4) and UCA0RXD (P2.5).
pub const P2SEL: u16 = 0x002E;

/// Bit names of the USCI_A0 registers in UART mode (SLAU056 "USCI_A Control and Status
/// Registers").
pub mod bits {
    /// UCA0CTL1: UCSSELx = 10, BRCLK = SMCLK.
    pub const UCSSEL_SMCLK: u8 = 0x80;
    /// UCA0CTL1: erroneous characters set UCA0RXIFG.
    pub const UCRXEIE: u8 = 0x20;
    /// UCA0CTL1: software reset.
    pub const UCSWRST: u8 = 0x01;
    /// UCA0STAT: framing error.
    pub const UCFE: u8 = 0x40;
    /// UCA0STAT: overrun error.
    pub const UCOE: u8 = 0x20;
    /// UCA0STAT: parity error.
    pub const UCPE: u8 = 0x10;
    /// UCA0STAT: break detected.
    pub const UCBRK: u8 = 0x08;
    /// UCA0STAT: receive error (one of UCFE, UCPE, UCOE).
    pub const UCRXERR: u8 = 0x04;
    /// IFG2: UCA0RXBUF holds a byte.
    pub const UCA0RXIFG: u8 = 0x01;
    /// IFG2: UCA0TXBUF is empty.
    pub const UCA0TXIFG: u8 = 0x02;
    /// P2SEL: P2.4 (TXD) and P2.5 (RXD).
    pub const P2_TXD_RXD: u8 = 0x30;
}

use bits::*;

/// The baud-rate generator's settings (low-frequency mode) and the bound on a write's wait.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UartConfig {
    ucbr: u16,
    ucbrs: u8,
    poll_limit: u16,
}

impl UartConfig {
    /// 115 200 Bd from [`super::SMCLK_HZ`]: UCBRx = 69, UCBRSx = 3; 200 polls per byte
    /// (`UartConfig::new(SMCLK_HZ, 115_200, 200)`, checked by a test).
    pub const FLIGHT: Self = Self {
        ucbr: 69,
        ucbrs: 3,
        poll_limit: 200,
    };

    /// `baud` from a BRCLK of `brclk_hz` in low-frequency mode, a write waiting at most
    /// `poll_limit` polls per byte. `None` if UCBRx would be below 3 (the mode's limit, baud
    /// ≤ f_BRCLK / 3) or above 65 535, or `poll_limit` is 0.
    pub const fn new(brclk_hz: u32, baud: u32, poll_limit: u16) -> Option<Self> {
        if baud == 0 || poll_limit == 0 {
            return None;
        }
        let int = brclk_hz / baud;
        let rem = brclk_hz - int * baud;
        // round(8 · rem / baud)
        let frac8 = (16 * (rem as u64) + baud as u64) / (2 * baud as u64);
        let (ucbr, ucbrs) = if frac8 >= 8 {
            (int + 1, 0)
        } else {
            (int, frac8 as u32)
        };
        if 3 > ucbr || ucbr > 0xFFFF {
            return None;
        }
        Some(Self {
            ucbr: ucbr as u16,
            ucbrs: ucbrs as u8,
            poll_limit,
        })
    }

    /// UCBRx.
    pub const fn ucbr(&self) -> u16 {
        self.ucbr
    }

    /// UCBRSx, the second-stage modulation (0–7).
    pub const fn ucbrs(&self) -> u8 {
        self.ucbrs
    }

    /// The mean rate from a BRCLK of `brclk_hz`, Bd: f_BRCLK / (UCBRx + UCBRSx / 8).
    pub const fn mean_baud(&self, brclk_hz: u32) -> u32 {
        ((8 * brclk_hz as u64) / (8 * self.ucbr as u64 + self.ucbrs as u64)) as u32
    }
}

/// A UART failure.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum UartError {
    /// A byte arrived before the previous one was read; one was lost.
    Overrun,
    /// A byte's stop bit was low.
    Framing,
    /// A byte's parity was wrong (parity is off in the flight configuration).
    Parity,
    /// A break (the line held low a whole character) was received.
    Break,
    /// The transmit buffer did not free within the poll limit.
    Timeout,
}

impl fmt::Display for UartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Overrun => "UART overrun",
            Self::Framing => "UART framing error",
            Self::Parity => "UART parity error",
            Self::Break => "UART break",
            Self::Timeout => "UART transmit timeout",
        })
    }
}

/// The error a UCA0STAT value reports, if any.
fn receive_error(stat: u8) -> Option<UartError> {
    if stat & UCOE != 0 {
        Some(UartError::Overrun)
    } else if stat & UCBRK != 0 {
        Some(UartError::Break)
    } else if stat & UCFE != 0 {
        Some(UartError::Framing)
    } else if stat & UCPE != 0 {
        Some(UartError::Parity)
    } else {
        None
    }
}

/// USCI_A0 as a UART (8N1).
pub struct UsciUart<R> {
    regs: R,
    config: UartConfig,
}

impl<R: Registers> UsciUart<R> {
    /// Configures USCI_A0 as the UART of `config` (held in UCSWRST while its registers and
    /// P2.4/P2.5 are set up, then released) and returns its driver.
    pub fn new(mut regs: R, config: UartConfig) -> Self {
        let [lo, hi] = config.ucbr.to_le_bytes();
        regs.write8(UCA0CTL1, UCSWRST | UCSSEL_SMCLK);
        regs.write8(UCA0CTL0, 0);
        regs.write8(UCA0BR0, lo);
        regs.write8(UCA0BR1, hi);
        // UCBRSx in bits 3–1, UCBRFx = 0, UCOS16 = 0
        regs.write8(UCA0MCTL, (config.ucbrs & 7) << 1);
        regs.set_bits8(P2SEL, P2_TXD_RXD);
        regs.write8(UCA0CTL1, UCSSEL_SMCLK | UCRXEIE);
        Self { regs, config }
    }

    /// Gives the register access back.
    pub fn release(self) -> R {
        self.regs
    }

    /// Writes `bytes` as the transmitter takes them, waiting at most the poll limit for each;
    /// the number written. [`UartError::Timeout`] if the first could not be written.
    pub fn write_bytes(&mut self, bytes: &[u8]) -> Result<usize, UartError> {
        for (n, &b) in bytes.iter().enumerate() {
            let mut free = false;
            for _ in 0..self.config.poll_limit {
                if self.regs.read8(IFG2) & UCA0TXIFG != 0 {
                    free = true;
                    break;
                }
            }
            if !free {
                return if n == 0 {
                    Err(UartError::Timeout)
                } else {
                    Ok(n)
                };
            }
            self.regs.write8(UCA0TXBUF, b);
        }
        Ok(bytes.len())
    }

    /// Reads the bytes already received into `buf`, without waiting; the number read. A
    /// receive error is returned when it is the first thing met (its byte is discarded).
    pub fn read_bytes(&mut self, buf: &mut [u8]) -> Result<usize, UartError> {
        for (n, slot) in buf.iter_mut().enumerate() {
            if self.regs.read8(IFG2) & UCA0RXIFG == 0 {
                return Ok(n);
            }
            let error = receive_error(self.regs.read8(UCA0STAT));
            if let Some(e) = error {
                if n > 0 {
                    // the good bytes first; the bad one is the next call's
                    return Ok(n);
                }
                // reading the buffer clears the flags
                let _ = self.regs.read8(UCA0RXBUF);
                return Err(e);
            }
            *slot = self.regs.read8(UCA0RXBUF);
        }
        Ok(buf.len())
    }
}

impl LinkError for UartError {
    /// Every UART failure is the link's transport failing.
    fn kind(&self) -> LinkErrorKind {
        LinkErrorKind::Transport
    }
}

impl<R: Registers> ErrorType for UsciUart<R> {
    type Error = UartError;
}

impl<R: Registers> ByteStream for UsciUart<R> {
    /// All of `bytes`, each waiting at most the poll limit ([`UsciUart::write_bytes`]);
    /// [`UartError::Timeout`] as soon as one cannot go (the bytes before it are on the line).
    fn write(&mut self, bytes: &[u8]) -> Result<(), UartError> {
        let mut rest = bytes;
        while !rest.is_empty() {
            let n = self.write_bytes(rest)?;
            // `write_bytes` wrote at least one byte (else it returned the timeout)
            rest = rest.get(core::cmp::max(n, 1)..).unwrap_or(&[]);
        }
        Ok(())
    }

    /// [`UsciUart::read_bytes`].
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, UartError> {
        self.read_bytes(buf)
    }
}

/// Bytes of the receive ring of the flight images ([`RxRing`]): a power of two, more than a
/// whole frame of the link (the longest packet, 113 B, COBS-framed: 116 B).
pub const RX_RING_BYTES: u16 = 128;

/// The loop's side of the receive ring the USCIAB0RX handler fills (see the
/// [module docs](self), "Receiving while the CPU computes or sleeps"): how far it has read.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct RxRing {
    /// The handler's count at the last byte taken (free-running, wrapping).
    taken: u16,
}

impl RxRing {
    /// A reader that has taken nothing: it must start with the handler's count at 0 (both
    /// start at reset), or be [`RxRing::resync`]ed.
    pub const fn new() -> Self {
        Self { taken: 0 }
    }

    /// Drops every byte not taken: the next read starts at the handler's count `count`.
    pub fn resync(&mut self, count: u16) {
        self.taken = count;
    }

    /// Moves the bytes received and not yet taken (at most `buf.len()`) into `buf`, and returns
    /// how many. `count` reads the handler's free-running count (a single word read: atomic on
    /// the MSP430), `byte(i)` the ring's byte at index `i` (below [`RX_RING_BYTES`]). If the
    /// handler lapped the reader (more than [`RX_RING_BYTES`] bytes pending, before or while the
    /// bytes are copied), every pending byte is dropped and [`UartError::Overrun`] returned.
    pub fn read(
        &mut self,
        mut count: impl FnMut() -> u16,
        mut byte: impl FnMut(usize) -> u8,
        buf: &mut [u8],
    ) -> Result<usize, UartError> {
        let head = count();
        let pending = head.wrapping_sub(self.taken);
        if pending > RX_RING_BYTES {
            self.taken = head;
            return Err(UartError::Overrun);
        }
        let start = self.taken;
        let mut n = 0;
        for slot in buf.iter_mut().take(usize::from(pending)) {
            *slot = byte(usize::from(self.taken % RX_RING_BYTES));
            self.taken = self.taken.wrapping_add(1);
            n += 1;
        }
        // the handler may have written over the slots just copied
        let now = count();
        if now.wrapping_sub(start) > RX_RING_BYTES {
            self.taken = now;
            return Err(UartError::Overrun);
        }
        Ok(n)
    }
}
