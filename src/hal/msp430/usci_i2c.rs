//! USCI_B0 as an I²C master: `embedded_hal::i2c::I2c` for the tile sensors' bus.
//!
//! Source: SLAU056L, "Universal Serial Communication Interface, I2C Mode": "USCI Initialization
//! and Reset" (the UCSWRST sequence), "I2C Master Mode" ("I2C Master Transmitter Mode", "I2C
//! Master Receiver Mode", "Arbitration"), "I2C Clock Generation" (f_SCL = f_BRCLK / UCBRx) and
//! the table "USCI_B Control and Status Registers" (UCB0CTL0, UCB0CTL1, UCB0BR0/1, UCB0STAT,
//! UCB0RXBUF, UCB0TXBUF, UCB0I2CSA; IFG2's UCB0TXIFG/UCB0RXIFG). Addresses: SLAS508K
//! peripheral file map. Pins: SLAS508K "Port P3, P3.0 to P3.3" (UCB0SDA on P3.1, UCB0SCL on
//! P3.2, P3SEL bits set; the direction bit does not matter).
//!
//! # Configuration
//! 7-bit addressing, single master, BRCLK = SMCLK. [`I2cConfig::FLIGHT`]: UCBRx = 80 from
//! SMCLK = 7 995 392 Hz, f_SCL = 99 942 Hz (standard mode; the prescaler is rounded up so the
//! clock never exceeds the rate asked for).
//!
//! # Protocol (polled, every wait bounded by [`I2cConfig`]'s poll limit)
//! A transaction's operations run as the `embedded-hal` contract says: a START before the
//! first, a repeated START where the direction changes, consecutive operations of one direction
//! merged, a STOP after the last.
//! - **Write**: UCTR and UCTXSTT set; each byte written to UCB0TXBUF when UCB0TXIFG is set
//!   (the first right after the START, before the address is acknowledged); after the last byte,
//!   UCB0TXIFG again (the byte moved to the shift register: the previous one, or the address,
//!   was acknowledged), then UCTXSTP (or a repeated START) takes effect after its acknowledge.
//!   A write of no byte waits for UCTXSTT to clear (the address acknowledged) instead.
//! - **Read**: UCTR cleared and UCTXSTT set; each byte read from UCB0RXBUF when UCB0RXIFG is
//!   set. UCTXSTP (or a repeated START) must be set *while the last byte is being received*: as
//!   soon as the byte before it is in UCB0RXBUF (before reading it), or, for a single byte, as
//!   soon as UCTXSTT clears ("I2C Master Receiver Mode"); one write of UCB0CTL1, not a
//!   read-modify-write. UCB0RXBUF is read as soon as UCB0RXIFG is seen, well inside the
//!   window of erratum USCI30 (the next byte's 7th bit, 60 µs at 100 kHz).
//! - **Errors**: UCNACKIFG → [`I2cError::AddressNack`] until the address is known acknowledged
//!   (the first UCB0RXIFG, or the UCB0TXIFG after the first byte), [`I2cError::DataNack`] after,
//!   and [`I2cError::Nack`] (source unknown) before the address of a repeated START that
//!   follows a write is acknowledged (the last byte written is acknowledged after the repeated
//!   START is requested: its NACK and the new address's come in the same window);
//!   UCALIFG → [`I2cError::ArbitrationLost`] (the USCI has dropped to slave mode); a flag that
//!   does not come within the poll limit → [`I2cError::Timeout`]. After any error the driver
//!   sends a STOP (unless arbitration was lost), waits for it (bounded), and re-initialises the
//!   module through UCSWRST, which clears every flag and restores master mode; the next
//!   transaction starts clean. (Erratum USCI25, UCB0TXIFG left set after a NACK when a repeated
//!   START follows, does not arise: a NACK always ends the transaction with a STOP and a reset.)
//!
//! A poll is 11 MCLK cycles (measured, [`super`] "Measured figures"): the flight limit of 1 000
//! polls is 1.4 ms, 15 byte times at 100 kHz, room for a slave's clock stretching; a stuck bus
//! costs the loop that once per transfer, then the driver's reset.

