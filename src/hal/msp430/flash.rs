//! The flash memory controller: segment erase and word write.
//!
//! Source: SLAU056L, "Flash Memory Controller": "Flash Memory Segmentation" (main memory in
//! 512-byte segments on 512-byte boundaries, information memory in 128-byte segments; an erase
//! sets every bit of one segment, a write can only clear bits), "Flash Memory Timing Generator"
//! (f_FTG from ACLK, MCLK or SMCLK divided by FNx + 1, within the data sheet's 257–476 kHz),
//! "Erasing Flash Memory" (segment erase: ERASE = 1, then a dummy write into the segment;
//! BUSY while it runs), "Writing Flash Memory" (byte/word write: WRT = 1, then the write), "Flash
//! Memory Access During Write or Erase" (code running from flash is held until the operation
//! ends; the interrupts must be disabled by the caller), "Flash Controller Registers"
//! (FCTL1/FCTL2/FCTL3: FWKEY = 0xA5 in the high byte of every write, else KEYV and a PUC; reads
//! return 0x96; LOCK, ACCVIFG, BUSY). Addresses: SLAS508K peripheral file map; timing:
//! SLAS508K "Flash Memory (FG461x devices only)": f_FTG 257–476 kHz, t_Word = 30 t_FTG,
//! t_Seg Erase = 4 819 t_FTG, endurance 10⁴ cycles at least.
//!
//! # Timing generator ([`FlashConfig::FLIGHT`])
//! MCLK ÷ 22 (FSSELx = 01, FNx = 21): 7 995 392 / 22 = 363 427 Hz, near the middle of the
//! 257–476 kHz range. A segment erase then takes 4 819 / f_FTG = 13.3 ms and a word write
//! 30 / f_FTG = 82.5 µs.
//!
//! Every operation unlocks the controller (LOCK cleared), runs, waits for BUSY to clear (bounded)
//! and locks it again, then checks ACCVIFG: the controller is never left unlocked between calls,
//! and a write is read back ([`FlashController::write_word`]).

use core::fmt;

use super::Registers;

/// Flash control register 1 (operation).
pub const FCTL1: u16 = 0x0128;
/// Flash control register 2 (timing generator).
pub const FCTL2: u16 = 0x012A;
/// Flash control register 3 (lock and status).
pub const FCTL3: u16 = 0x012C;

/// Bit names of the flash controller registers (SLAU056 "Flash Controller Registers").
pub mod bits {
    /// The password in the high byte of every write.
    pub const FWKEY: u16 = 0xA500;
    /// The high byte every read returns.
    pub const FRKEY: u16 = 0x9600;
    /// FCTL1: segment erase.
    pub const ERASE: u16 = 0x0002;
    /// FCTL1: byte/word write.
    pub const WRT: u16 = 0x0040;
    /// FCTL2: FSSELx = 01, MCLK.
    pub const FSSEL_MCLK: u16 = 0x0040;
    /// FCTL2: FNx mask (divider − 1).
    pub const FN_MASK: u16 = 0x003F;
    /// FCTL3: an operation is running.
    pub const BUSY: u16 = 0x0001;
    /// FCTL3: a write without the password was seen.
    pub const KEYV: u16 = 0x0002;
    /// FCTL3: access violation.
    pub const ACCVIFG: u16 = 0x0004;
    /// FCTL3: the flash is locked.
    pub const LOCK: u16 = 0x0010;
}

use bits::*;

/// Bytes in a main-memory segment.
pub const SEGMENT_BYTES: u16 = 512;

/// The timing generator's clock and divider, and the bound on a wait for BUSY.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FlashConfig {
    divider: u8,
    poll_limit: u16,
}

impl FlashConfig {
    /// MCLK ÷ 22 from [`super::SMCLK_HZ`] (363 427 Hz), 20 000 polls per wait (a poll is about
    /// 10 cycles: 25 ms, twice a segment erase) (`FlashConfig::from_mclk(SMCLK_HZ, 20_000)`,
    /// checked by a test).
    pub const FLIGHT: Self = Self {
        divider: 22,
        poll_limit: 20_000,
    };

