//! Timer_B7 as the coils' PWM: up mode from SMCLK, outputs in reset/set mode, one
//! `embedded_hal::pwm::SetDutyCycle` per channel.
//!
//! Source: SLAU056L, "Timer_B": "Timer Mode Control" (up mode: TBR counts 0 … TBCCR0, a period
//! of TBCCR0 + 1 counts), "TBCLx Compare Latch" (CLLDx = 01: the new TBCCRx is loaded into the
//! compare latch when TBR counts to 0, so a duty change takes effect at a period boundary and
//! never cuts a pulse), "Output Modes" and "Output Example—Timer in Up Mode" (mode 7,
//! reset/set: the output is reset when TBR counts to TBCLx and set when it counts to TBCL0, a
//! duty of TBCCRx / (TBCCR0 + 1)), and the table "Timer_B Registers" (TBCTL: TBSSELx = 10
//! SMCLK, CNTLx = 00 16-bit, MCx; TBCCTLx: CLLDx, OUTMODx, OUT). Addresses: SLAS508K
//! peripheral file map. Outputs: SLAS508K "Port P2, P2.0 to P2.3" (TB1 on P2.2) and "Port P3,
//! P3.4 to P3.7" (TB3–TB6 on P3.4–P3.7), PxSEL and PxDIR bits set.
//!
//! # Duty cycle
//! A duty d of [`SetDutyCycle::max_duty_cycle`] = TBCCR0 + 1 counts: d = 0 holds the output
//! low (output mode 0, OUT = 0) and d = TBCCR0 + 1 high (mode 0, OUT = 1), without the one-count
//! spike mode 7 gives at either end; in between, mode 7 with TBCCRx = d: high for d counts of
//! each period. [`PwmConfig::FLIGHT`]: 400 counts of SMCLK = 7 995 392 Hz, 19 988 Hz (above
//! the audio band; the coil's L/R smooths it), a resolution of 1/400 = 0.25 % of full dipole.

use core::convert::Infallible;

use embedded_hal::pwm::{ErrorType, SetDutyCycle};

use super::gpio::{Pin, P2, P3};
use super::Registers;

/// Timer_B control.
pub const TBCTL: u16 = 0x0180;
/// Timer_B capture/compare control 0; channel n at `TBCCTL0 + 2n`.
pub const TBCCTL0: u16 = 0x0182;
/// Timer_B counter.
pub const TBR: u16 = 0x0190;
/// Timer_B capture/compare 0 (the period); channel n at `TBCCR0 + 2n`.
pub const TBCCR0: u16 = 0x0192;

/// Bit names of the Timer_B registers (SLAU056 "Timer_B Registers").
pub mod bits {
    /// TBCTL: TBSSELx = 10, SMCLK.
    pub const TBSSEL_SMCLK: u16 = 0x0200;
    /// TBCTL: MCx = 01, up mode.
    pub const MC_UP: u16 = 0x0010;
    /// TBCTL: MCx mask.
    pub const MC_MASK: u16 = 0x0030;
    /// TBCTL: clears TBR and the divider.
    pub const TBCLR: u16 = 0x0004;
    /// TBCCTLx: CLLDx = 01, TBCLx loaded when TBR counts to 0.
    pub const CLLD_AT_ZERO: u16 = 0x0200;
    /// TBCCTLx: OUTMODx mask (bits 7–5).
    pub const OUTMOD_MASK: u16 = 0x00E0;
    /// TBCCTLx: OUTMODx = 111, reset/set.
    pub const OUTMOD_RESET_SET: u16 = 0x00E0;
    /// TBCCTLx: the output's level in output mode 0.
    pub const OUT: u16 = 0x0004;
}

use bits::*;

/// The PWM period.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PwmConfig {
    period_counts: u16,
}

impl PwmConfig {
    /// 400 counts of [`super::SMCLK_HZ`]: 19 988 Hz.
    pub const FLIGHT: Self = Self { period_counts: 400 };

    /// A period of `period_counts` timer counts (2 … 65 535).
    pub const fn new(period_counts: u16) -> Option<Self> {
        if 2 > period_counts {
            None
        } else {
            Some(Self { period_counts })
        }
    }