use core::fmt;

use embedded_hal::i2c::{self, Operation, SevenBitAddress};

use super::{Registers, IFG2};

/// USCI_B0 control register 0.
pub const UCB0CTL0: u16 = 0x0068;
/// USCI_B0 control register 1.
pub const UCB0CTL1: u16 = 0x0069;
/// USCI_B0 bit-rate prescaler, low byte.
pub const UCB0BR0: u16 = 0x006A;
/// USCI_B0 bit-rate prescaler, high byte.
pub const UCB0BR1: u16 = 0x006B;
/// USCI_B0 I²C interrupt enable.
pub const UCB0I2CIE: u16 = 0x006C;
/// USCI_B0 status.
pub const UCB0STAT: u16 = 0x006D;
/// USCI_B0 receive buffer.
pub const UCB0RXBUF: u16 = 0x006E;
/// USCI_B0 transmit buffer.
pub const UCB0TXBUF: u16 = 0x006F;
/// USCI_B0 I²C slave address (word).
pub const UCB0I2CSA: u16 = 0x011A;
/// P3SEL, the function select of UCB0SDA (P3.1) and UCB0SCL (P3.2).
pub const P3SEL: u16 = 0x001B;

/// Bit names of the USCI_B0 registers in I²C mode (SLAU056 "USCI_B Control and Status
/// Registers").
pub mod bits {
    /// UCB0CTL0: master mode.
    pub const UCMST: u8 = 0x08;
    /// UCB0CTL0: UCMODEx = 11, I²C.
    pub const UCMODE_I2C: u8 = 0x06;
    /// UCB0CTL0: synchronous mode (set in I²C mode).
    pub const UCSYNC: u8 = 0x01;
    /// UCB0CTL1: UCSSELx = 10, BRCLK = SMCLK.
    pub const UCSSEL_SMCLK: u8 = 0x80;
    /// UCB0CTL1: transmitter.
    pub const UCTR: u8 = 0x10;
    /// UCB0CTL1: generate a STOP.
    pub const UCTXSTP: u8 = 0x04;
    /// UCB0CTL1: generate a (repeated) START.
    pub const UCTXSTT: u8 = 0x02;
    /// UCB0CTL1: software reset.
    pub const UCSWRST: u8 = 0x01;
    /// UCB0STAT: SCL held low.
    pub const UCSCLLOW: u8 = 0x40;
    /// UCB0STAT: bus busy (between a START and a STOP).
    pub const UCBBUSY: u8 = 0x10;
    /// UCB0STAT: not-acknowledge received.
    pub const UCNACKIFG: u8 = 0x08;
    /// UCB0STAT: arbitration lost.
    pub const UCALIFG: u8 = 0x01;
    /// IFG2: UCB0RXBUF holds a byte.
    pub const UCB0RXIFG: u8 = 0x04;
    /// IFG2: UCB0TXBUF is empty.
    pub const UCB0TXIFG: u8 = 0x08;
    /// P3SEL: P3.1 (SDA) and P3.2 (SCL).
    pub const P3_SDA_SCL: u8 = 0x06;
}

use bits::*;

/// The bus's configuration: the SCL prescaler and the bound on every wait.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct I2cConfig {
    prescaler: u16,
    poll_limit: u16,
}

impl I2cConfig {
    /// The flight configuration: 100 kHz (99 942 Hz) from [`super::SMCLK_HZ`], 1 000 polls per
    /// wait (`I2cConfig::new(SMCLK_HZ, 100_000, 1_000)`, checked by a test).
    pub const FLIGHT: Self = Self {
        prescaler: 80,
        poll_limit: 1_000,
    };

    /// SCL at most `scl_hz` from a BRCLK of `brclk_hz` (UCBRx = ⌈brclk / scl⌉), every wait
    /// bounded by `poll_limit` polls. `None` if UCBRx would be below 4 (the single-master
    /// maximum of f_BRCLK / 4) or above 65 535, or `poll_limit` is 0.
    pub const fn new(brclk_hz: u32, scl_hz: u32, poll_limit: u16) -> Option<Self> {
        if scl_hz == 0 || poll_limit == 0 {
            return None;
        }
        let prescaler = brclk_hz.div_ceil(scl_hz);
        if 4 > prescaler || prescaler > 0xFFFF {
            return None;
        }
        Some(Self {
            prescaler: prescaler as u16,
            poll_limit,
        })
    }

