//! Attitude control: principal axes, the thesis's slew planner and the reference trajectory
//! that flies it in closed loop, wheel allocation, closed-loop laws, and sizing.
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref`, quaternions scalar-first.

pub mod bdot;
pub mod disturbance;
pub mod magnetorquer;
pub mod principal_axes;
pub mod sizing;
pub mod slew;
pub mod slew_trajectory;
pub mod sun_safe;
pub mod tracking;
pub mod wheels;
