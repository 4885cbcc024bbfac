//! The reference node (issue #29): the on-board clock as uplinked, SGP4 propagation, the Sun,
//! the shadow, the IGRF field, and the guidance (the ground's track and slew commands). Each
//! period it answers the attitude node's STATUS with the REF for the next step
//! ([`crate::link::messages`]); it commands no actuator.
//!
//! | module | what |
//! |---|---|
//! | [`models`] | position, Sun, shadow and field at a step's UTC |
//! | [`guidance`] | track and slew commands, the slew's plan and its momentum at each step |
//!
//! # The clock
//! The clock is the UTC of the step the next REF is for, advanced one control period per REF.
//! After a reset the node has none: its REFs say `clock_valid = false` (the attitude node
//! never uses them) until the ground sets it ([`ReferenceNode::set_clock`]) or a STATUS brings
//! the attitude node's copy back. The clock is never written to flash.
//!
//! Attitudes are `v_body = A · v_ref`, reference TEME of date ([`crate::attitude`]).

use crate::acs_loop::{AcsConfig, AcsError};
use crate::attitude::Quaternion;
use crate::env::albedo;
use crate::env::igrf::coefficient_count;
use crate::linalg::Vec3;
use crate::link::messages::{Guidance, GuidanceKind, Reference, Status};
use crate::orbit::sgp4::Sgp4;
use crate::telemetry::Housekeeping;
use crate::tiles::MAX_TILES;
use crate::time::{Epoch, TimeSpan, Utc};

pub mod guidance;
pub mod models;

use guidance::SlewProgress;

/// The reference node's state, for the configuration of a satellite of `N` tiles, with room for
/// `F` IGRF coefficients (`F` ≥ [`coefficient_count`] of the configured degree; they take
/// `4·F` bytes of stack while the field is evaluated, none in the state).
#[derive(Clone, Debug)]
pub struct ReferenceNode<
    'c,
    const N: usize = MAX_TILES,
    const F: usize = { crate::env::igrf::FULL_COEFFS },
> {
    config: &'c AcsConfig<N>,
    orbit: Option<Sgp4>,
    /// The UTC of the step the next REF is for; `None` until set.
    clock: Option<Epoch<Utc>>,
    /// The control period: positive ([`ReferenceNode::new`] refuses another), so the clock
    /// moves on by [`Epoch::add_nonnegative`] (the same epoch as [`Epoch::add`], in fewer
    /// bytes of MSP430 code).
    period: TimeSpan,
    /// The guidance in force.
    guidance: Guidance,
    /// The slew in progress, if the guidance is one.
    slew: Option<SlewProgress>,
    /// The id of the last guidance the attitude node accepted (its last STATUS).
    accepted_id: u16,
    /// The housekeeping schedule the ground sets ([`crate::telemetry`]).
    housekeeping: Housekeeping,
}

