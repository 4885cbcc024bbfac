//! The acs flight firmware: reset → init → fixed-rate loop (read tiles, ACS step, command tiles).
//!
//! The ACS loop (`acs` issue #8) does not exist yet: [`acs_step`] is the single place where its
//! `step` will be called; until then it commands the safe state.
#![no_std]
#![no_main]

use acs_firmware::tiles::{self, TileCommands, TileSensors, TILES};

/// One control period: sensors in, actuator commands out.
///
/// When the ACS loop lands, this becomes `loop_state.step(&sensors, dt)` (its state lives in
/// `main`'s stack frame, created once before the loop).
#[inline(never)]
fn acs_step(sensors: &[TileSensors; TILES]) -> [TileCommands; TILES] {
    let _ = sensors;
    [TileCommands::SAFE; TILES]
}

/// Entry point, called by the reset handler (`acs_firmware::rt`).
#[no_mangle]
pub extern "C" fn main() -> ! {
    tiles::command_safe();
    loop {
        let sensors = tiles::read_sensors();
        let cmds = acs_step(&sensors);
        tiles::command(&cmds);
    }
}