    /// UCBRx, the SCL prescaler.
    pub const fn prescaler(&self) -> u16 {
        self.prescaler
    }

    /// The SCL frequency from a BRCLK of `brclk_hz`, Hz.
    pub const fn scl_hz(&self, brclk_hz: u32) -> u32 {
        brclk_hz / self.prescaler as u32
    }
}

/// Why a transaction failed.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum I2cError {
    /// No device acknowledged the address.
    AddressNack,
    /// The device did not acknowledge a data byte.
    DataNack,
    /// Not acknowledged, either the last byte written before a repeated START or the address
    /// after it (the two are not told apart by the flags: both arrive before the driver can
    /// look).
    Nack,
    /// Another master won the bus.
    ArbitrationLost,
    /// A flag did not come within the poll limit (a stuck bus, a slave stretching the clock too
    /// long).
    Timeout,
    /// A read of no byte (the USCI always receives at least one byte after a read address).
    EmptyRead,
    /// An address above 0x7F (7-bit addressing).
    BadAddress,
}

impl fmt::Display for I2cError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::AddressNack => "I2C address not acknowledged",
            Self::DataNack => "I2C data not acknowledged",
            Self::Nack => "I2C byte or address not acknowledged",
            Self::ArbitrationLost => "I2C arbitration lost",
            Self::Timeout => "I2C timeout",
            Self::EmptyRead => "I2C read of no byte",
            Self::BadAddress => "I2C address beyond 7 bits",
        })
    }
}

impl i2c::Error for I2cError {
    fn kind(&self) -> i2c::ErrorKind {
        use i2c::{ErrorKind, NoAcknowledgeSource};
        match self {
            Self::AddressNack => ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address),
            Self::DataNack => ErrorKind::NoAcknowledge(NoAcknowledgeSource::Data),
            Self::Nack => ErrorKind::NoAcknowledge(NoAcknowledgeSource::Unknown),
            Self::ArbitrationLost => ErrorKind::ArbitrationLoss,
            // embedded-hal 1.0 has no timeout kind
            Self::Timeout | Self::EmptyRead | Self::BadAddress => ErrorKind::Other,
        }
    }
}

impl crate::hal::Error for I2cError {
    fn kind(&self) -> crate::hal::ErrorKind {
        use crate::hal::ErrorKind;
        match self {
            Self::AddressNack => ErrorKind::DeviceAbsent,
            Self::DataNack | Self::Nack | Self::ArbitrationLost => ErrorKind::Bus,
            Self::Timeout => ErrorKind::Timeout,
            Self::EmptyRead | Self::BadAddress => ErrorKind::Other,
        }
    }
}

/// What follows an operation.
#[derive(Copy, Clone, PartialEq, Eq)]
enum End {
    /// The next operation has the same direction: its bytes follow without a START.
    Continue,
    /// A repeated START, reading (`true`) or writing.
    Restart(bool),
    /// The transaction's STOP.
    Stop,
}

/// The progress of the current segment (the bytes between two STARTs, or a START and a STOP).
#[derive(Copy, Clone, Default)]
struct Segment {
    /// Bytes written to UCB0TXBUF or read from UCB0RXBUF.
    bytes: u16,
    /// The address is known to have been acknowledged.
    acked: bool,
    /// The segment began with a repeated START after a write: a NACK before its address is
    /// acknowledged may be the previous byte's.
    after_write: bool,
}

/// USCI_B0 as an I²C master. Each handle borrows its configuration (a `static` or a
/// constant such as [`I2cConfig::FLIGHT`]): the attitude node holds one handle per device in
/// its stack frame, and a reference is half a configuration's 4 B (the flight image's stack
/// bound fell by 108 B with it).
pub struct UsciI2c<R> {
    regs: R,
    config: &'static I2cConfig,
}

