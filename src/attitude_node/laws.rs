//! Step phase 5: the mode's events and the mode's law (B-dot, sun-safe, the slew's reference
//! from the reference node tracked in closed loop, quaternion tracking), as a coil dipole and a
//! wheel momentum.
//!
//! Attitudes are `v_body = A(q) · v_ref`, reference TEME of date ([`crate::attitude`]).

use super::modes::{Event, ModeState, INVALID_STEPS_TO_SAFE};
use super::{AttitudeNode, Faults, Mode};
use crate::acs_loop::StepReport;
use crate::control::bdot::bdot_from_rates;
use crate::control::magnetorquer::dipole_for_torque;
use crate::control::slew_trajectory::SlewReference;
use crate::control::sun_safe::sun_safe_torque;
use crate::control::tracking::tracking_torque;
use crate::linalg::Vec3;
use crate::link::messages::{Guidance, GuidanceKind};

/// The step's models put the satellite in the umbra (the Sun's visible fraction 0): without an
/// attitude, `Tracking` and `Slew` wait there (the filter starts when the Sun is seen) instead
/// of counting towards the fall-back to `SunSafe`.
pub(crate) fn in_umbra(det: &StepReport) -> bool {
    det.sun_fraction.is_some_and(|f| !(f > 0.0))
}

/// A law's command, or none (zero) with the refusal reported in `faults.law`.
pub(super) fn reported(command: Option<Vec3>, faults: &mut Faults) -> Vec3 {
    faults.law |= command.is_none();
    command.unwrap_or_else(Vec3::zeros)
}

