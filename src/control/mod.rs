//! Attitude control: principal axes, the thesis's open-loop slew planner, wheel allocation,
//! closed-loop laws, and sizing.
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref`, quaternions scalar-first.

pub mod bdot;
pub mod disturbance;
pub mod magnetorquer;
pub mod principal_axes;
pub mod sizing;
pub mod slew;
pub mod sun_safe;
pub mod tracking;
pub mod wheels;
