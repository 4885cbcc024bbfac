//! The attitude node's mode machine: the modes, what changes them, and the one function that
//! makes every transition (the table of [`crate::acs_loop`]'s module docs).
//!
//! Attitudes are `v_body = A(q) · v_ref`, reference TEME of date, quaternions scalar-first
//! ([`crate::attitude`]).

use crate::attitude::Quaternion;
use crate::control::slew_trajectory::SlewFollower;
use crate::linalg::Vec3;

/// Consecutive steps without a valid attitude, outside the umbra, after which `Slew`/`Tracking`
/// fall back to `SunSafe`. In the umbra they wait instead, `Tracking` damping the rate: the
/// filter starts again when the Sun is seen (issue #30; `laws::in_umbra`).
pub const INVALID_STEPS_TO_SAFE: u16 = 30;

/// The operating mode.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Mode {
    /// Rate damping with the magnetorquers (B-dot).
    Detumble,
    /// Sun pointing of the array normal, rate damping in eclipse.
    SunSafe,
    /// A slew in progress: the reference node's plan, flown in closed loop on its reference
    /// trajectory ([`crate::control::slew_trajectory`]).
    Slew,
    /// Closed-loop tracking of a commanded attitude.
    Tracking,
}

impl Mode {
    /// The mode as a telemetry code: 0 `Detumble`, 1 `SunSafe`, 2 `Slew`, 3 `Tracking`.
    pub fn code(self) -> u16 {
        match self {
            Self::Detumble => 0,
            Self::SunSafe => 1,
            Self::Slew => 2,
            Self::Tracking => 3,
        }
    }
}

/// The mode with the data it runs on (issue #19 item 3): a slew carries its target and its
/// follower (with the momentum the wheels hold beside its feed-forward), tracking its target,
/// so no mode can run without its data.
/// [`Mode`] is its tag (telemetry); [`next_mode`] holds every transition.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) enum ModeState {
    Detumble,
    SunSafe,
    /// The slew the reference node plans, flown in closed loop on its reference trajectory
    /// (`follower`: [`crate::control::slew_trajectory`]), then tracking of `target` (reference
    /// → body); the wheels hold the follower's momentum (theirs when the slew was accepted, the
    /// feedback's torque integrated) less the reference's feed-forward momentum.
    Slew {
        target: Quaternion,
        follower: SlewFollower,
    },
    /// Tracking of `target` (reference → body).
    Tracking {
        target: Quaternion,
    },
}

impl ModeState {
    /// The mode's tag.
    pub(super) fn mode(&self) -> Mode {
        match self {
            Self::Detumble => Mode::Detumble,
            Self::SunSafe => Mode::SunSafe,
            Self::Slew { .. } => Mode::Slew,
            Self::Tracking { .. } => Mode::Tracking,
        }
    }
}

/// What changes the mode: the step's findings, the ground's sun-safe command and the reference
/// node's guidance.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) enum Event {
    /// The body rate is above `detumble_enter_radps`.
    RateAbove,
    /// The body rate is below `detumble_exit_radps`.
    RateBelow,
    /// [`INVALID_STEPS_TO_SAFE`] steps in a row without a valid attitude.
    AttitudeLost,
    /// The slew's plan is done (its guidance turned to tracking).
    SlewDone,
    /// Ground: sun-safe.
    SunSafe,
    /// Guidance: track `target` (reference → body).
    Track(Quaternion),
    /// Guidance: a slew to the target, the wheels' momentum at its start.
    Slew { h_base: Vec3, target: Quaternion },
}

/// The mode machine's one transition function (the table of the module docs): `state` becomes
/// the mode after `event`, in place. An event that does not apply to the mode leaves it.
pub(super) fn next_mode(state: &mut ModeState, event: Event) {
    use ModeState as S;
    // each new state written in place (on the MSP430 a state built aside is a `memcpy`)
    match event {
        Event::RateAbove => *state = S::Detumble,
        Event::RateBelow => {
            if let S::Detumble = state {
                *state = S::SunSafe;
            }
        }
        Event::AttitudeLost => {
            if let S::Slew { .. } | S::Tracking { .. } = state {
                *state = S::SunSafe;
            }
        }
        Event::SlewDone => {
            if let S::Slew { target, .. } = state {
                *state = S::Tracking { target: *target };
            }
        }
        Event::SunSafe => *state = S::SunSafe,
        Event::Track(target) => *state = S::Tracking { target },
        Event::Slew { h_base, target } => {
            *state = S::Slew {
                target,
                follower: SlewFollower::new(h_base),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every (mode, event) pair through `next_mode` against the table of the module docs; the
    /// scripted-bus walk of every transition through the public API is `tests/modes.rs`.
    #[test]
    fn next_mode_table() {
        let q = |x: f32| Quaternion {
            q0: 1.0,
            q1: x,
            q2: 0.0,
            q3: 0.0,
        };
        let h = Vec3::x();
        let detumble = ModeState::Detumble;
        let sun_safe = ModeState::SunSafe;
        let slew = ModeState::Slew {
            target: q(0.1),
            follower: SlewFollower::new(h),
        };
        let tracking = ModeState::Tracking { target: q(0.2) };
        let new_slew = ModeState::Slew {
            target: q(0.3),
            follower: SlewFollower::new(h),
        };
        let events = [
            Event::RateAbove,
            Event::RateBelow,
            Event::AttitudeLost,
            Event::SlewDone,
            Event::SunSafe,
            Event::Track(q(0.4)),
            Event::Slew {
                h_base: h,
                target: q(0.3),
            },
        ];
        let track_new = ModeState::Tracking { target: q(0.4) };
        // rows: the state before; the state after each event, in `events`' order
        #[rustfmt::skip]
        let table = [
            (detumble, [detumble, sun_safe, detumble, detumble, sun_safe, track_new, new_slew]),
            (sun_safe, [detumble, sun_safe, sun_safe, sun_safe, sun_safe, track_new, new_slew]),
            (slew, [detumble, slew, sun_safe, ModeState::Tracking { target: q(0.1) }, sun_safe, track_new, new_slew]),
            (tracking, [detumble, tracking, sun_safe, tracking, sun_safe, track_new, new_slew]),
        ];
        for (before, afters) in table.iter() {
            for (event, after) in events.iter().zip(afters.iter()) {
                let mut state = *before;
                next_mode(&mut state, *event);
                assert_eq!(state, *after, "{before:?} + {event:?}");
            }
        }
    }
}
