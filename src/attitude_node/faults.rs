//! What went wrong in a step, as flags and as the one telemetry word the ground sees.

/// What went wrong in a step (several may be set); the step still commands safe actuators.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Faults {
    /// At least one device read failed this step.
    pub device_read: bool,
    /// At least one actuator refused or failed a command.
    pub actuator: bool,
    /// The orbit could not be propagated (decayed, out of range...) or the reference node has
    /// no element set.
    pub orbit: bool,
    /// The Sun or field model failed (date out of range...).
    pub model: bool,
    /// The field could not be determined from the magnetometers, or its magnitude is more than
    /// [`super::FIELD_MAGNITUDE_TOLERANCE`] from the model's (refused).
    pub field: bool,
    /// The rate could not be determined from the gyros.
    pub rate: bool,
    /// No attitude this step (eclipse, no lit tile, degenerate geometry...).
    pub attitude: bool,
    /// A wheel command was limited to its wheel's limit (that wheel alone: the others keep
    /// theirs), or the coils' dipole scaled down to their limits.
    pub saturated: bool,
    /// A control law, the momentum dumping or an allocator refused its input (NaN, infinite
    /// or degenerate): its command is withheld, never replaced by a zero command unreported;
    /// the coils stay off and the wheels hold the momentum in force.
    pub law: bool,
    /// The time since the previous step was not within (0, 2] control periods (a clock
    /// correction, a reset, a missed period): the attitude filter and the B-dot derivative
    /// restarted, and the laws integrated one nominal period.
    pub clock: bool,
    /// The date is past the field model's last epoch: its secular variation extrapolated
    /// ([`crate::env::igrf::Igrf::is_extrapolated`]; the flight tables: 2030.0 to 2035.0).
    pub extrapolated: bool,
    /// No usable REF this step (missing, late, corrupt, made for another step, or without a
    /// valid clock): the step ran without the reference node's models and guidance
    /// ([`crate::link::messages`]).
    pub link: bool,
}

impl Faults {
    /// The flags as a telemetry word: bit 0 `device_read`, 1 `actuator`, 2 `orbit`, 3 `model`,
    /// 4 `field`, 5 `rate`, 6 `attitude`, 7 `saturated`, 8 `law`, 9 `clock`, 10 `extrapolated`,
    /// 11 `link`.
    pub fn bits(&self) -> u16 {
        [
            self.device_read,
            self.actuator,
            self.orbit,
            self.model,
            self.field,
            self.rate,
            self.attitude,
            self.saturated,
            self.law,
            self.clock,
            self.extrapolated,
            self.link,
        ]
        .iter()
        .rev()
        .fold(0u16, |m, f| (m << 1) | u16::from(*f))
    }

    /// The reference node's faults (orbit, model, extrapolated) from a REF's fault word.
    pub(super) fn take_reference(&mut self, bits: u16) {
        self.orbit = bits & 1 << 2 != 0;
        self.model = bits & 1 << 3 != 0;
        self.extrapolated = bits & 1 << 10 != 0;
    }
}
