//! Timer_A3 as the control-period timer: up mode from ACLK, one period per TACCR0 match.
//!
//! Source: SLAU056L, "Timer_A": "Timer Mode Control" (up mode, MCx = 01: TAR counts from 0 to
//! TACCR0 and restarts at 0, a period of TACCR0 + 1 counts), "Timer_A Interrupts" ("TACCR0
//! Interrupt": TACCR0 CCIFG is set when TAR counts to TACCR0; it is cleared by software, or
//! automatically when the TACCR0 interrupt is serviced) and the table "Timer_A Registers"
//! (TACTL: TASSELx = 01 ACLK, IDx the input divider, MCx, TACLR; TACCTL0: CCIE, CCIFG).
//! Addresses: SLAS508K peripheral file map.
//!
//! # The flight period
//! ACLK = 32 768 Hz (watch crystal), divider 1, TACCR0 = 32 767: one TACCR0 match each
//! 32 768 / 32 768 Hz = 1 s ([`Period::ONE_SECOND`]); the crystal's tolerance is the period's.
//!
//! # Sleeping between periods (LPM3)
//! On the part the loop does: step; [`PeriodTimer::enable_wakeup`] (CCIE); enter LPM3 with
//! interrupts enabled (`bis #0x00D8, SR`: SCG1 | SCG0 | CPUOFF | GIE, SLAU056 "Operating
//! Modes"). In LPM3 MCLK, SMCLK and the DCO stop; ACLK, hence Timer_A, runs. At the match the
//! TACCR0 interrupt (vector 0xFFEC, SLAS508K interrupt vector table) is accepted, which clears
//! CCIFG; its handler clears the low-power bits of the status register saved on the stack
//! (`bic #0x00F0, 0(SP)`; `reti`), so the CPU returns to the loop awake and runs the next step.
//! The flight node images do this (`firmware/src/periph.rs`: the handler as `TIMERA0_VECTOR` in
//! their vector table; their processor-in-the-loop build paces itself on the PIL host). Without
//! interrupts the loop calls [`PeriodTimer::wait_period`] instead, polling CCIFG (the CPU stays
//! in active mode).
//!
//! If a step overruns its period, CCIFG is already set when the loop waits: the next step starts
//! at once, and periods that passed whole are not counted (TAR, restarted at each match, does
//! not tell how many).
//!
//! # Duty cycle
//! With the step taking N_step MCLK cycles and the sensors' bus t_bus each period T, the CPU is
//! active for the fraction d = (N_step / f_MCLK + t_bus) / T of the time and in LPM3 for the
//! rest; the mean supply current is Ī = d · I_AM + (1 − d) · I_LPM3 (I_AM at f_MCLK and I_LPM3 in
//! SLAS508K §5.4, "Supply Current Into AVCC + DVCC"). For the attitude node's step (342 800
//! cycles at most with the multiplier, 42.9 ms at 7 995 392 Hz, `firmware/pil`), 18 sensor reads
//! of about 0.7 ms and T = 1 s: d ≈ 5.5 %.

use core::fmt;

use super::Registers;

/// Timer_A control.
pub const TACTL: u16 = 0x0160;
/// Timer_A capture/compare control 0.
pub const TACCTL0: u16 = 0x0162;
/// Timer_A counter.
pub const TAR: u16 = 0x0170;
/// Timer_A capture/compare 0.
pub const TACCR0: u16 = 0x0172;

/// Bit names of the Timer_A registers (SLAU056 "Timer_A Registers").
pub mod bits {
    /// TACTL: TASSELx = 01, ACLK.
    pub const TASSEL_ACLK: u16 = 0x0100;
    /// TACTL: IDx, the input divider (÷1, ÷2, ÷4, ÷8 for 0–3), bits 7–6.
    pub const ID_SHIFT: u16 = 6;
    /// TACTL: MCx = 01, up mode.
    pub const MC_UP: u16 = 0x0010;
    /// TACTL: MCx mask.
    pub const MC_MASK: u16 = 0x0030;
    /// TACTL: clears TAR and the divider.
    pub const TACLR: u16 = 0x0004;
    /// TACTL: TAR overflow flag.
    pub const TAIFG: u16 = 0x0001;
    /// TACCTL0: interrupt enable.
    pub const CCIE: u16 = 0x0010;
    /// TACCTL0: interrupt flag.
    pub const CCIFG: u16 = 0x0001;
}

