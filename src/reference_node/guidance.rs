//! The reference node's guidance: the ground's track and slew commands, which it owns. A slew is
//! the thesis's three-axis decomposition (seed 000 §7, [`crate::control::slew`]) planned from
//! the attitude the attitude node last reported, each rotation rounded up to whole control
//! periods with its momentum scaled to keep the angle; each REF carries the plan's body momentum
//! at that step's UTC (the feed-forward), then, the plan done, tracking of its target.
//!
//! Attitudes are `v_body = A · v_ref`, reference TEME of date ([`crate::attitude`]).

use super::ReferenceNode;
use crate::acs_loop::AcsError;
use crate::attitude::{Dcm, Quaternion};
use crate::control::slew::{decompose, manoeuvre_matrix, plan, Branch, SlewPlan};
use crate::linalg::Vec3;
use crate::link::messages::{Guidance, GuidanceKind};
use crate::time::{Epoch, Utc};

/// A slew in progress: what its execution needs of the plan (the rotations' durations, rounded
/// to whole control periods, and body momenta, in execution order) and its start.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) struct SlewProgress {
    /// `(duration_s, h_body)` of each rotation.
    steps: [(f32, Vec3); 3],
    started: Epoch<Utc>,
}

impl<const N: usize, const F: usize> ReferenceNode<'_, N, F> {
    /// The ground's track command: track `target` (reference → body) from the next REF on.
    pub fn track(&mut self, target: Quaternion) {
        self.slew = None;
        self.new_guidance(GuidanceKind::Track, target);
    }

    /// The ground's slew command: the thesis's plan from `attitude` (the last the attitude node
    /// reported, reference → body) to `target` within `within_s`, started `now`; the guidance
    /// left as it was if the planner refuses. Out of line: the planner's temporaries stay off
    /// the step's stack.
    #[inline(never)]
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn slew(
        &mut self,
        attitude: &Quaternion,
        target: &Dcm,
        within_s: f32,
        now: Epoch<Utc>,
    ) -> Result<(), AcsError> {
        let m = manoeuvre_matrix(&attitude.to_dcm(), target, &self.config.axes);
        let angles = decompose(&m, Branch::Shortest).map_err(|_| AcsError::CannotSlew)?;
        let plan: SlewPlan = plan(
            &self.config.axes,
            &angles,
            &self.config.slew_limits,
            within_s,
        )
        .map_err(|_| AcsError::CannotSlew)?;
        // whole control periods, same angle: L·t constant
        let period = self.config.control_period_s;
        let mut slew = SlewProgress {
            steps: [(0.0f32, Vec3::zeros()); 3],
            started: now,
        };
        for ((duration, h), s) in slew.steps.iter_mut().zip(plan.steps.iter()) {
            if s.duration_s > 0.0 {
                let ticks = crate::fmath::max(s.duration_s / period - 1e-4, 0.0) as u32 + 1;
                let rounded = ticks as f32 * period;
                *h = s.h_body * (s.duration_s / rounded);
                *duration = rounded;
            }
        }
        self.slew = Some(slew);
        self.new_guidance(GuidanceKind::Slew, target.to_quaternion());
        Ok(())
    }

    /// A new command's guidance, with an id neither this node nor the attitude node used last
    /// (after a reset of this node its count starts from the attitude node's).
    fn new_guidance(&mut self, kind: GuidanceKind, target: Quaternion) {
        let last = core::cmp::max(self.guidance.id, self.accepted_id);
        let id = match last.wrapping_add(1) {
            0 => 1,
            id => id,
        };
        self.guidance = Guidance {
            id,
            kind,
            target,
            ..Guidance::NONE
        };
    }

    /// The guidance at `now`: a slew's momentum at that time, or, its plan done, tracking of
    /// its target.
    pub(super) fn guidance_at(&mut self, now: &Epoch<Utc>) -> Guidance {
        if let Some(p) = &self.slew {
            match self.slew_momentum(p, now) {
                Some(h) => self.guidance.h_ff_body_nms = h,
                None => {
                    self.slew = None;
                    self.guidance.kind = GuidanceKind::Track;
                    self.guidance.h_ff_body_nms = Vec3::zeros();
                }
            }
        }
        self.guidance
    }

    /// The body momentum the slew `p` asks of the wheels, beyond what they held before it, at
    /// `now` (the step's momentum while rotating, none while stopping between axes), `None`
    /// when the plan is done.
    fn slew_momentum(&self, p: &SlewProgress, now: &Epoch<Utc>) -> Option<Vec3> {
        // half a period of margin: boundaries fall on ticks
        let t = now.seconds_since_f32(&p.started) + 0.5 * self.config.control_period_s;
        let mut t0 = 0.0f32;
        for (duration_s, h_body) in p.steps.iter() {
            if t0 + duration_s > t {
                // rotating: the body holds the step's momentum
                return Some(*h_body);
            }
            if t0 + duration_s + self.config.slew_pause_s > t {
                // stopping before the next axis
                return Some(Vec3::zeros());
            }
            t0 += duration_s + self.config.slew_pause_s;
        }
        None
    }
}
