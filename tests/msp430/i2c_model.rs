//! USCI_B0 in I²C master mode with slave devices on its bus (SLAU056L, "Universal Serial
//! Communication Interface, I2C Mode").
//!
//! What is modelled, as the user's guide states it:
//! - UCSWRST: while set, UCB0TXIFG, UCB0RXIFG, the UCB0STAT flags, UCTXSTT and UCTXSTP are
//!   clear; UCB0CTL0 and UCB0BR0/1 may only be written while it is set (a violation otherwise).
//! - UCTXSTT with UCTR: a START, UCB0TXIFG set at once (before the address); the address phase
//!   lasts `address_ticks`; on the acknowledge UCTXSTT clears and a byte waiting in UCB0TXBUF
//!   moves to the shift register (UCB0TXIFG set again); without one the master holds SCL.
//!   Without UCTR: on the acknowledge UCTXSTT clears and the first byte's reception begins.
//! - A byte takes `byte_ticks`. In transmit, when it ends the slave acknowledges or not
//!   (UCNACKIFG, the master holds the bus); then UCTXSTP pending → STOP, UCTXSTT pending →
//!   repeated START, a byte in UCB0TXBUF → shifted next, else SCL held. In receive, a finished
//!   byte moves to UCB0RXBUF (UCB0RXIFG) if it is empty, else the bus stalls until it is read
//!   (then the last bit and the acknowledge take 2 ticks); whether it was the last byte (NACK +
//!   STOP, or a repeated START) is decided when it moves, by UCTXSTP/UCTXSTT set by then.
//! - A STOP takes 2 ticks, then UCTXSTP clears and the bus is free (UCBBUSY clear).
//! - A data byte not acknowledged while a repeated START is already requested: UCNACKIFG set and
//!   the repeated START made (the case of erratum USCI25).
//! - Injected faults: a slave that NACKs its address or a given data byte, arbitration lost at
//!   the next address phase (UCALIFG, UCMST cleared: the module is a slave until reconfigured),
//!   a stuck bus (nothing progresses, UCSCLLOW), a bus busy with another master (UCBBUSY).
//! - Violations: UCB0TXBUF written while full, UCB0RXBUF read while empty, a STOP requested with
//!   a byte still in UCB0TXBUF (lost), a START while not master, configuration outside reset.

use acs::hal::msp430::usci_i2c::bits::*;

/// What happened on the bus, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Event {
    Start {
        address: u8,
        read: bool,
    },
    Restart {
        address: u8,
        read: bool,
    },
    /// A byte the master wrote (and the slave acknowledged).
    Write(u8),
    /// A byte the master received.
    Read(u8),
    /// The slave did not acknowledge (address or data).
    Nack,
    Stop,
    ArbitrationLost,
    /// UCSWRST set during a transfer: the lines released without a STOP.
    Reset,
}

/// A slave: a register file with an auto-incrementing pointer set by the first written byte.
#[derive(Clone, Debug)]
pub struct Slave {
    pub address: u8,
    pub registers: [u8; 256],
    pub pointer: u8,
    /// Does not acknowledge its address.
    pub nack_address: bool,
    /// Does not acknowledge the `k`-th byte written in a transaction (0: the register byte).
    pub nack_write_byte: Option<usize>,
    written: usize,
}

impl Slave {
    pub fn new(address: u8) -> Self {
        Self {
            address,
            registers: [0; 256],
            pointer: 0,
            nack_address: false,
            nack_write_byte: None,
            written: 0,
        }
    }

    /// Big-endian `i16` words from `register` on.
    pub fn with_words(mut self, register: u8, words: &[i16]) -> Self {
        for (k, w) in words.iter().enumerate() {
            let [hi, lo] = w.to_be_bytes();
            self.registers[usize::from(register) + 2 * k] = hi;
            self.registers[usize::from(register) + 2 * k + 1] = lo;
        }
        self
    }

