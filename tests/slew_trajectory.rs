//! The slew's reference trajectory (`acs::control::slew_trajectory`, issue #30 item 4): over
//! random slews, the trajectory ends at the plan's target, never asks more rate than the plan
//! or more torque than its share of the wheels', and its feed-forward turns the body by the
//! reference's angle each period.

mod common;
mod figures;
use common::Lcg;
use figures::figure;

use acs::attitude::{Dcm, Quaternion};
use acs::control::principal_axes::{principal_axes, PrincipalAxes};
use acs::control::slew::{decompose, manoeuvre_matrix, plan, Branch, SlewError, SlewLimits};
use acs::control::slew_trajectory::{turned, SlewFollower, SlewTrajectory, TORQUE_FRACTION};
use acs::flight::CONFIG;
use acs::linalg::{Mat3, Vec3};

/// Random attitudes from the tests' shared generator.
trait RandomAttitude {
    /// A uniformly random attitude (Shoemake).
    fn attitude(&mut self) -> Quaternion;
}

impl RandomAttitude for Lcg {
    fn attitude(&mut self) -> Quaternion {
        let (u1, u2, u3) = (self.uniform(), self.uniform(), self.uniform());
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        let q = [
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
            b * (tau * u3).cos(),
        ];
        Quaternion::new_normalize(q[0] as f32, q[1] as f32, q[2] as f32, q[3] as f32).unwrap()
    }
}

/// What one slew's trajectory measured.
#[derive(Default)]
struct Flown {
    /// The attitude the trajectory rests at, from the target, rad.
    end_rad: f64,
    /// The attitude the feed-forward's mean rates integrate to (f64), from the reference's at
    /// each period, rad: worst.
    feed_forward_rad: f64,
    /// The largest rate over the plan's rate of its rotation.
    rate_ratio: f64,
    /// The largest change of the feed-forward momentum over a period about a body axis, over
    /// the ramps' share of the wheels' torque about that axis.
    torque_ratio: f64,
    /// The trajectory's length, s.
    duration_s: f64,
}

fn qmul(p: [f64; 4], r: [f64; 4]) -> [f64; 4] {
    [
        p[0] * r[0] - p[1] * r[1] - p[2] * r[2] - p[3] * r[3],
        p[1] * r[0] + p[2] * r[3] - p[3] * r[2] + p[0] * r[1],
        -p[1] * r[3] + p[2] * r[0] + p[3] * r[1] + p[0] * r[2],
        p[1] * r[2] - p[2] * r[1] + p[3] * r[0] + p[0] * r[3],
    ]
}

fn angle_between(a: [f64; 4], q: &Quaternion) -> f64 {
    // 2 atan2(|v|, |w|) of a* ⊗ q: well conditioned near zero (an acos of the dot product
    // turns the f32 norm's 1e-7 into 1e-3 rad)
    let r = qmul(
        [a[0], -a[1], -a[2], -a[3]],
        [q.q0 as f64, q.q1 as f64, q.q2 as f64, q.q3 as f64],
    );
    2.0 * (r[1] * r[1] + r[2] * r[2] + r[3] * r[3])
        .sqrt()
        .atan2(r[0].abs())
}

/// Flies the trajectory of the slew from `start` to `target` at whole periods.
fn fly(
    axes: &PrincipalAxes,
    limits: &SlewLimits,
    torque_nm: &Vec3,
    start: &Quaternion,
    target: &Quaternion,
    period_s: f32,
) -> Flown {
    let m = manoeuvre_matrix(&start.to_dcm(), &target.to_dcm(), axes);
    let angles = decompose(&m, Branch::Shortest).unwrap();
    let p = plan(axes, &angles, limits, 1.0e4).unwrap();
    let pause = 5.0;
    let mut trajectory = SlewTrajectory::new(&p, axes, torque_nm, period_s, pause).unwrap();
    let mut follower = SlewFollower::new(Vec3::zeros());
    let mut followed = *start;
    let inverse = axes.inertia_body.try_inverse().unwrap();
    let peak = p
        .steps
        .iter()
        .map(|s| s.omega_body_radps.norm() as f64)
        .fold(0.0, f64::max);
    // the ramps' share of the wheels' torque about each body axis
    let tau = *torque_nm * TORQUE_FRACTION;
    let mut flown = Flown::default();
    let mut q_ff = [
        start.q0 as f64,
        start.q1 as f64,
        start.q2 as f64,
        start.q3 as f64,
    ];
    let mut last: Option<acs::control::slew_trajectory::SlewReference> = None;
    for k in 0.. {
        let t = k as f32 * period_s;
        let Some(r) = trajectory.at(t, period_s) else {
            flown.duration_s = t as f64;
            break;
        };
        // the follower's profile attitude (the one it tracks lags it by the wheels'
        // transition, TORQUE_FRACTION of half a period, along the same rate: turned back)
        let tracked = follower.advance(Some(&r), Some(start), period_s).unwrap();
        let lag = TORQUE_FRACTION * 0.5 * period_s;
        followed = turned(&tracked, &(r.rate_body_radps * lag));
        flown.feed_forward_rad = flown.feed_forward_rad.max(angle_between(q_ff, &followed));
        flown.rate_ratio = flown.rate_ratio.max(r.rate_body_radps.norm() as f64 / peak);
        if let Some(l) = &last {
            let dh = (r.h_ff_body_nms - l.h_ff_body_nms) / period_s;
            let ratio = dh.abs().component_div(&tau).max() as f64;
            flown.torque_ratio = flown.torque_ratio.max(ratio);
        }
        // the body turned by the feed-forward's mean rate over the period
        let w = inverse * r.h_ff_body_nms;
        let w = [w.x as f64, w.y as f64, w.z as f64];
        let n = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        if n > 0.0 {
            let half = 0.5 * n * period_s as f64;
            let s = half.sin() / n;
            q_ff = qmul(q_ff, [half.cos(), w[0] * s, w[1] * s, w[2] * s]);
        }
        last = Some(r);
        assert!(k < 100_000, "the trajectory never ends");
    }
    flown.end_rad = angle_between(
        [
            target.q0 as f64,
            target.q1 as f64,
            target.q2 as f64,
            target.q3 as f64,
        ],
        &followed,
    );
    flown
}