use bits::*;

/// The poll limit of [`PeriodTimer::wait_period`] for the flight period: about 2 s of polling
/// (44 MCLK cycles a poll at 7 995 392 Hz, measured in the simulator), twice the period, so a
/// stopped crystal is reported within two periods.
pub const FLIGHT_POLL_LIMIT: u32 = 363_000;

/// A control period: TACCR0 and the input divider.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Period {
    ccr0: u16,
    divider_log2: u8,
}

impl Period {
    /// 1 s at ACLK = 32 768 Hz: TACCR0 = 32 767, divider 1.
    pub const ONE_SECOND: Self = Self {
        ccr0: 32_767,
        divider_log2: 0,
    };

    /// A period of `ticks` ACLK cycles, with the smallest input divider (1, 2, 4, 8) that
    /// divides it and brings it to at most 65 536 counts; `None` if none does or `ticks` is 0.
    pub const fn from_aclk_ticks(ticks: u32) -> Option<Self> {
        let mut log2 = 0;
        while 4 > log2 {
            let counts = ticks >> log2;
            if counts > 0 && 0x1_0000 >= counts && counts << log2 == ticks {
                return Some(Self {
                    ccr0: (counts - 1) as u16,
                    divider_log2: log2 as u8,
                });
            }
            log2 += 1;
        }
        None
    }

    /// The period in ACLK cycles.
    pub const fn aclk_ticks(&self) -> u32 {
        (self.ccr0 as u32 + 1) << self.divider_log2
    }

    /// TACCR0.
    pub const fn ccr0(&self) -> u16 {
        self.ccr0
    }
}

/// The period timer did not run.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TimerError {
    /// No period ended within the poll limit (ACLK stopped: the crystal failed).
    Timeout,
}

impl fmt::Display for TimerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("period timer timeout: ACLK stopped")
    }
}

/// Timer_A counting control periods.
pub struct PeriodTimer<R> {
    regs: R,
    poll_limit: u32,
}

impl<R: Registers> PeriodTimer<R> {
    /// Starts Timer_A in up mode from ACLK with `period` (TAR cleared, CCIFG cleared, no
    /// interrupt); [`PeriodTimer::wait_period`] polls at most `poll_limit` times (a poll is 44
    /// MCLK cycles at 7 995 392 Hz: a 1 s period is about 182 000 polls; [`FLIGHT_POLL_LIMIT`]
    /// allows two).
    pub fn start(mut regs: R, period: Period, poll_limit: u32) -> Self {
        // stopped and cleared while TACCR0 is written
        regs.write16(TACTL, TACLR);
        regs.write16(TACCR0, period.ccr0);
        regs.write16(TACCTL0, 0);
        let id = u16::from(period.divider_log2 & 3) << ID_SHIFT;
        regs.write16(TACTL, TASSEL_ACLK | id | MC_UP | TACLR);
        Self { regs, poll_limit }
    }

    /// True (once) if a period ended since the last call: CCIFG was set, and is cleared.
    pub fn period_elapsed(&mut self) -> bool {
        let cctl = self.regs.read16(TACCTL0);
        if cctl & CCIFG == 0 {
            return false;
        }
        self.regs.write16(TACCTL0, cctl & !CCIFG);
        true
    }

    /// Waits for the end of the current period (polling CCIFG, then clearing it);
    /// [`TimerError::Timeout`] after the poll limit.
    pub fn wait_period(&mut self) -> Result<(), TimerError> {
        for _ in 0..self.poll_limit {
            if self.period_elapsed() {
                return Ok(());
            }
        }
        Err(TimerError::Timeout)
    }

    /// Enables the TACCR0 interrupt (CCIE), the wake-up from LPM3.
    pub fn enable_wakeup(&mut self) {
        let cctl = self.regs.read16(TACCTL0);
        self.regs.write16(TACCTL0, cctl | CCIE);
    }

    /// Disables the TACCR0 interrupt.
    pub fn disable_wakeup(&mut self) {
        let cctl = self.regs.read16(TACCTL0);
        self.regs.write16(TACCTL0, cctl & !CCIE);
    }

    /// Stops the timer (MCx = 00) and gives the register access back.
    pub fn stop(mut self) -> R {
        let ctl = self.regs.read16(TACTL);
        self.regs.write16(TACTL, ctl & !MC_MASK);
        self.regs
    }
}