    /// Receives a written byte; false: not acknowledged.
    fn write(&mut self, byte: u8) -> bool {
        let k = self.written;
        self.written += 1;
        if self.nack_write_byte == Some(k) {
            return false;
        }
        if k == 0 {
            self.pointer = byte;
        } else {
            self.registers[usize::from(self.pointer)] = byte;
            self.pointer = self.pointer.wrapping_add(1);
        }
        true
    }

    fn read(&mut self) -> u8 {
        let b = self.registers[usize::from(self.pointer)];
        self.pointer = self.pointer.wrapping_add(1);
        b
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Idle,
    Address {
        ticks: u32,
    },
    /// Shifting a byte out (`Some`), or holding SCL low for one (`None`).
    Transmit {
        byte: Option<u8>,
        ticks: u32,
    },
    /// Receiving a byte; at 0 ticks it is complete (stalled while UCB0RXBUF is full).
    Receive {
        byte: u8,
        ticks: u32,
    },
    /// After a NACK: the bus held until STOP or repeated START.
    NackHold,
    Stopping {
        ticks: u32,
    },
}

pub struct I2cModel {
    pub ctl0: u8,
    pub ctl1: u8,
    pub br0: u8,
    pub br1: u8,
    pub ie: u8,
    stat: u8,
    pub sa: u16,
    pub oa: u16,
    txifg: bool,
    rxifg: bool,
    txbuf: Option<u8>,
    rxbuf: u8,
    phase: Phase,
    read: bool,
    active: Option<usize>,
    pub slaves: Vec<Slave>,
    pub events: Vec<Event>,
    pub violations: Vec<String>,
    pub address_ticks: u32,
    pub byte_ticks: u32,
    /// Nothing progresses (SCL held low by a slave).
    pub stuck: bool,
    /// Another master holds the bus (UCBBUSY set).
    pub external_busy: bool,
    /// Arbitration is lost at the next address phase.
    pub lose_arbitration: bool,
}

impl Default for I2cModel {
    fn default() -> Self {
        Self {
            ctl0: 0x01,
            // reset state: UCSWRST set
            ctl1: UCSWRST,
            br0: 0,
            br1: 0,
            ie: 0,
            stat: 0,
            sa: 0,
            oa: 0,
            txifg: false,
            rxifg: false,
            txbuf: None,
            rxbuf: 0,
            phase: Phase::Idle,
            read: false,
            active: None,
            slaves: Vec::new(),
            events: Vec::new(),
            violations: Vec::new(),
            address_ticks: 3,
            byte_ticks: 3,
            stuck: false,
            external_busy: false,
            lose_arbitration: false,
        }
    }
}

impl I2cModel {
    fn in_reset(&self) -> bool {
        self.ctl1 & UCSWRST != 0
    }

    /// IFG2's USCI_B0 bits.
    pub fn ifg(&self) -> u8 {
        (if self.txifg { UCB0TXIFG } else { 0 }) | (if self.rxifg { UCB0RXIFG } else { 0 })
    }

    pub fn is_master(&self) -> bool {
        self.ctl0 & UCMST != 0
    }

    fn address(&self) -> u8 {
        (self.sa & 0x7F) as u8
    }

    fn reset_state(&mut self) {
        if !matches!(self.phase, Phase::Idle) {
            self.events.push(Event::Reset);
        }
        self.txifg = false;
        self.rxifg = false;
        self.txbuf = None;
        self.stat = 0;
        self.ctl1 &= !(UCTXSTT | UCTXSTP);
        self.phase = Phase::Idle;
        self.active = None;
    }

    pub fn read8(&mut self, addr: u16) -> u8 {
        match addr {
            0x68 => self.ctl0,
            0x69 => {
                self.tick();
                self.ctl1
            }
            0x6A => self.br0,
            0x6B => self.br1,
            0x6C => self.ie,
            0x6D => {
                self.tick();
                let busy = self.external_busy || !matches!(self.phase, Phase::Idle);
                self.stat | if busy { UCBBUSY } else { 0 } | if self.stuck { UCSCLLOW } else { 0 }
            }
            0x6E => {
                if !self.rxifg {
                    self.violations.push("UCB0RXBUF read while empty".into());
                }
                self.rxifg = false;
                if let Phase::Receive { byte, ticks: 0 } = self.phase {
                    // the stalled byte's last bit and acknowledge
                    self.phase = Phase::Receive { byte, ticks: 2 };
                }
                self.rxbuf
            }
            _ => 0, // UCB0TXBUF reads back nothing useful
        }
    }

