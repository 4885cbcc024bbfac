//! Digital outputs on the ports P1–P10 (the bridges' direction pins), as
//! `embedded_hal::digital::OutputPin`; and the pin-function selection the other drivers use.
//!
//! SLAU056 "Digital I/O": each port has an input register `PxIN`, an output register `PxOUT`, a
//! direction register `PxDIR` (1: output) and a function-select register `PxSEL` (0: the port
//! function, 1: the peripheral's). The addresses are those of the SLAS508K peripheral file map
//! (ports 7–10 are interleaved byte pairs of the word ports PA and PB).
//!
//! A pin is configured once ([`OutputPin::new`]: `PxSEL` bit cleared, `PxOUT` bit cleared, then
//! `PxDIR` bit set, so the pin never drives high before it is commanded); `set_high`/`set_low`
//! are one read-modify-write of `PxOUT` each.

use core::convert::Infallible;

use super::Registers;

/// The registers of one port.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Port {
    /// `PxIN`.
    pub input: u16,
    /// `PxOUT`.
    pub output: u16,
    /// `PxDIR`.
    pub direction: u16,
    /// `PxSEL`.
    pub select: u16,
}

/// Port P1 (SLAS508K peripheral file map).
pub const P1: Port = port(0x20, 0x21, 0x22, 0x26);
/// Port P2.
pub const P2: Port = port(0x28, 0x29, 0x2A, 0x2E);
/// Port P3 (UCB0SDA P3.1, UCB0SCL P3.2, TB3–TB6 on P3.4–P3.7).
pub const P3: Port = port(0x18, 0x19, 0x1A, 0x1B);
/// Port P4.
pub const P4: Port = port(0x1C, 0x1D, 0x1E, 0x1F);
/// Port P5.
pub const P5: Port = port(0x30, 0x31, 0x32, 0x33);
/// Port P6.
pub const P6: Port = port(0x34, 0x35, 0x36, 0x37);
/// Port P7 (low byte of PA).
pub const P7: Port = port(0x38, 0x3A, 0x3C, 0x3E);
/// Port P8 (high byte of PA).
pub const P8: Port = port(0x39, 0x3B, 0x3D, 0x3F);
/// Port P9 (low byte of PB).
pub const P9: Port = port(0x08, 0x0A, 0x0C, 0x0E);
/// Port P10 (high byte of PB).
pub const P10: Port = port(0x09, 0x0B, 0x0D, 0x0F);

const fn port(input: u16, output: u16, direction: u16, select: u16) -> Port {
    Port {
        input,
        output,
        direction,
        select,
    }
}

/// One pin: a port and a bit number (0–7).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Pin {
    /// The port.
    pub port: Port,
    /// The bit, 0–7 (taken modulo 8).
    pub bit: u8,
}

impl Pin {
    /// Pin `bit` (0–7) of `port`.
    pub const fn new(port: Port, bit: u8) -> Self {
        Self { port, bit }
    }

    /// The pin's bit mask in its port's registers.
    pub const fn mask(&self) -> u8 {
        1 << (self.bit & 7)
    }

    /// Gives the pin to its peripheral function (`PxSEL` bit set), as an output (`PxDIR` set)
    /// or an input.
    pub fn select_peripheral<R: Registers>(&self, regs: &mut R, output: bool) {
        if output {
            regs.set_bits8(self.port.direction, self.mask());
        } else {
            regs.clear_bits8(self.port.direction, self.mask());
        }
        regs.set_bits8(self.port.select, self.mask());
    }
}

/// A port pin driven as a digital output.
pub struct OutputPin<R> {
    regs: R,
    pin: Pin,
}

impl<R: Registers> OutputPin<R> {
    /// Makes `pin` a port output, low.
    pub fn new(mut regs: R, pin: Pin) -> Self {
        let mask = pin.mask();
        regs.clear_bits8(pin.port.select, mask);
        regs.clear_bits8(pin.port.output, mask);
        regs.set_bits8(pin.port.direction, mask);
        Self { regs, pin }
    }

    /// The pin.
    pub fn pin(&self) -> Pin {
        self.pin
    }
}

impl<R: Registers> embedded_hal::digital::ErrorType for OutputPin<R> {
    type Error = Infallible;
}

impl<R: Registers> embedded_hal::digital::OutputPin for OutputPin<R> {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.regs.clear_bits8(self.pin.port.output, self.pin.mask());
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        self.regs.set_bits8(self.pin.port.output, self.pin.mask());
        Ok(())
    }
}
