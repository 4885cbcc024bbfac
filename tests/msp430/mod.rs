//! Register models of the MSP430FG4619's peripherals, for the drivers of `acs::hal::msp430`.
//!
//! Each model implements what the user's guide (SLAU056L) says the registers do, as far as a
//! driver can observe it, and records what the driver did (bus events, flash operations) and any
//! use the guide forbids (a violation: configuration outside UCSWRST, a write to a full buffer,
//! a flash write without the password, a 0 programmed to 1 without an erase, ...). Time passes
//! as the driver polls: each read of a status or flag register is one tick.
//!
//! [`Mcu`] routes the addresses of the SLAS508K peripheral file map to the models; [`Handle`]
//! (a shared reference to it) is the drivers' [`Registers`].

#![allow(dead_code)]

pub mod flash_model;
pub mod i2c_model;
pub mod timer_model;
pub mod uart_model;

use std::cell::RefCell;
use std::rc::Rc;

use acs::hal::msp430::Registers;

pub use flash_model::FlashModel;
pub use i2c_model::{Event, I2cModel, Slave};
pub use timer_model::{TimerAModel, TimerBModel};
pub use uart_model::UartModel;

/// The part: its peripherals' models and the ports.
pub struct Mcu {
    pub i2c: I2cModel,
    pub uart: UartModel,
    pub timer_a: TimerAModel,
    pub timer_b: TimerBModel,
    pub flash: FlashModel,
    /// P1–P10's registers (addresses 0x08–0x3F), plain bytes.
    pub ports: [u8; 0x40],
    /// Register and memory accesses so far.
    pub accesses: u64,
    /// Accesses to addresses no model owns.
    pub unmapped: Vec<String>,
}

impl Default for Mcu {
    fn default() -> Self {
        Self {
            i2c: I2cModel::default(),
            uart: UartModel::default(),
            timer_a: TimerAModel::default(),
            timer_b: TimerBModel::default(),
            flash: FlashModel::default(),
            ports: [0; 0x40],
            accesses: 0,
            unmapped: Vec::new(),
        }
    }
}

impl Mcu {
    /// Every violation any model recorded.
    pub fn violations(&self) -> Vec<String> {
        let mut v = self.unmapped.clone();
        v.extend(self.i2c.violations.iter().cloned());
        v.extend(self.uart.violations.iter().cloned());
        v.extend(self.timer_a.violations.iter().cloned());
        v.extend(self.timer_b.violations.iter().cloned());
        v.extend(self.flash.violations.iter().cloned());
        v
    }

    /// A port register's value (no access counted).
    pub fn read_port(&self, addr: u16) -> u8 {
        self.ports[usize::from(addr)]
    }

    fn read8(&mut self, addr: u16) -> u8 {
        self.accesses += 1;
        match addr {
            0x0003 => {
                // IFG2: USCI_A0's bits 0–1, USCI_B0's bits 2–3; a flag read is a tick of both
                self.uart.tick();
                self.i2c.tick();
                self.uart.ifg() | self.i2c.ifg()
            }
            0x0008..=0x003F => self.ports[usize::from(addr)],
            0x0060..=0x0067 => self.uart.read8(addr),
            0x0068..=0x006F => self.i2c.read8(addr),
            a if a >= 0x1000 => self.flash.read8(a),
            _ => {
                self.unmapped.push(format!("read8 of {addr:#06x}"));
                0
            }
        }
    }

    fn write8(&mut self, addr: u16, value: u8) {
        self.accesses += 1;
        match addr {
            0x0008..=0x003F => self.ports[usize::from(addr)] = value,
            0x0060..=0x0067 => self.uart.write8(addr, value),
            0x0068..=0x006F => self.i2c.write8(addr, value),
            a if a >= 0x1000 => self.flash.write8(a, value),
            _ => self.unmapped.push(format!("write8 of {addr:#06x}")),
        }
    }

    fn read16(&mut self, addr: u16) -> u16 {
        self.accesses += 1;
        if !addr.is_multiple_of(2) {
            self.unmapped.push(format!("odd word read at {addr:#06x}"));
        }
        match addr {
            0x0118 | 0x011A => self.i2c.read16(addr),
            0x0128..=0x012D => self.flash.read_control(addr),
            0x0160..=0x0177 => self.timer_a.read16(addr),
            0x0180..=0x019F => self.timer_b.read16(addr),
            a if a >= 0x1000 => self.flash.read16(a),
            _ => {
                self.unmapped.push(format!("read16 of {addr:#06x}"));
                0
            }
        }
    }

    fn write16(&mut self, addr: u16, value: u16) {
        self.accesses += 1;
        if !addr.is_multiple_of(2) {
            self.unmapped.push(format!("odd word write at {addr:#06x}"));
        }
        match addr {
            0x0118 | 0x011A => self.i2c.write16(addr, value),
            0x0128..=0x012D => self.flash.write_control(addr, value),
            0x0160..=0x0177 => self.timer_a.write16(addr, value),
            0x0180..=0x019F => self.timer_b.write16(addr, value),
            a if a >= 0x1000 => self.flash.write16(a, value),
            _ => self.unmapped.push(format!("write16 of {addr:#06x}")),
        }
    }
}

/// A handle on a shared [`Mcu`]: the register access of every driver under test. Clones are
/// handles on the same part (the firmware's register access is a zero-sized `Copy` type).
#[derive(Clone, Default)]
pub struct Handle(pub Rc<RefCell<Mcu>>);

impl Handle {
    /// A new part, every model in its reset state.
    pub fn new() -> Self {
        Self::default()
    }

    /// The part, to inspect or change a model.
    pub fn mcu(&self) -> std::cell::RefMut<'_, Mcu> {
        self.0.borrow_mut()
    }
}

impl Registers for Handle {
    fn read8(&mut self, addr: u16) -> u8 {
        self.0.borrow_mut().read8(addr)
    }
    fn write8(&mut self, addr: u16, value: u8) {
        self.0.borrow_mut().write8(addr, value)
    }
    fn read16(&mut self, addr: u16) -> u16 {
        self.0.borrow_mut().read16(addr)
    }
    fn write16(&mut self, addr: u16, value: u16) {
        self.0.borrow_mut().write16(addr, value)
    }
}