    /// The timing generator from MCLK = `mclk_hz`, divided to the frequency just below the
    /// middle of the allowed range (⌈f_MCLK / 366 500 Hz⌉); `None` if the divider would leave
    /// 1–64 or the frequency 257–476 kHz, or `poll_limit` is 0.
    pub const fn from_mclk(mclk_hz: u32, poll_limit: u16) -> Option<Self> {
        let divider = mclk_hz.div_ceil(366_500);
        if divider == 0 || divider > 64 || poll_limit == 0 {
            return None;
        }
        let f = mclk_hz / divider;
        if !(f >= 257_000 && 476_000 >= f) {
            return None;
        }
        Some(Self {
            divider: divider as u8,
            poll_limit,
        })
    }

    /// The divider (FNx + 1).
    pub const fn divider(&self) -> u8 {
        self.divider
    }

    /// The FCTL2 word, password included.
    pub const fn fctl2(&self) -> u16 {
        FWKEY | FSSEL_MCLK | ((self.divider as u16).saturating_sub(1) & FN_MASK)
    }
}

/// A flash operation failed.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FlashError {
    /// The controller flagged an access violation (ACCVIFG).
    AccessViolation,
    /// BUSY did not clear within the poll limit.
    Timeout,
    /// A written word did not read back (a bit that was not erased).
    Verify {
        /// The word's address.
        address: u16,
    },
}

impl fmt::Display for FlashError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::AccessViolation => f.write_str("flash access violation"),
            Self::Timeout => f.write_str("flash controller busy too long"),
            Self::Verify { address } => write!(f, "flash word at {address:#06x} did not verify"),
        }
    }
}

/// The flash controller.
pub struct FlashController<R> {
    regs: R,
    config: FlashConfig,
}

impl<R: Registers> FlashController<R> {
    /// Sets the timing generator of `config` and locks the flash.
    pub fn new(mut regs: R, config: FlashConfig) -> Self {
        regs.write16(FCTL2, config.fctl2());
        regs.write16(FCTL3, FWKEY | LOCK);
        Self { regs, config }
    }

    /// Gives the register access back.
    pub fn release(self) -> R {
        self.regs
    }

    /// Reads the flash word at the even address `addr`.
    pub fn read_word(&mut self, addr: u16) -> u16 {
        self.regs.read16(addr)
    }

    /// Erases the segment holding `addr` (every bit set).
    pub fn erase_segment(&mut self, addr: u16) -> Result<(), FlashError> {
        self.operation(ERASE, addr & !1, 0)
    }

    /// Writes `value` at the even address `addr`, which must be erased (a write only clears
    /// bits), and reads it back.
    pub fn write_word(&mut self, addr: u16, value: u16) -> Result<(), FlashError> {
        let addr = addr & !1;
        self.operation(WRT, addr, value)?;
        if self.regs.read16(addr) != value {
            return Err(FlashError::Verify { address: addr });
        }
        Ok(())
    }

    /// Unlock, FCTL1 = `mode`, the write that starts the operation, wait, ACCVIFG read, FCTL1
    /// cleared, lock (the FCTL3 write also clears ACCVIFG: it is read before).
    fn operation(&mut self, mode: u16, addr: u16, value: u16) -> Result<(), FlashError> {
        self.wait_idle()?;
        self.regs.write16(FCTL3, FWKEY);
        self.regs.write16(FCTL1, FWKEY | mode);
        self.regs.write16(addr, value);
        let waited = self.wait_idle();
        let violation = self.regs.read16(FCTL3) & ACCVIFG != 0;
        self.regs.write16(FCTL1, FWKEY);
        self.regs.write16(FCTL3, FWKEY | LOCK);
        waited?;
        if violation {
            return Err(FlashError::AccessViolation);
        }
        Ok(())
    }

    fn wait_idle(&mut self) -> Result<(), FlashError> {
        for _ in 0..self.config.poll_limit {
            if self.regs.read16(FCTL3) & BUSY == 0 {
                return Ok(());
            }
        }
        Err(FlashError::Timeout)
    }
}