/// 200 random slews on the flight configuration and 200 on a satellite whose principal axes are
/// not its body axes, at the flight period and the thesis's 0.1 s.
#[test]
fn trajectories_end_at_the_target_within_the_wheels_limits() {
    let tilted = Mat3::new(
        0.012, 0.001, -0.0005, 0.001, 0.010, 0.0008, -0.0005, 0.0008, 0.014,
    );
    let tilted = principal_axes(&tilted).unwrap();
    let cases: [(&str, &PrincipalAxes, f32); 3] = [
        ("flight", &CONFIG.axes, 1.0),
        ("flight_0.1s", &CONFIG.axes, 0.1),
        ("tilted", &tilted, 1.0),
    ];
    let mut rng = Lcg(30);
    for (name, axes, period) in cases {
        let (mut end, mut ff, mut rate, mut torque, mut longest) =
            (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for _ in 0..200 {
            let (start, target) = (rng.attitude(), rng.attitude());
            let f = fly(
                axes,
                &CONFIG.slew_limits,
                &CONFIG.wheel_torque_nm,
                &start,
                &target,
                period,
            );
            end = end.max(f.end_rad);
            ff = ff.max(f.feed_forward_rad);
            rate = rate.max(f.rate_ratio);
            torque = torque.max(f.torque_ratio);
            longest = longest.max(f.duration_s);
        }
        println!(
            "{name}: end {end:.3e} rad, feed-forward {ff:.3e} rad, rate/plan {rate:.6}, torque/ramp {torque:.6}, longest {longest:.0} s"
        );
        figure(&format!("slew_trajectory.{name}.end_rad"), end);
        figure(&format!("slew_trajectory.{name}.feed_forward_rad"), ff);
        figure(&format!("slew_trajectory.{name}.rate_over_plan"), rate);
        figure(&format!("slew_trajectory.{name}.torque_over_ramp"), torque);
        // the trajectory ends at the target: the decomposition's f32 rounding
        assert!(end < 1e-5, "{name}: end {end}");
        // the feed-forward turns the body by the reference's angle: the profile is linear
        // between whole periods, the mean rate exact
        assert!(ff < 1e-5, "{name}: feed-forward {ff}");
        // never more rate than the plan's (its momentum), nor more torque than the ramps'
        assert!(rate <= 1.0 + 1e-5, "{name}: rate {rate}");
        assert!(torque <= 1.0 + 1e-3, "{name}: torque {torque}");
    }
}

/// A torque, period or pause that is not positive and finite is refused; a null slew takes no
/// time.
#[test]
fn invalid_limits_are_refused_and_a_null_slew_takes_no_time() {
    let axes = &CONFIG.axes;
    let q = Quaternion::IDENTITY;
    let plan_to = |target: &Dcm| {
        let m = manoeuvre_matrix(&q.to_dcm(), target, axes);
        let angles = decompose(&m, Branch::Shortest).unwrap();
        plan(axes, &angles, &CONFIG.slew_limits, 100.0).unwrap()
    };
    let p = plan_to(&Dcm::a1(0.5));
    let torque = CONFIG.wheel_torque_nm;
    let (nan, inf) = (f32::NAN, f32::INFINITY);
    for (t, period, pause) in [
        (Vec3::new(0.0, 1e-4, 1e-4), 1.0, 5.0),
        (Vec3::new(nan, 1e-4, 1e-4), 1.0, 5.0),
        (Vec3::new(1e-4, nan, 1e-4), 1.0, 5.0),
        (Vec3::new(1e-4, 1e-4, nan), 1.0, 5.0),
        (Vec3::new(1e-4, inf, 1e-4), 1.0, 5.0),
        (Vec3::new(1e-4, -1e-4, 1e-4), 1.0, 5.0),
        (torque, 0.0, 5.0),
        (torque, inf, 5.0),
        (torque, nan, 5.0),
        (torque, 1.0, -1.0),
        (torque, 1.0, inf),
        (torque, 1.0, nan),
    ] {
        assert_eq!(
            SlewTrajectory::new(&p, axes, &t, period, pause),
            Err(SlewError::InvalidLimits),
            "{t:?} {period} {pause}"
        );
    }
    let mut trajectory =
        SlewTrajectory::new(&plan_to(&q.to_dcm()), axes, &torque, 1.0, 5.0).unwrap();
    assert_eq!(trajectory.duration_s(), 0.0);
    assert_eq!(trajectory.at(0.0, 1.0), None);
}
