//! Attitude control.