impl<R: Registers> UsciI2c<R> {
    /// Configures USCI_B0 as the I²C master of `config` (the module held in UCSWRST while its
    /// registers and P3.1/P3.2 are set up, then released) and returns its driver.
    pub fn new(regs: R, config: &'static I2cConfig) -> Self {
        let mut bus = Self::attach(regs, config);
        bus.regs.write8(UCB0CTL1, UCSWRST | UCSSEL_SMCLK);
        bus.regs.set_bits8(P3SEL, P3_SDA_SCL);
        bus.reset();
        bus
    }

    /// A driver for a USCI_B0 already configured by [`UsciI2c::new`] (with the same `config`),
    /// without touching it: one handle per device driver on the bus when the register access
    /// is a shared zero-sized type (the firmware's). The handles must not be used concurrently
    /// (the flight loop is single-threaded and no interrupt uses the bus).
    pub fn attach(regs: R, config: &'static I2cConfig) -> Self {
        Self { regs, config }
    }

    /// Gives the register access back.
    pub fn release(self) -> R {
        self.regs
    }

    /// UCSWRST set, the master configuration written, UCSWRST cleared: every flag cleared,
    /// master mode restored (SLAU056 "USCI Initialization and Reset").
    fn reset(&mut self) {
        let [lo, hi] = self.config.prescaler.to_le_bytes();
        self.regs.write8(UCB0CTL1, UCSWRST | UCSSEL_SMCLK);
        self.regs.write8(UCB0CTL0, UCMST | UCMODE_I2C | UCSYNC);
        self.regs.write8(UCB0BR0, lo);
        self.regs.write8(UCB0BR1, hi);
        self.regs.write8(UCB0I2CIE, 0);
        self.regs.write8(UCB0CTL1, UCSSEL_SMCLK);
    }

    /// Polls until bit `mask` of `addr` is set (`set`) or clear; a NACK or a lost arbitration
    /// ends the wait first, the poll limit last.
    fn wait(&mut self, addr: u16, mask: u8, set: bool, seg: &Segment) -> Result<(), I2cError> {
        for _ in 0..self.config.poll_limit {
            let stat = self.regs.read8(UCB0STAT);
            if stat & UCALIFG != 0 {
                return Err(I2cError::ArbitrationLost);
            }
            if stat & UCNACKIFG != 0 {
                return Err(if seg.acked {
                    I2cError::DataNack
                } else if seg.after_write {
                    I2cError::Nack
                } else {
                    I2cError::AddressNack
                });
            }
            let value = if addr == UCB0STAT {
                stat
            } else {
                self.regs.read8(addr)
            };
            if (value & mask != 0) == set {
                return Ok(());
            }
        }
        Err(I2cError::Timeout)
    }

    /// A (repeated) START, reading or writing.
    fn start(&mut self, read: bool) {
        let tr = if read { 0 } else { UCTR };
        self.regs.write8(UCB0CTL1, UCSSEL_SMCLK | tr | UCTXSTT);
    }

    /// Requests what follows the byte on the bus: a STOP or a repeated START. One write of
    /// UCB0CTL1 (its value is known: UCTXSTT clear, UCTR `tr`), no read-modify-write: the
    /// request is made as early as it can be.
    fn request_end(&mut self, end: End, tr: u8) {
        match end {
            End::Continue => {}
            End::Restart(read) => self.start(read),
            End::Stop => self.regs.write8(UCB0CTL1, UCSSEL_SMCLK | tr | UCTXSTP),
        }
    }

    fn write_segment(&mut self, bytes: &[u8], end: End, seg: &mut Segment) -> Result<(), I2cError> {
        for &b in bytes {
            self.wait(IFG2, UCB0TXIFG, true, seg)?;
            // a free buffer after a byte was written: that byte reached the shift register,
            // so the address was acknowledged
            seg.acked |= seg.bytes > 0;
            self.regs.write8(UCB0TXBUF, b);
            seg.bytes = seg.bytes.saturating_add(1);
        }
        if end == End::Continue {
            return Ok(());
        }
        if seg.bytes > 0 {
            // the last byte in the shift register
            self.wait(IFG2, UCB0TXIFG, true, seg)?;
        } else {
            // no data: the address acknowledged
            self.wait(UCB0CTL1, UCTXSTT, false, seg)?;
        }
        seg.acked = true;
        self.request_end(end, UCTR);
        match end {
            End::Stop => self.wait(UCB0CTL1, UCTXSTP, false, seg),
            _ => {
                *seg = Segment {
                    after_write: true,
                    ..Segment::default()
                };
                Ok(())
            }
        }
    }

