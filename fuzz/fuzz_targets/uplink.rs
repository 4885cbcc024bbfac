//! The ground uplink decoder ([`acs::uplink::apply`]) over the flight loop: a sequence of
//! arbitrary command codes and argument words (element words mostly a real set with fuzzed
//! changes), with a loop step on a quiet bus between commands. Never panics; a refused command
//! leaves the mode and the clock as they were; the status word is 0 exactly when accepted.
#![no_main]

#[path = "common.rs"]
mod common;

use acs::acs_loop::StepReport;
use acs::flight::{FlightLoop, CONFIG, CONTROL_PERIOD_S};
use acs::hal::{ErrorKind, TileBus};
use acs::time::{Epoch, TimeSpan, Utc};
use arbitrary::Unstructured;
use libfuzzer_sys::fuzz_target;

/// A bus whose tiles do not answer (the loop steps on its models and safe states).
struct Quiet;

impl TileBus for Quiet {
    fn read_sun(&mut self, _: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        Ok(None)
    }
    fn read_magnetometer(&mut self, _: usize) -> Result<[i16; 2], ErrorKind> {
        Err(ErrorKind::Timeout)
    }
    fn read_gyro(&mut self, _: usize) -> Result<i16, ErrorKind> {
        Ok(0)
    }
    fn set_wheel_momentum(&mut self, _: usize, h: f32) -> Result<(), ErrorKind> {
        assert!(h.is_finite());
        Ok(())
    }
    fn set_dipole(&mut self, _: usize, m: f32) -> Result<(), ErrorKind> {
        assert!(m.is_finite());
        Ok(())
    }
    fn delay_us(&mut self, _: u32) {}
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let mut acs = FlightLoop::new(&CONFIG, common::orbit()).expect("the flight loop builds");
    let mut clock = Epoch::<Utc>::from_parts(9_210, 43_200, 0).expect("a date");
    let period = TimeSpan::from_whole_seconds(CONTROL_PERIOD_S as i32);
    let mut report = StepReport::empty(acs.mode());
    for _ in 0..16 {
        let Ok((code, args)) = common::uplink_command(&mut u) else {
            break;
        };
        let (mode, before) = (acs.mode(), clock);
        let r = acs::uplink::apply(code, &args, &mut acs, &mut clock, report.attitude.as_ref());
        assert_eq!(acs::uplink::status(&r) == 0, r.is_ok());
        if let Err(e) = r {
            let _ = e.to_string();
            assert_eq!((acs.mode(), clock), (mode, before), "refused {code}: {e}");
        }
        if u.arbitrary::<bool>().unwrap_or(false) {
            acs.step_into(&mut Quiet, clock, CONTROL_PERIOD_S, &mut report);
            common::check_report(&report);
            clock = clock.add(period);
        }
    }
});