impl<'c, const N: usize, const F: usize> ReferenceNode<'c, N, F> {
    /// A node with the given orbit (or none: its REFs say `elements_valid = false` and carry no
    /// models, with [`crate::acs_loop::Faults::orbit`] set) and no clock.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn new(config: &'c AcsConfig<N>, orbit: impl Into<Option<Sgp4>>) -> Result<Self, AcsError> {
        let ok = config.control_period_s > 0.0
            && config.control_period_s.is_finite()
            && config.slew_pause_s >= 0.0
            && config.slew_pause_s.is_finite();
        if !ok || coefficient_count(config.igrf_degree.get()) > F {
            return Err(AcsError::InvalidConfig);
        }
        Ok(Self {
            config,
            orbit: orbit.into(),
            clock: None,
            period: TimeSpan::from_seconds_f32(config.control_period_s),
            // element by element (`Guidance::NONE` was a 44-byte copy from flash)
            guidance: Guidance {
                id: 0,
                kind: GuidanceKind::None,
                target: Quaternion {
                    q0: 1.0,
                    q1: 0.0,
                    q2: 0.0,
                    q3: 0.0,
                },
                rate_body_radps: Vec3::new(0.0, 0.0, 0.0),
                h_ff_body_nms: Vec3::new(0.0, 0.0, 0.0),
            },
            slew: None,
            accepted_id: 0,
            housekeeping: Housekeeping::new(),
        })
    }

    /// Replaces the element set (an uplink: check the words with [`Sgp4::from_words`] first, so
    /// that a refused set leaves the one in use).
    pub fn set_orbit(&mut self, orbit: Sgp4) {
        self.orbit = Some(orbit);
    }

    /// Sets the clock: `utc` is the UTC of the step the next REF is for.
    pub fn set_clock(&mut self, utc: Epoch<Utc>) {
        self.clock = Some(utc);
    }

    /// The guidance in force (the next REF's, before a slew's momentum is updated to its UTC).
    pub fn guidance(&self) -> &Guidance {
        &self.guidance
    }

    /// The element set's epoch, if the node holds one.
    pub fn elements_epoch(&self) -> Option<Epoch<Utc>> {
        self.orbit.as_ref().map(Sgp4::epoch)
    }

    /// The housekeeping schedule ([`crate::telemetry`]).
    pub fn housekeeping(&self) -> &Housekeeping {
        &self.housekeeping
    }

    /// The housekeeping schedule, for the ground's interval and the image's period count.
    pub fn housekeeping_mut(&mut self) -> &mut Housekeeping {
        &mut self.housekeeping
    }

    /// The clock (the UTC of the step the next REF is for), if set.
    pub fn clock(&self) -> Option<Epoch<Utc>> {
        self.clock
    }

    /// The REF for step `step`, after the attitude node's last STATUS (if any): the models at
    /// the clock and the guidance; then the clock moves on one period. Without a clock, a REF
    /// with `clock_valid = false` and nothing else (unless `status` brings the attitude node's
    /// clock for the step before). [`ReferenceNode::reference_into`] builds it in place.
    pub fn reference(&mut self, step: u32, status: Option<&Status>) -> Reference {
        let mut r = Reference {
            step,
            utc: Epoch::DAY0,
            clock_valid: false,
            elements_valid: false,
            r_teme_km: None,
            sun_teme: None,
            illumination: None,
            b_teme_nt: None,
            albedo_teme: None,
            guidance: Guidance::NONE,
            faults: 0,
        };
        self.reference_into(step, status, &mut r);
        r
    }

    /// [`ReferenceNode::reference`] written into `r` (every field: its previous value does not
    /// matter), with no copy of the REF on the way (the flight images: 126 bytes, ~800 cycles
    /// a step on the MSP430).
    #[inline(never)]
    pub fn reference_into(&mut self, step: u32, status: Option<&Status>, r: &mut Reference) {
        if let Some(s) = status {
            self.accepted_id = s.guidance_id;
            if self.clock.is_none() && s.step.wrapping_add(1) == step {
                self.clock = s.utc.map(|u| u.add_nonnegative(self.period));
            }
        }
        // the guidance first (it does not depend on the models): the REF then takes it once
        if let Some(now) = self.clock {
            self.advance_guidance(&now);
        }
        r.step = step;
        r.elements_valid = self.orbit.is_some();
        r.guidance = self.guidance;
        if let Some(now) = self.clock {
            // the models straight into the REF, their faults as the word (`Faults::bits`)
            r.faults = self.models(&now, r);
            r.utc = now;
            r.clock_valid = true;
            // the albedo the attitude node's lit Sun sensors see, at the last STATUS's attitude
            r.albedo_teme = match (&r.r_teme_km, &r.sun_teme, status.and_then(|s| s.attitude)) {
                (Some(pos), Some(sun), Some(q)) => albedo::seen_by_lit_sensors(
                    self.config.tiles.as_slice(),
                    pos,
                    sun,
                    &q,
                    self.config.filter.sun_sensor_cos_half_fov,
                ),
                _ => None,
            };
            self.clock = Some(now.add_nonnegative(self.period));
        } else {
            r.utc = Epoch::DAY0;
            r.clock_valid = false;
            r.r_teme_km = None;
            r.sun_teme = None;
            r.illumination = None;
            r.b_teme_nt = None;
            r.albedo_teme = None;
            r.faults = 0;
        }
    }
}