    fn read_segment(
        &mut self,
        buf: &mut [u8],
        end: End,
        seg: &mut Segment,
    ) -> Result<(), I2cError> {
        let n = buf.len();
        let ends = end != End::Continue;
        if ends && n == 1 {
            if seg.bytes == 0 {
                // a single byte: it is being received once the address is acknowledged
                self.wait(UCB0CTL1, UCTXSTT, false, seg)?;
            }
            // NACK + STOP (or a repeated START) after the byte being received
            self.request_end(end, 0);
        }
        for (k, slot) in buf.iter_mut().enumerate() {
            self.wait(IFG2, UCB0RXIFG, true, seg)?;
            seg.acked = true;
            if ends && k + 2 == n {
                // byte k is in the buffer, so the last byte is being received: request the
                // end before reading byte k, the earliest moment
                self.request_end(end, 0);
            }
            *slot = self.regs.read8(UCB0RXBUF);
            seg.bytes = seg.bytes.saturating_add(1);
        }
        match end {
            End::Continue => Ok(()),
            End::Stop => self.wait(UCB0CTL1, UCTXSTP, false, seg),
            End::Restart(_) => {
                *seg = Segment::default();
                Ok(())
            }
        }
    }

    fn run(&mut self, operations: &mut [Operation<'_>]) -> Result<(), I2cError> {
        let mut seg = Segment::default();
        for i in 0..operations.len() {
            let next = operations.get(i + 1).map(is_read);
            let Some(op) = operations.get_mut(i) else {
                break;
            };
            let read = is_read(op);
            let end = match next {
                None => End::Stop,
                Some(r) if r == read => End::Continue,
                Some(r) => End::Restart(r),
            };
            if i == 0 {
                self.start(read);
            }
            match op {
                Operation::Write(bytes) => self.write_segment(bytes, end, &mut seg)?,
                Operation::Read(buf) => self.read_segment(buf, end, &mut seg)?,
            }
        }
        Ok(())
    }

    /// After an error: a STOP unless arbitration was lost (bounded wait), then the reset.
    fn recover(&mut self, error: I2cError) {
        if error != I2cError::ArbitrationLost {
            // clear the flags (UCBBUSY and UCSCLLOW are read-only), then STOP
            self.regs.write8(UCB0STAT, 0);
            self.regs.set_bits8(UCB0CTL1, UCTXSTP);
            let _ = self.wait(UCB0CTL1, UCTXSTP, false, &Segment::default());
        }
        self.reset();
    }
}

fn is_read(op: &Operation<'_>) -> bool {
    matches!(op, Operation::Read(_))
}

impl<R: Registers> i2c::ErrorType for UsciI2c<R> {
    type Error = I2cError;
}

impl<R: Registers> i2c::I2c<SevenBitAddress> for UsciI2c<R> {
    fn transaction(
        &mut self,
        address: SevenBitAddress,
        operations: &mut [Operation<'_>],
    ) -> Result<(), I2cError> {
        if address > 0x7F {
            return Err(I2cError::BadAddress);
        }
        if operations
            .iter()
            .any(|op| matches!(op, Operation::Read(b) if b.is_empty()))
        {
            return Err(I2cError::EmptyRead);
        }
        if operations.is_empty() {
            return Ok(());
        }
        // the previous STOP sent, no other master on the bus
        if let Err(e) = self.wait(UCB0STAT, UCBBUSY, false, &Segment::default()) {
            self.reset();
            return Err(e);
        }
        self.regs.write16(UCB0I2CSA, u16::from(address));
        let result = self.run(operations);
        if let Err(e) = result {
            self.recover(e);
        }
        result
    }
}
