//! The flash controller and the flash memory (SLAU056L "Flash Memory Controller"; SLAS508K
//! §6.8 and "Flash Memory (FG461x devices only)").
//!
//! - FCTL1–3: a write without 0xA5 in the high byte is refused (KEYV; on the part a PUC) and
//!   counted as a violation; reads return 0x96 in the high byte. FCTL3 starts with LOCK set.
//! - A write into flash (0x1000–0x10FF information memory, 0x2100–0xFFFF main memory) with LOCK
//!   set, or with neither ERASE nor WRT, sets ACCVIFG and changes nothing. With ERASE, it erases
//!   the whole segment holding the address (512-byte main segments on 512-byte boundaries,
//!   128-byte information segments). With WRT, a word write ANDs the word into the memory: it
//!   can only clear bits; programming a 1 over a 0 is a violation (erase-before-write). Byte
//!   writes into flash are violations (the drivers write words).
//! - The timing generator (FCTL2) must give 257–476 kHz from the model's clocks when an
//!   operation starts (a violation otherwise).
//! - Each operation keeps BUSY set for `busy_polls` reads of FCTL3; a write into flash while BUSY
//!   is a violation.
//! - Erases per segment and word writes are counted. `power_budget`: the number of operations
//!   that still complete; the next one and all after are lost (the power is gone) until
//!   [`FlashModel::power_on`].

use std::collections::BTreeMap;

use acs::hal::msp430::flash::bits::*;

pub struct FlashModel {
    /// The 64 KiB address space's memory (flash erased, RAM zero).
    pub memory: Vec<u8>,
    pub fctl1: u16,
    pub fctl2: u16,
    pub fctl3: u16,
    busy: u32,
    pub busy_polls: u32,
    pub mclk_hz: u32,
    pub aclk_hz: u32,
    /// Segment start → erases.
    pub erases: BTreeMap<u16, u32>,
    pub word_writes: u32,
    pub key_violations: u32,
    pub access_violations: u32,
    pub power_budget: Option<u32>,
    pub powered: bool,
    /// The next write into flash is refused with ACCVIFG (as a write into a segment being
    /// erased would be).
    pub refuse_next: bool,
    pub violations: Vec<String>,
}

impl Default for FlashModel {
    fn default() -> Self {
        let mut memory = vec![0xFF; 0x1_0000];
        memory[..0x1000].fill(0);
        memory[0x1100..0x2100].fill(0);
        Self {
            memory,
            fctl1: 0,
            fctl2: 0x42,
            fctl3: LOCK,
            busy: 0,
            busy_polls: 2,
            mclk_hz: acs::hal::msp430::SMCLK_HZ,
            aclk_hz: acs::hal::msp430::ACLK_HZ,
            erases: BTreeMap::new(),
            word_writes: 0,
            key_violations: 0,
            access_violations: 0,
            power_budget: None,
            powered: true,
            refuse_next: false,
            violations: Vec::new(),
        }
    }
}

fn is_flash(addr: u16) -> bool {
    (0x1000..0x1100).contains(&addr) || addr >= 0x2100
}

impl FlashModel {
    /// Power back: the controller in its reset state, the memory as it was.
    pub fn power_on(&mut self) {
        self.powered = true;
        self.power_budget = None;
        self.fctl1 = 0;
        self.fctl3 = LOCK;
        self.busy = 0;
    }

    /// The segment holding `addr`.
    pub fn segment_of(addr: u16) -> (u16, u16) {
        if addr < 0x1100 {
            (addr & !127, 128)
        } else {
            (addr & !511, 512)
        }
    }

    pub fn word(&self, addr: u16) -> u16 {
        let a = usize::from(addr);
        u16::from_le_bytes([self.memory[a], self.memory[a + 1]])
    }

    pub fn set_word(&mut self, addr: u16, value: u16) {
        let a = usize::from(addr);
        self.memory[a..a + 2].copy_from_slice(&value.to_le_bytes());
    }

    pub fn read8(&mut self, addr: u16) -> u8 {
        self.memory[usize::from(addr)]
    }

    pub fn read16(&mut self, addr: u16) -> u16 {
        self.word(addr)
    }

    pub fn read_control(&mut self, addr: u16) -> u16 {
        match addr {
            0x128 => FRKEY | self.fctl1,
            0x12A => FRKEY | self.fctl2,
            _ => {
                let busy = if self.busy > 0 {
                    self.busy -= 1;
                    BUSY
                } else {
                    0
                };
                FRKEY | self.fctl3 | busy
            }
        }
    }

    pub fn write_control(&mut self, addr: u16, value: u16) {
        if value & 0xFF00 != FWKEY {
            self.key_violations += 1;
            self.fctl3 |= KEYV;
            self.violations.push(format!(
                "FCTL write {value:#06x} at {addr:#06x} without FWKEY (a PUC)"
            ));
            return;
        }
        let low = value & 0x00FF;
        match addr {
            0x128 => self.fctl1 = low,
            0x12A => self.fctl2 = low,
            _ => self.fctl3 = low & !BUSY,
        }
    }

    fn timing_ok(&mut self) -> bool {
        let clock = match (self.fctl2 >> 6) & 3 {
            0 => self.aclk_hz,
            1 => self.mclk_hz,
            _ => self.mclk_hz,
        };
        let f = clock / (u32::from(self.fctl2 & FN_MASK) + 1);
        if !(257_000..=476_000).contains(&f) {
            self.violations.push(format!(
                "flash timing generator at {f} Hz, outside 257–476 kHz"
            ));
            return false;
        }
        true
    }

    /// A flash operation starts; false if the power is gone.
    fn consume(&mut self) -> bool {
        if !self.powered {
            return false;
        }
        match self.power_budget {
            Some(0) => {
                self.powered = false;
                false
            }
            Some(n) => {
                self.power_budget = Some(n - 1);
                true
            }
            None => true,
        }
    }

    pub fn write8(&mut self, addr: u16, value: u8) {
        if is_flash(addr) {
            self.violations
                .push(format!("byte write {value:#04x} into flash at {addr:#06x}"));
            return;
        }
        self.memory[usize::from(addr)] = value;
    }

    pub fn write16(&mut self, addr: u16, value: u16) {
        if !is_flash(addr) {
            self.set_word(addr, value);
            return;
        }
        if !self.powered {
            return;
        }
        if self.busy > 0 {
            self.violations
                .push(format!("flash written at {addr:#06x} while BUSY"));
            return;
        }
        if self.fctl3 & LOCK != 0 || self.fctl1 & (ERASE | WRT) == 0 || self.refuse_next {
            self.refuse_next = false;
            self.access_violations += 1;
            self.fctl3 |= ACCVIFG;
            return;
        }
        if !self.timing_ok() || !self.consume() {
            return;
        }
        self.busy = self.busy_polls;
        if self.fctl1 & ERASE != 0 {
            let (start, len) = Self::segment_of(addr);
            self.memory[usize::from(start)..usize::from(start) + usize::from(len)].fill(0xFF);
            *self.erases.entry(start).or_insert(0) += 1;
        } else {
            let old = self.word(addr);
            if value & !old != 0 {
                self.violations.push(format!(
                    "word {value:#06x} programmed over {old:#06x} at {addr:#06x} without an erase"
                ));
            }
            self.set_word(addr, old & value);
            self.word_writes += 1;
        }
    }
}
