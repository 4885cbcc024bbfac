//! USCI_A0 in UART mode (SLAU056L, "Universal Serial Communication Interface, UART Mode").
//!
//! - UCSWRST: while set the receive flags and errors are clear and UCA0TXIFG is set; UCA0CTL0,
//!   UCA0BRx and UCA0MCTL may only be written while it is set.
//! - Transmit: a byte written to UCA0TXBUF moves to the shift register at once if it is idle
//!   (UCA0TXIFG stays set), else waits in UCA0TXBUF (UCA0TXIFG clear) until the shift register
//!   has sent its byte (`byte_ticks` ticks; each flag read is a tick). Sent bytes go to
//!   [`UartModel::tx_line`]. A write while UCA0TXIFG is clear is a violation (a byte lost).
//! - Receive: the test delivers bytes from the line ([`UartModel::deliver`]); a byte arriving
//!   while UCA0RXBUF is unread overwrites it and sets UCOE (overrun); a byte with a framing
//!   error sets UCFE; either sets UCRXERR. An erroneous byte sets UCA0RXIFG only with UCRXEIE
//!   (else it is rejected). Reading UCA0RXBUF clears UCA0RXIFG and the error flags.
//! - `tx_stuck`: the shift register never finishes (a transmitter that stopped).

use std::collections::VecDeque;

use acs::hal::msp430::usci_uart::bits::*;

pub struct UartModel {
    pub ctl0: u8,
    pub ctl1: u8,
    pub br0: u8,
    pub br1: u8,
    pub mctl: u8,
    stat: u8,
    rxbuf: u8,
    rxifg: bool,
    txifg: bool,
    txbuf: Option<u8>,
    shifter: Option<(u8, u32)>,
    /// Bytes sent on TXD.
    pub tx_line: Vec<u8>,
    /// Bytes waiting on RXD (`true`: with a framing error).
    pub rx_line: VecDeque<(u8, bool)>,
    pub byte_ticks: u32,
    pub tx_stuck: bool,
    pub violations: Vec<String>,
}

impl Default for UartModel {
    fn default() -> Self {
        Self {
            ctl0: 0,
            ctl1: UCSWRST,
            br0: 0,
            br1: 0,
            mctl: 0,
            stat: 0,
            rxbuf: 0,
            rxifg: false,
            txifg: true,
            txbuf: None,
            shifter: None,
            tx_line: Vec::new(),
            rx_line: VecDeque::new(),
            byte_ticks: 4,
            tx_stuck: false,
            violations: Vec::new(),
        }
    }
}

impl UartModel {
    fn in_reset(&self) -> bool {
        self.ctl1 & UCSWRST != 0
    }

    /// IFG2's USCI_A0 bits.
    pub fn ifg(&self) -> u8 {
        (if self.txifg { UCA0TXIFG } else { 0 }) | (if self.rxifg { UCA0RXIFG } else { 0 })
    }

    /// One unit of line time for the transmitter.
    pub fn tick(&mut self) {
        if self.in_reset() || self.tx_stuck {
            return;
        }
        if let Some((b, ticks)) = self.shifter {
            if ticks > 1 {
                self.shifter = Some((b, ticks - 1));
                return;
            }
            self.tx_line.push(b);
            self.shifter = self.txbuf.take().map(|n| (n, self.byte_ticks));
            self.txifg = true;
        }
    }

    /// Moves the next byte from the line into UCA0RXBUF (false: the line is empty).
    pub fn deliver(&mut self) -> bool {
        let Some((byte, framing)) = self.rx_line.pop_front() else {
            return false;
        };
        if self.in_reset() {
            return true;
        }
        if framing && self.ctl1 & UCRXEIE == 0 {
            // rejected
            return true;
        }
        if self.rxifg {
            self.stat |= UCOE | UCRXERR;
        }
        if framing {
            self.stat |= UCFE | UCRXERR;
        }
        self.rxbuf = byte;
        self.rxifg = true;
        true
    }

    pub fn read8(&mut self, addr: u16) -> u8 {
        match addr {
            0x60 => self.ctl0,
            0x61 => self.ctl1,
            0x62 => self.br0,
            0x63 => self.br1,
            0x64 => self.mctl,
            0x65 => {
                self.tick();
                self.stat | if self.shifter.is_some() { 0x01 } else { 0 }
            }
            0x66 => {
                if !self.rxifg {
                    self.violations.push("UCA0RXBUF read while empty".into());
                }
                self.rxifg = false;
                self.stat &= !(UCFE | UCPE | UCOE | UCBRK | UCRXERR);
                self.rxbuf
            }
            _ => 0,
        }
    }

    pub fn write8(&mut self, addr: u16, value: u8) {
        let config = matches!(addr, 0x60 | 0x62 | 0x63 | 0x64);
        if config && !self.in_reset() {
            self.violations.push(format!(
                "USCI_A0 register {addr:#04x} written outside UCSWRST"
            ));
        }
        match addr {
            0x60 => self.ctl0 = value,
            0x61 => {
                self.ctl1 = value;
                if value & UCSWRST != 0 {
                    self.rxifg = false;
                    self.stat = 0;
                    self.txifg = true;
                    self.txbuf = None;
                    self.shifter = None;
                }
            }
            0x62 => self.br0 = value,
            0x63 => self.br1 = value,
            0x64 => self.mctl = value,
            0x67 => {
                if self.in_reset() {
                    self.violations.push("UCA0TXBUF written in reset".into());
                    return;
                }
                if !self.txifg {
                    self.violations
                        .push("UCA0TXBUF written while full: a byte is lost".into());
                }
                if self.shifter.is_none() {
                    self.shifter = Some((value, self.byte_ticks));
                    self.txifg = true;
                } else {
                    self.txbuf = Some(value);
                    self.txifg = false;
                }
            }
            _ => {}
        }
    }
}