    /// The period in timer counts (TBCCR0 + 1).
    pub const fn period_counts(&self) -> u16 {
        self.period_counts
    }
}

/// A Timer_B output: its channel (1–6) and its pin.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct TbOutput {
    channel: u8,
    pin: Pin,
}

impl TbOutput {
    /// TB1 on P2.2.
    pub const TB1: Self = Self {
        channel: 1,
        pin: Pin::new(P2, 2),
    };
    /// TB3 on P3.4.
    pub const TB3: Self = Self {
        channel: 3,
        pin: Pin::new(P3, 4),
    };
    /// TB4 on P3.5.
    pub const TB4: Self = Self {
        channel: 4,
        pin: Pin::new(P3, 5),
    };
    /// TB5 on P3.6.
    pub const TB5: Self = Self {
        channel: 5,
        pin: Pin::new(P3, 6),
    };
    /// TB6 on P3.7.
    pub const TB6: Self = Self {
        channel: 6,
        pin: Pin::new(P3, 7),
    };

    /// The channel number.
    pub const fn channel(&self) -> u8 {
        self.channel
    }

    /// TBCCTLx.
    pub const fn control_register(&self) -> u16 {
        TBCCTL0 + 2 * self.channel as u16
    }

    /// TBCCRx.
    pub const fn compare_register(&self) -> u16 {
        TBCCR0 + 2 * self.channel as u16
    }
}

/// Timer_B running the PWM period.
pub struct TimerBPwm<R> {
    regs: R,
    config: PwmConfig,
}

impl<R: Registers> TimerBPwm<R> {
    /// Starts Timer_B in up mode from SMCLK with the period of `config` (TBR cleared).
    pub fn start(mut regs: R, config: PwmConfig) -> Self {
        regs.write16(TBCTL, TBCLR);
        regs.write16(TBCCR0, config.period_counts.saturating_sub(1));
        regs.write16(TBCTL, TBSSEL_SMCLK | MC_UP | TBCLR);
        Self { regs, config }
    }

    /// The PWM channel on `output`, off (a copy of the register access: the firmware's is a
    /// zero-sized type).
    pub fn channel(&self, output: TbOutput) -> PwmChannel<R>
    where
        R: Clone,
    {
        PwmChannel::new(self.regs.clone(), output, self.config)
    }

    /// Stops the timer (MCx = 00; the outputs keep their level) and gives the register access
    /// back.
    pub fn stop(mut self) -> R {
        let ctl = self.regs.read16(TBCTL);
        self.regs.write16(TBCTL, ctl & !MC_MASK);
        self.regs
    }
}

/// One PWM output of Timer_B.
pub struct PwmChannel<R> {
    regs: R,
    output: TbOutput,
    period_counts: u16,
}

impl<R: Registers> PwmChannel<R> {
    /// The channel on `output` of a Timer_B running `config`'s period, off (low), its pin given
    /// to the timer.
    pub fn new(mut regs: R, output: TbOutput, config: PwmConfig) -> Self {
        regs.write16(output.control_register(), 0);
        regs.write16(output.compare_register(), 0);
        output.pin.select_peripheral(&mut regs, true);
        Self {
            regs,
            output,
            period_counts: config.period_counts,
        }
    }

    /// The output.
    pub fn output(&self) -> TbOutput {
        self.output
    }
}

impl<R: Registers> ErrorType for PwmChannel<R> {
    type Error = Infallible;
}

impl<R: Registers> SetDutyCycle for PwmChannel<R> {
    fn max_duty_cycle(&self) -> u16 {
        self.period_counts
    }

    /// `duty` counts high per period; beyond the period, full on.
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Infallible> {
        let control = if duty == 0 {
            0
        } else if duty >= self.period_counts {
            OUT
        } else {
            self.regs.write16(self.output.compare_register(), duty);
            CLLD_AT_ZERO | OUTMOD_RESET_SET
        };
        self.regs.write16(self.output.control_register(), control);
        Ok(())
    }
}
