//! The acs flight firmware: reset → init → fixed-rate loop (read tiles, ACS step, command tiles).
//!
//! With feature `acs-loop` the loop is `acs::acs_loop::AcsLoop::step` over the mailbox tile bus
//! (`acs_firmware::flight`); it does not fit the MSP430FG439's flash yet (README), so the default
//! build keeps the stub [`acs_step`], which commands the safe state.
#![no_std]
#![no_main]

use acs_firmware::tiles;
#[cfg(not(feature = "acs-loop"))]
use acs_firmware::tiles::{TileCommands, TileSensors, TILES};

/// One control period: sensors in, actuator commands out.
///
/// When the ACS loop lands, this becomes `loop_state.step(&sensors, dt)` (its state lives in
/// `main`'s stack frame, created once before the loop).
#[cfg(not(feature = "acs-loop"))]
#[inline(never)]
fn acs_step(sensors: &[TileSensors; TILES]) -> [TileCommands; TILES] {
    let _ = sensors;
    [TileCommands::SAFE; TILES]
}

/// Entry point, called by the reset handler (`acs_firmware::rt`): the ACS loop at one step per
/// control period (the period timer is not modelled: steps run back to back).
///
/// SGP4 is initialised first, in its own frames: they are gone before [`run`] puts the loop's
/// state on the stack, so start-up and the steps do not add up (README "MSP430 firmware", RAM).
#[cfg(feature = "acs-loop")]
#[no_mangle]
pub extern "C" fn main() -> ! {
    tiles::command_safe();
    run(acs_firmware::flight::flight_orbit())
}

/// The loop over the flight configuration and `orbit`, used in place (its state lives in this
/// frame); the safe state and a halt if it cannot be built.
#[cfg(feature = "acs-loop")]
#[inline(never)]
fn run(orbit: Option<acs::orbit::sgp4::Sgp4>) -> ! {
    use acs_firmware::flight;
    let mut slot = None;
    if let Some(orbit) = orbit {
        flight::init_loop(&mut slot, orbit);
    }
    let Some(acs) = slot.as_mut() else {
        acs_firmware::safe_state();
        acs_firmware::fw_halt()
    };
    let mut bus = flight::MailboxBus;
    let mut tick: u32 = 0;
    loop {
        if let Some(now) = flight::tick_epoch(tick) {
            let _report = acs.step(&mut bus, now, 1.0);
        }
        tick = tick.wrapping_add(1);
    }
}

/// Entry point, called by the reset handler (`acs_firmware::rt`).
#[cfg(not(feature = "acs-loop"))]
#[no_mangle]
pub extern "C" fn main() -> ! {
    tiles::command_safe();
    loop {
        let sensors = tiles::read_sensors();
        let cmds = acs_step(&sensors);
        tiles::command(&cmds);
    }
}