impl<const N: usize> AttitudeNode<'_, N> {
    /// The umbra by the step's REF ([`in_umbra`]), or without one by the last REF's.
    fn umbra(&self, det: &StepReport) -> bool {
        match det.sun_fraction {
            Some(_) => in_umbra(det),
            None => self.last_umbra,
        }
    }

    /// Step phase 5a: the events of the rate and of the validity of the attitude.
    pub(super) fn change_mode(&mut self, det: &StepReport) {
        let rate = det.omega_body_radps.map(|w| crate::linalg::norm(&w));
        if let Some(r) = rate {
            if r > self.config.detumble_enter_radps {
                self.transition(Event::RateAbove);
            } else if self.config.detumble_exit_radps > r {
                self.transition(Event::RateBelow);
            }
        }
        if matches!(self.mode(), Mode::Slew | Mode::Tracking) {
            if det.attitude.is_some() {
                self.invalid_steps = 0;
            } else if !self.umbra(det) {
                self.invalid_steps = self.invalid_steps.saturating_add(1);
                if self.invalid_steps >= INVALID_STEPS_TO_SAFE {
                    self.transition(Event::AttitudeLost);
                    // lost for want of the reference node: its guidance resumes with the link
                    self.resume_guidance = self.without_reference > 0;
                }
            }
        }
    }

    /// Step phase 5b: the mode's law on the step's report `det`. Writes the coil dipole (body,
    /// A·m²) into `det.dipole_body_am2` (in place: on the MSP430 each copy of a vector is a
    /// `memcpy`) and returns the wheel momentum to hold (body, kg·m²/s; `None`: hold the
    /// momentum in force). A law that refuses its input sets `faults.law` and commands nothing
    /// (coils off, wheels held).
    #[inline(never)]
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub(super) fn laws(
        &mut self,
        det: &mut StepReport,
        dt: f32,
        guidance: Option<&Guidance>,
        faults: &mut Faults,
    ) -> Option<Vec3> {
        // by reference: on the MSP430 each copy of an option is a `memcpy` call
        let (omega, b_body_nt) = (det.omega_body_radps.as_ref(), det.b_body_nt.as_ref());
        det.dipole_body_am2 = Vec3::zeros();
        let mut torque: Option<Vec3> = None;
        let mut h_target: Option<Vec3> = None;
        // the Sun of the sun-safe law if it runs this step: in sun-safe (with the rate), and in
        // tracking without an attitude in the umbra (no Sun: the rate damped)
        let mut sun_safe_sun: Option<Option<&Vec3>> = None;
        match &self.mode {
            // the command written into `dipole` in place (on the MSP430 each copy of a vector
            // is a `memcpy`); a refusal leaves it zero, reported
            ModeState::Detumble => match (omega, b_body_nt) {
                (Some(w), Some(b)) => {
                    // the derivative form must not difference against a sample taken
                    // before a gyro outage: forget it while the gyro form runs
                    self.bdot.reset();
                    match bdot_from_rates(&self.config.bdot, w, b) {
                        Ok(m) => det.dipole_body_am2 = m,
                        Err(_) => faults.law = true,
                    }
                }
                // `Ok(None)`: the first sample of the derivative form, nothing to command
                (None, Some(b)) => match self.bdot.update(&self.config.bdot, b, dt) {
                    Ok(Some(m)) => det.dipole_body_am2 = m,
                    Ok(None) => {}
                    Err(_) => faults.law = true,
                },
                _ => {}
            },
            ModeState::SunSafe => sun_safe_sun = Some(det.sun_body.as_ref()),
            ModeState::Slew { .. } | ModeState::Tracking { .. } => {}
        }
        // a slew: the REF's reference (its rate, feed-forward) tracked in closed loop, the
        // follower's attitude integrated from its rates, the feedback's torque integrated into
        // the wheels beside the feed-forward (without an attitude the feed-forward alone;
        // without a REF the wheels hold and the follower holds its rate); its guidance turned
        // to tracking: done, track the target
        if let ModeState::Slew { .. } = self.mode {
            match guidance {
                Some(g) if g.kind == GuidanceKind::Track => self.transition(Event::SlewDone),
                _ => {
                    let reference =
                        guidance
                            .filter(|g| g.kind == GuidanceKind::Slew)
                            .map(|g| SlewReference {
                                rate_body_radps: g.rate_body_radps,
                                h_ff_body_nms: g.h_ff_body_nms,
                            });
                    let h_w = self.wheels_body();
                    let config = self.config;
                    if let ModeState::Slew { follower, .. } = &mut self.mode {
                        h_target =
                            config.follow_slew(follower, reference.as_ref(), det, &h_w, dt, faults);
                    }
                }
            }
        }
        // the wheels' momentum in force, summed once for the tracking law and the integration
        let mut h_now: Option<Vec3> = None;
        if let ModeState::Tracking { target } = &self.mode {
            // no attitude in the umbra (the filter starts with the Sun): damp the rate, wait
            if let (None, Some(_), true) = (det.attitude.as_ref(), omega, self.umbra(det)) {
                sun_safe_sun = Some(None);
            }
            if let (Some(q), Some(w)) = (det.attitude.as_ref(), omega) {
                let h_w = self.wheels_body();
                h_now = Some(h_w);
                // (torque is none until here: a refusal leaves it so, reported)
                match tracking_torque(
                    &self.config.tracking,
                    &self.config.axes.inertia_body,
                    q,
                    w,
                    target,
                    &Vec3::zeros(),
                    &h_w,
                ) {
                    Ok(t) => torque = Some(t),
                    Err(_) => faults.law = true,
                }
            }
        }
        // the sun-safe law (one call for both uses; tracking's is the attitude's case only)
        // (torque is none until here in both: a refusal leaves it so, reported)
        if let (Some(sun), Some(w)) = (sun_safe_sun, omega) {
            match sun_safe_torque(&self.config.sun_safe, sun, &self.config.sun_axis_body, w) {
                Ok(t) => torque = Some(t),
                Err(_) => faults.law = true,
            }
        }
        // wheels: a torque law integrates into momentum (ḣ = −τ); a slew sets momentum
        if let Some(tau) = &mut torque {
            if self.have_wheels() {
                // no more than the wheels deliver: a momentum they cannot follow is never
                // commanded (the laws integrate the commanded momentum: the read-back only
                // checks the wheels, `attitude_node::health`). The coils' per-axis scaling keeping
                // the direction; it refuses a limit that is not positive and finite: none
                if let Ok((t, _)) =
                    crate::control::magnetorquer::saturate_dipole(tau, &self.config.wheel_torque_nm)
                {
                    *tau = t;
                }
                let h_w = h_now.unwrap_or_else(|| self.wheels_body());
                h_target = Some(crate::linalg::sub_scaled(&h_w, tau, dt));
            } else if let Some(b) = b_body_nt {
                match dipole_for_torque(tau, b) {
                    Ok(m) => det.dipole_body_am2 = m,
                    Err(_) => {
                        faults.law = true;
                        det.dipole_body_am2 = Vec3::zeros();
                    }
                }
            }
        }
        h_target
    }
}
