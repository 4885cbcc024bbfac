//! The reference node's guidance: the ground's track and slew commands, which it owns. A slew is
//! the thesis's three-axis decomposition (seed 000 §7, [`crate::control::slew`]) planned from
//! the attitude the attitude node last reported and flown on its reference trajectory
//! ([`crate::control::slew_trajectory`]: rate ramps the wheels' torque allows, whole control
//! periods); each REF carries its target and the reference at that step's UTC (the mean rate
//! over the period before and the body's feed-forward momentum over the period after), which
//! the attitude node follows in closed loop, then, the trajectory done, tracking of the
//! target.
//!
//! Attitudes are `v_body = A · v_ref`, reference TEME of date ([`crate::attitude`]).

use super::ReferenceNode;
use crate::acs_loop::AcsError;
use crate::attitude::{Dcm, Quaternion};
use crate::control::slew_trajectory::SlewTrajectory;
use crate::linalg::Vec3;
use crate::link::messages::{Guidance, GuidanceKind};
use crate::time::{Epoch, Utc};

/// A slew in progress: its reference trajectory and its start.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) struct SlewProgress {
    trajectory: SlewTrajectory,
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
        let trajectory = self
            .config
            .slew_trajectory(&attitude.to_dcm(), target, within_s)?;
        self.slew = Some(SlewProgress {
            trajectory,
            started: now,
        });
        self.new_guidance(GuidanceKind::Slew, target.to_quaternion());
        Ok(())
    }

    /// A new command's guidance, with an id neither this node nor the attitude node used last
    /// (after a reset of this node its count starts from the attitude node's). Out of line on
    /// the MSP430: the track and the slew commands share it.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    fn new_guidance(&mut self, kind: GuidanceKind, target: Quaternion) {
        let last = core::cmp::max(self.guidance.id, self.accepted_id);
        let id = match last.wrapping_add(1) {
            0 => 1,
            id => id,
        };
        // the rates element by element (from `Guidance::NONE` they were copied from flash)
        self.guidance = Guidance {
            id,
            kind,
            target,
            rate_body_radps: Vec3::new(0.0, 0.0, 0.0),
            h_ff_body_nms: Vec3::new(0.0, 0.0, 0.0),
        };
    }

    /// The guidance moved to `now`: a slew's reference at that time, or, its trajectory done,
    /// tracking of its target.
    pub(super) fn advance_guidance(&mut self, now: &Epoch<Utc>) {
        let period = self.config.control_period_s;
        if let Some(p) = &mut self.slew {
            let g = &mut self.guidance;
            match p.trajectory.at(now.seconds_since_f32(&p.started), period) {
                Some(r) => {
                    g.rate_body_radps = r.rate_body_radps;
                    g.h_ff_body_nms = r.h_ff_body_nms;
                }
                None => {
                    g.kind = GuidanceKind::Track;
                    // element by element (`Vec3::zeros()` is a loop and a copy on the MSP430)
                    g.rate_body_radps = Vec3::new(0.0, 0.0, 0.0);
                    g.h_ff_body_nms = Vec3::new(0.0, 0.0, 0.0);
                    self.slew = None;
                }
            }
        }
    }
}