    pub fn write8(&mut self, addr: u16, value: u8) {
        match addr {
            0x68 => {
                if !self.in_reset() {
                    self.violations
                        .push("UCB0CTL0 written outside UCSWRST".into());
                }
                self.ctl0 = value;
            }
            0x69 => self.write_ctl1(value),
            0x6A | 0x6B => {
                if !self.in_reset() {
                    self.violations
                        .push("UCB0BRx written outside UCSWRST".into());
                }
                if addr == 0x6A {
                    self.br0 = value;
                } else {
                    self.br1 = value;
                }
            }
            0x6C => self.ie = value,
            // software clears the flags; UCBBUSY and UCSCLLOW are read-only
            0x6D => self.stat = value & !(UCBBUSY | UCSCLLOW),
            0x6F => {
                if self.in_reset() {
                    self.violations.push("UCB0TXBUF written in reset".into());
                    return;
                }
                if !self.txifg {
                    self.violations
                        .push("UCB0TXBUF written while full: a byte is lost".into());
                }
                self.txifg = false;
                self.txbuf = Some(value);
            }
            _ => {}
        }
    }

    pub fn read16(&mut self, addr: u16) -> u16 {
        if addr == 0x11A {
            self.sa
        } else {
            self.oa
        }
    }

    pub fn write16(&mut self, addr: u16, value: u16) {
        if addr == 0x11A {
            self.sa = value;
        } else {
            self.oa = value;
        }
    }

    fn write_ctl1(&mut self, value: u8) {
        let was_reset = self.in_reset();
        self.ctl1 = value;
        if value & UCSWRST != 0 {
            self.reset_state();
            return;
        }
        if was_reset {
            // leaving reset: the transmitter's buffer is free only once a START is made
            return;
        }
        if value & UCTXSTT != 0 && matches!(self.phase, Phase::Idle) {
            if !self.is_master() || self.ctl0 & UCMODE_I2C != UCMODE_I2C {
                self.violations
                    .push("START requested while not an I2C master".into());
                self.ctl1 &= !UCTXSTT;
                return;
            }
            self.start(false);
        }
    }

    /// A START (or a repeated START) with the address in UCB0I2CSA and the direction of UCTR.
    fn start(&mut self, repeated: bool) {
        if repeated && self.txbuf.take().is_some() && self.phase != Phase::NackHold {
            self.violations
                .push("repeated START with a byte still in UCB0TXBUF: it is never sent".into());
        }
        self.read = self.ctl1 & UCTR == 0;
        let event = if repeated {
            Event::Restart {
                address: self.address(),
                read: self.read,
            }
        } else {
            Event::Start {
                address: self.address(),
                read: self.read,
            }
        };
        self.events.push(event);
        self.txifg = !self.read;
        self.phase = Phase::Address {
            ticks: self.address_ticks,
        };
    }

    fn stop(&mut self) {
        if self.txbuf.take().is_some() && self.phase != Phase::NackHold {
            self.violations
                .push("STOP with a byte still in UCB0TXBUF: it is never sent".into());
        }
        self.phase = Phase::Stopping { ticks: 2 };
    }

    fn nack(&mut self) {
        self.events.push(Event::Nack);
        self.stat |= UCNACKIFG;
        self.txifg = false;
        self.phase = Phase::NackHold;
    }

    /// After a byte (or the address, or a NACK): a pending STOP or repeated START, if any.
    fn pending_end(&mut self) -> bool {
        if self.ctl1 & UCTXSTP != 0 {
            self.stop();
            true
        } else if self.ctl1 & UCTXSTT != 0 {
            self.start(true);
            true
        } else {
            false
        }
    }

