//! The flight loop ([`acs::flight::CONFIG`] through [`acs::acs_loop::AcsLoop`]) over a fuzzed
//! tile bus: every reading an arbitrary raw value, an error or `None` (no Sun), every command
//! accepted or refused, for up to 64 steps, with arbitrary ground commands
//! ([`acs::uplink::apply`]) between steps. Asserts: no panic; every wheel and coil command
//! finite, within its limit and addressed to a device that exists; every report field finite.
#![no_main]

#[path = "common.rs"]
mod common;

use acs::acs_loop::StepReport;
use acs::flight::{FlightLoop, COIL_LIMIT_AM2, CONFIG, CONTROL_PERIOD_S, TILES, WHEEL_LIMIT_NMS};
use acs::hal::{ErrorKind, TileBus};
use acs::time::{Epoch, TimeSpan, Utc};
use arbitrary::Unstructured;
use libfuzzer_sys::fuzz_target;

/// The largest number of steps of one input.
const MAX_STEPS: usize = 64;

/// A command within its limit, exactly: the allocation scales a saturated command by one ulp
/// less than the rounded `limit / max`, so no rounding takes it past the limit (a driver refuses
/// anything above it).
fn within(x: f32, limit: f32) -> bool {
    x.is_finite() && x.abs() <= limit
}

struct FuzzBus<'a> {
    u: Unstructured<'a>,
}

impl FuzzBus<'_> {
    /// `Ok(())` or an error, as the input says (empty input: `Ok`).
    fn outcome(&mut self) -> Result<(), ErrorKind> {
        match self.u.int_in_range(0u8..=15).unwrap_or(0) {
            11 => Err(ErrorKind::DeviceAbsent),
            12 => Err(ErrorKind::Timeout),
            13 => Err(ErrorKind::OutOfRange),
            14 => Err(ErrorKind::Bus),
            15 => Err(ErrorKind::Other),
            _ => Ok(()),
        }
    }

    fn raw(&mut self) -> i16 {
        self.u.arbitrary().unwrap_or(0)
    }
}

impl TileBus for FuzzBus<'_> {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        assert!(tile < TILES);
        self.outcome()?;
        if self.u.arbitrary::<bool>().unwrap_or(false) {
            Ok(None)
        } else {
            Ok(Some([self.raw(), self.raw()]))
        }
    }

    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        assert!(tile < TILES);
        self.outcome()?;
        Ok([self.raw(), self.raw()])
    }

    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        assert!(tile < TILES);
        self.outcome()?;
        Ok(self.raw())
    }

    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        assert!(
            tile < TILES && CONFIG.tiles[tile].equipment.reaction_wheel,
            "no wheel on tile {tile}"
        );
        assert!(
            within(h_nms, WHEEL_LIMIT_NMS),
            "wheel {tile}: {h_nms} N·m·s"
        );
        self.outcome()
    }

    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        assert!(coil < CONFIG.coils.len(), "no coil {coil}");
        assert!(within(m_am2, COIL_LIMIT_AM2), "coil {coil}: {m_am2} A·m²");
        self.outcome()
    }

    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        assert!(
            tile < TILES && CONFIG.tiles[tile].equipment.reaction_wheel,
            "no wheel on tile {tile}"
        );
        self.outcome()?;
        Ok(self.u.arbitrary::<bool>().unwrap_or(false).then(|| self.raw()))
    }

    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        assert!(coil < CONFIG.coils.len(), "no coil {coil}");
        self.outcome()?;
        Ok(self.u.arbitrary::<bool>().unwrap_or(false).then(|| self.raw()))
    }
    fn delay_us(&mut self, _: u32) {}
}

fuzz_target!(|data: &[u8]| {
    let mut acs = FlightLoop::new(&CONFIG, common::orbit()).expect("the flight loop builds");
    let mut clock = Epoch::<Utc>::from_parts(9_210, 43_200, 0).expect("2025-03-20 is a date");
    let period = TimeSpan::from_whole_seconds(CONTROL_PERIOD_S as i32);
    let mut bus = FuzzBus {
        u: Unstructured::new(data),
    };
    let mut report = StepReport::empty(acs.mode());
    for _ in 0..MAX_STEPS {
        if bus.u.is_empty() {
            break;
        }
        if bus.u.ratio(1u8, 6).unwrap_or(false) {
            if let Ok((code, args)) = common::uplink_command(&mut bus.u) {
                let _ =
                    acs::uplink::apply(code, &args, &mut acs, &mut clock, report.attitude.as_ref());
            }
        }
        acs.step_into(&mut bus, clock, CONTROL_PERIOD_S, &mut report);
        common::check_report(&report);
        clock = clock.add(period);
    }
});
