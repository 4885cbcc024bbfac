//! Timer_A3 (counting) and Timer_B7 (registers and the output waveform they define).
//!
//! Timer_A (SLAU056L "Timer_A"): TACLR clears TAR and the divider and reads back 0; in up mode
//! TAR counts 0 … TACCR0 and restarts at 0; TACCR0 CCIFG is set when TAR counts to TACCR0,
//! TAIFG when it counts from TACCR0 to 0. Time advances by [`TimerAModel::advance`] (ACLK
//! cycles) and by `ticks_per_poll` ACLK cycles at each read of TACCTL0 (a stopped crystal: 0).
//!
//! Timer_B (SLAU056L "Timer_B", "Output Modes"): the registers; [`TimerBModel::duty`] is the
//! output's duty cycle they define in up mode: output mode 0 holds OUT, mode 7 (reset/set) is
//! high for TBCLx of TBCCR0 + 1 counts. Any other mode, or the timer not in up mode from SMCLK,
//! is a violation when asked.

use acs::hal::msp430::pwm::bits as tb;
use acs::hal::msp430::timer_a::bits::*;

#[derive(Default)]
pub struct TimerAModel {
    pub ctl: u16,
    pub cctl0: u16,
    pub ccr0: u16,
    pub tar: u16,
    divider_phase: u32,
    pub ticks_per_poll: u32,
    /// Reads of TACCTL0 so far.
    pub polls: u64,
    pub violations: Vec<String>,
}

impl TimerAModel {
    /// `aclk` ACLK cycles pass.
    pub fn advance(&mut self, aclk: u32) {
        if self.ctl & MC_MASK != MC_UP {
            return;
        }
        let divider = 1u32 << ((self.ctl >> ID_SHIFT) & 3);
        let total = self.divider_phase + aclk;
        let counts = total / divider;
        self.divider_phase = total % divider;
        for _ in 0..counts {
            if self.tar == self.ccr0 {
                self.tar = 0;
                self.ctl |= TAIFG;
            } else {
                self.tar += 1;
                if self.tar == self.ccr0 {
                    self.cctl0 |= CCIFG;
                }
            }
        }
    }

    pub fn read16(&mut self, addr: u16) -> u16 {
        match addr {
            0x160 => self.ctl,
            0x162 => {
                self.polls += 1;
                let t = self.ticks_per_poll;
                self.advance(t);
                self.cctl0
            }
            0x170 => self.tar,
            0x172 => self.ccr0,
            _ => 0,
        }
    }

    pub fn write16(&mut self, addr: u16, value: u16) {
        match addr {
            0x160 => {
                if value & TACLR != 0 {
                    self.tar = 0;
                    self.divider_phase = 0;
                }
                self.ctl = value & !TACLR;
            }
            0x162 => self.cctl0 = value,
            0x170 => self.tar = value,
            0x172 => self.ccr0 = value,
            _ => {}
        }
    }
}

#[derive(Default)]
pub struct TimerBModel {
    /// The words at 0x0180–0x019F.
    pub regs: [u16; 16],
    pub violations: Vec<String>,
}

impl TimerBModel {
    pub fn read16(&mut self, addr: u16) -> u16 {
        self.regs[usize::from((addr - 0x180) / 2)]
    }

    pub fn write16(&mut self, addr: u16, value: u16) {
        let value = if addr == 0x180 {
            value & !tb::TBCLR
        } else {
            value
        };
        self.regs[usize::from((addr - 0x180) / 2)] = value;
    }

    pub fn ctl(&self) -> u16 {
        self.regs[0]
    }

    pub fn cctl(&self, channel: usize) -> u16 {
        self.regs[1 + channel]
    }

    pub fn ccr(&self, channel: usize) -> u16 {
        self.regs[9 + channel]
    }

    /// The duty cycle (0–1) of output `channel`, or `None` (and a violation) if the registers
    /// do not define one.
    pub fn duty(&mut self, channel: usize) -> Option<f64> {
        if self.ctl() & (tb::MC_MASK | 0x0300) != tb::MC_UP | tb::TBSSEL_SMCLK {
            self.violations.push(format!(
                "Timer_B not in up mode from SMCLK: {:#06x}",
                self.ctl()
            ));
            return None;
        }
        let cctl = self.cctl(channel);
        match cctl & tb::OUTMOD_MASK {
            0 => Some(if cctl & tb::OUT != 0 { 1.0 } else { 0.0 }),
            tb::OUTMOD_RESET_SET => {
                let period = f64::from(self.ccr(0)) + 1.0;
                Some(f64::from(self.ccr(channel)).min(period) / period)
            }
            m => {
                self.violations
                    .push(format!("TB{channel} in output mode {}", m >> 5));
                None
            }
        }
    }
}