    /// One unit of bus time.
    pub fn tick(&mut self) {
        if self.stuck || self.in_reset() {
            return;
        }
        match self.phase {
            Phase::Idle => {}
            Phase::Address { ticks } if ticks > 1 => {
                self.phase = Phase::Address { ticks: ticks - 1 };
            }
            Phase::Address { .. } => self.address_done(),
            Phase::Transmit {
                byte: Some(b),
                ticks,
            } => {
                if ticks > 1 {
                    self.phase = Phase::Transmit {
                        byte: Some(b),
                        ticks: ticks - 1,
                    };
                    return;
                }
                let acked = match self.active.and_then(|i| self.slaves.get_mut(i)) {
                    Some(s) => s.write(b),
                    None => false,
                };
                if !acked {
                    if self.ctl1 & (UCTXSTT | UCTXSTP) == UCTXSTT {
                        // a repeated START already requested goes out after the NACK (erratum
                        // USCI25 describes this case: UCB0TXIFG is not reset)
                        self.events.push(Event::Nack);
                        self.stat |= UCNACKIFG;
                        self.start(true);
                    } else {
                        self.nack();
                    }
                    return;
                }
                self.events.push(Event::Write(b));
                self.next_transmit();
            }
            Phase::Transmit { byte: None, .. } => self.next_transmit(),
            Phase::Receive { byte, ticks } => {
                if ticks > 1 {
                    self.phase = Phase::Receive {
                        byte,
                        ticks: ticks - 1,
                    };
                    return;
                }
                if self.rxifg {
                    // stalled until UCB0RXBUF is read
                    self.phase = Phase::Receive { byte, ticks: 0 };
                    return;
                }
                self.rxbuf = byte;
                self.rxifg = true;
                self.events.push(Event::Read(byte));
                if !self.pending_end() {
                    let next = match self.active.and_then(|i| self.slaves.get_mut(i)) {
                        Some(s) => s.read(),
                        None => 0xFF,
                    };
                    self.phase = Phase::Receive {
                        byte: next,
                        ticks: self.byte_ticks,
                    };
                }
            }
            Phase::NackHold => {
                self.pending_end();
            }
            Phase::Stopping { ticks } if ticks > 1 => {
                self.phase = Phase::Stopping { ticks: ticks - 1 };
            }
            Phase::Stopping { .. } => {
                self.events.push(Event::Stop);
                self.ctl1 &= !(UCTXSTP | UCTXSTT);
                self.txifg = false;
                self.phase = Phase::Idle;
                self.active = None;
            }
        }
    }

    fn address_done(&mut self) {
        if self.lose_arbitration {
            self.lose_arbitration = false;
            self.events.push(Event::ArbitrationLost);
            self.stat |= UCALIFG;
            self.ctl0 &= !UCMST;
            self.ctl1 &= !UCTXSTT;
            self.txifg = false;
            self.phase = Phase::Idle;
            self.active = None;
            return;
        }
        let address = self.address();
        self.active = self
            .slaves
            .iter()
            .position(|s| s.address == address && !s.nack_address);
        // a repeated START's UCTXSTT is the one that just completed
        self.ctl1 &= !UCTXSTT;
        let Some(i) = self.active else {
            self.nack();
            return;
        };
        if self.read {
            let byte = self.slaves[i].read();
            self.phase = Phase::Receive {
                byte,
                ticks: self.byte_ticks,
            };
        } else {
            self.slaves[i].written = 0;
            self.phase = Phase::Transmit {
                byte: None,
                ticks: 0,
            };
            self.next_transmit();
        }
    }

    /// The transmitter between bytes: a pending end, the next byte, or SCL held.
    fn next_transmit(&mut self) {
        if self.pending_end() {
            return;
        }
        match self.txbuf.take() {
            Some(b) => {
                self.txifg = true;
                self.phase = Phase::Transmit {
                    byte: Some(b),
                    ticks: self.byte_ticks,
                };
            }
            None => {
                self.phase = Phase::Transmit {
                    byte: None,
                    ticks: 0,
                };
            }
        }
    }
}
