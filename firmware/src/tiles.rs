//! Tile drivers, stubbed for the simulator.
//!
//! On the satellite each power tile carries a sun sensor, a two-axis magnetometer, a one-axis
//! gyro, a reaction wheel and a magnetorquer, reached over the tile bus. Here the drivers read
//! the sensors from a RAM mailbox ([`SENSORS`]) that the simulator or a debugger writes, and write
//! the actuator commands to another ([`ACTUATORS`]) that it reads: the firmware around them is the
//! flight one, only the bus transactions are missing.

/// Number of tiles (the six faces of the AraMiS cube).
pub const TILES: usize = 6;

/// Raw sensor readings of one tile, as the tile bus delivers them (engineering units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct TileSensors {
    /// Sun sensor, normalised current (0..1, 0 in shadow).
    pub sun: f32,
    /// Magnetometer, two in-plane axes, nT.
    pub mag_nt: [f32; 2],
    /// Gyro, rate about the tile normal, rad/s.
    pub gyro_radps: f32,
}

/// Actuator commands of one tile.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct TileCommands {
    /// Reaction-wheel momentum command, kg·m²/s (0: stop).
    pub wheel_momentum_nms: f32,
    /// Magnetorquer dipole, A·m² (0: off).
    pub dipole_am2: f32,
}

impl TileCommands {
    /// The safe state: wheel commanded to zero momentum, magnetorquer off.
    pub const SAFE: TileCommands = TileCommands {
        wheel_momentum_nms: 0.0,
        dipole_am2: 0.0,
    };
}

/// Sensor mailbox (written by the simulator).
#[no_mangle]
pub static mut SENSORS: [TileSensors; TILES] = [TileSensors {
    sun: 0.0,
    mag_nt: [0.0; 2],
    gyro_radps: 0.0,
}; TILES];

/// Actuator mailbox (read by the simulator).
#[no_mangle]
pub static mut ACTUATORS: [TileCommands; TILES] = [TileCommands::SAFE; TILES];

/// Reads every tile's sensors.
pub fn read_sensors() -> [TileSensors; TILES] {
    // SAFETY: single-threaded firmware, no interrupt touches the mailbox; volatile so that the
    // compiler does not assume the simulator-written memory constant.
    unsafe { core::ptr::read_volatile(&raw const SENSORS) }
}

/// Sends the actuator commands to every tile.
pub fn command(cmds: &[TileCommands; TILES]) {
    // SAFETY: as in `read_sensors`.
    unsafe { core::ptr::write_volatile(&raw mut ACTUATORS, *cmds) }
}

/// Commands one tile's wheel momentum and/or dipole (`None`: unchanged); `None` if there is no
/// such tile.
pub fn command_one(tile: usize, wheel: Option<f32>, dipole: Option<f32>) -> Option<()> {
    // SAFETY: as in `read_sensors`.
    let mut all = unsafe { core::ptr::read_volatile(&raw const ACTUATORS) };
    let t = all.get_mut(tile)?;
    if let Some(h) = wheel {
        t.wheel_momentum_nms = h;
    }
    if let Some(m) = dipole {
        t.dipole_am2 = m;
    }
    command(&all);
    Some(())
}

/// Commands every actuator to its safe state ([`TileCommands::SAFE`]); used by
/// [`crate::safe_state`].
pub fn command_safe() {
    command(&[TileCommands::SAFE; TILES]);
}
