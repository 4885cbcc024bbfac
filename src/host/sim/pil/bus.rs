//! The flight image's tile mailboxes on the host: the raw readings of one step as the image's
//! `TILE_*` mailboxes hold them, and the [`Recorder`] that captures them from the simulator
//! while the host loop steps.
//!
//! The mailboxes (`firmware/src/tiles.rs`) hold exactly what [`TileBus`] returns and takes:
//!
//! | symbol | host field | bytes (little-endian) |
//! |---|---|---|
//! | `TILE_SUN` | [`Readings::sun`] | `[[i16; 2]; 6]`, 24 |
//! | `TILE_SUN_SEEN` | [`Readings::sun_seen`] (bit `i`: tile `i` sees the Sun) | `u16`, 2 |
//! | `TILE_MAG` | [`Readings::mag`] | `[[i16; 2]; 6]`, 24 |
//! | `TILE_GYRO` | [`Readings::gyro`] | `[i16; 6]`, 12 |
//! | `TILE_READ_ERRORS` | [`Readings::read_errors`] (bits `i`, `8 + i`, `16 + i`: sun, magnetometer, gyro of tile `i` fail) | `u32`, 4 |
//! | `ACTUATOR_REFUSE` | [`Readings::refuse`] (bits `i`, `8 + c`: wheel `i`, coil `c` refuse) | `u16`, 2 |
//! | `TILE_WHEEL` | [`Readings::wheel`] (the wheels' momentum read-back, 1e-7 kg·m²/s) | `[i16; 6]`, 12 |
//! | `COIL_READ` | [`Readings::coil`] (the coils' dipole read-back, 1e-5 A·m²) | `[i16; 3]`, 6 |
//! | `READBACK_ERRORS` | [`Readings::readback_errors`] (bits `i`, `8 + c`: the read-back of wheel `i`, coil `c` fails) | `u16`, 2 |
//! | `ERROR_KINDS` | [`Readings::error_kinds`] (the kind of each failure, [`ErrorKind::code`]: entry `b` for read bit `b`, `24 + b` for read-back bit `b`; 0, a bus error, where nothing failed or nothing was read) | `[u8; 40]`, 40 |
//! | `CMD_WHEEL_NMS` | [`Commands::wheel_nms`] | `[f32; 6]`, 24 |
//! | `CMD_DIPOLE_AM2` | [`Commands::dipole_am2`] | `[f32; 3]`, 12 |
//!
//! The image's bus (`MailboxBus`, `firmware/src/tiles.rs`) answers a read from these words and
//! refuses an actuator's commands for the whole step when its refuse bit is set (the command
//! mailbox then keeps its value). The [`Recorder`] gives the host loop the same semantics: it
//! passes every call to the simulator, records what it answered into the mailboxes, and keeps
//! the host's own command mailboxes, written only when a command is accepted.

use crate::flight::TILES;
use crate::hal::{ErrorKind, TileBus};

/// The number of magnetorquer coils of the flight image's command mailbox.
pub const COILS: usize = 3;

/// Entries of the `ERROR_KINDS` mailbox: 24 read bits, then 16 read-back bits.
pub const ERROR_KINDS_LEN: usize = 40;

/// The raw tile readings of one step, as the image's mailboxes hold them (see the
/// [module docs](self)).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Readings {
    /// Sun-sensor angles `(a, b)`, 1e-4 rad (0 where not seen).
    pub sun: [[i16; 2]; TILES],
    /// Bit `i`: tile `i`'s sun sensor sees the Sun.
    pub sun_seen: u16,
    /// Magnetometer, tile x and y, 10 nT.
    pub mag: [[i16; 2]; TILES],
    /// Gyro rate about tile z, 1e-4 rad/s.
    pub gyro: [i16; TILES],
    /// Devices that did not answer: bits `i`, `8 + i`, `16 + i` for the sun sensor,
    /// magnetometer and gyro of tile `i`.
    pub read_errors: u32,
    /// Actuators that refused: bits `i` (wheel of tile `i`) and `8 + c` (coil `c`).
    pub refuse: u16,
    /// The wheels' momentum read-back, 1e-7 kg·m²/s (0 where not read).
    pub wheel: [i16; TILES],
    /// The coils' dipole read-back, 1e-5 A·m² (0 where not read).
    pub coil: [i16; COILS],
    /// Read-backs that failed (or were not read): bits `i` (wheel of tile `i`) and `8 + c`
    /// (coil `c`).
    pub readback_errors: u16,
    /// The kind of each failure ([`ErrorKind::code`]): entry `b` for bit `b` of
    /// `read_errors`, `24 + b` for bit `b` of `readback_errors`; 0 (the image reads a bus
    /// error) where nothing failed or nothing was read.
    pub error_kinds: [u8; ERROR_KINDS_LEN],
}

impl Default for Readings {
    /// Nothing read yet: every device of every tile in error, nothing seen, nothing refused (a
    /// device the host loop did not read answers the image with an error, so a read on one
    /// side only shows as a fault difference).
    fn default() -> Self {
        let tiles = (1u32 << TILES) - 1;
        Self {
            sun: [[0; 2]; TILES],
            sun_seen: 0,
            mag: [[0; 2]; TILES],
            gyro: [0; TILES],
            read_errors: tiles | tiles << 8 | tiles << 16,
            refuse: 0,
            wheel: [0; TILES],
            coil: [0; COILS],
            readback_errors: ((1u16 << COILS) - 1) << 8 | tiles as u16,
            error_kinds: [0; ERROR_KINDS_LEN],
        }
    }
}

fn i16_bytes(values: impl IntoIterator<Item = i16>) -> Vec<u8> {
    values.into_iter().flat_map(i16::to_le_bytes).collect()
}

impl Readings {
    /// The mailbox contents: (symbol, little-endian bytes), in the order of the
    /// [module docs](self).
    pub fn mailboxes(&self) -> [(&'static str, Vec<u8>); 10] {
        [
            ("TILE_SUN", i16_bytes(self.sun.iter().flatten().copied())),
            ("TILE_SUN_SEEN", self.sun_seen.to_le_bytes().to_vec()),
            ("TILE_MAG", i16_bytes(self.mag.iter().flatten().copied())),
            ("TILE_GYRO", i16_bytes(self.gyro.iter().copied())),
            ("TILE_READ_ERRORS", self.read_errors.to_le_bytes().to_vec()),
            ("ACTUATOR_REFUSE", self.refuse.to_le_bytes().to_vec()),
            ("TILE_WHEEL", i16_bytes(self.wheel.iter().copied())),
            ("COIL_READ", i16_bytes(self.coil.iter().copied())),
            (
                "READBACK_ERRORS",
                self.readback_errors.to_le_bytes().to_vec(),
            ),
            ("ERROR_KINDS", self.error_kinds.to_vec()),
        ]
    }
}

/// The actuator command mailboxes: what the loop last commanded and the actuator accepted.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Commands {
    /// Wheel momentum commands, kg·m²/s along tile z.
    pub wheel_nms: [f32; TILES],
    /// Coil dipole commands, A·m².
    pub dipole_am2: [f32; COILS],
}

impl Commands {
    /// The commands from the little-endian bytes of `CMD_WHEEL_NMS` and `CMD_DIPOLE_AM2`
    /// (`None` if a length is wrong).
    pub fn from_le_bytes(wheel: &[u8], dipole: &[u8]) -> Option<Self> {
        fn floats<const N: usize>(bytes: &[u8]) -> Option<[f32; N]> {
            if bytes.len() != 4 * N {
                return None;
            }
            let mut out = [0.0; N];
            for (x, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
                *x = f32::from_le_bytes(b.try_into().ok()?);
            }
            Some(out)
        }
        Some(Self {
            wheel_nms: floats(wheel)?,
            dipole_am2: floats(dipole)?,
        })
    }
}

/// Why the readings of a step cannot be put in the mailboxes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RecordError {
    /// A device was read twice in one step (the mailbox holds one value).
    ReadTwice {
        /// `"sun sensor"`, `"magnetometer"`, `"gyro"`, `"wheel read-back"` or `"coil read-back"`.
        device: &'static str,
        /// Tile index.
        tile: usize,
    },
    /// An actuator accepted one command and refused another in the same step (the image's
    /// refuse bit holds for the whole step).
    MixedRefusal {
        /// `"wheel"` or `"coil"`.
        actuator: &'static str,
        /// Tile or coil index.
        index: usize,
    },
}

impl std::fmt::Display for RecordError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::ReadTwice { device, tile } => write!(
                f,
                "the {device} of tile {tile} was read twice in one step: a mailbox holds one reading"
            ),
            Self::MixedRefusal { actuator, index } => write!(
                f,
                "{actuator} {index} accepted one command and refused another in the same step: \
                 the image's refuse bit holds for the whole step"
            ),
        }
    }
}

/// A [`TileBus`] over another (the simulator) that records one step's readings into the
/// mailbox format and keeps the host's command mailboxes.
pub struct Recorder<'a, B: TileBus> {
    bus: &'a mut B,
    commands: &'a mut Commands,
    readings: Readings,
    /// Devices read this step (the bit layout of [`Readings::read_errors`]).
    read: u32,
    /// Read-backs made this step (the bit layout of [`Readings::readback_errors`]).
    read_back: u16,
    accepted: u16,
    refused: u16,
    error: Option<RecordError>,
}

/// Bit `i` as a `u32` (0 beyond 31).
fn bit(i: usize) -> u32 {
    u32::try_from(i)
        .ok()
        .and_then(|i| 1u32.checked_shl(i))
        .unwrap_or(0)
}

impl<'a, B: TileBus> Recorder<'a, B> {
    /// A recorder for one step over `bus`, writing accepted commands into `commands` (kept
    /// from step to step, as the image's mailboxes are).
    pub fn new(bus: &'a mut B, commands: &'a mut Commands) -> Self {
        Self {
            bus,
            commands,
            readings: Readings::default(),
            read: 0,
            read_back: 0,
            accepted: 0,
            refused: 0,
            error: None,
        }
    }

    /// The step's readings, with the refuse bits of the actuators that refused.
    pub fn finish(self) -> Result<Readings, RecordError> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let mixed = self.accepted & self.refused;
        if mixed != 0 {
            let first = mixed.trailing_zeros() as usize;
            return Err(if first < 8 {
                RecordError::MixedRefusal {
                    actuator: "wheel",
                    index: first,
                }
            } else {
                RecordError::MixedRefusal {
                    actuator: "coil",
                    index: first - 8,
                }
            });
        }
        Ok(Readings {
            refuse: self.refused,
            ..self.readings
        })
    }

    /// Marks device bit `b` read; false (and an error kept) if it was already.
    fn first_read(&mut self, b: u32, device: &'static str, tile: usize) -> bool {
        if self.read & b != 0 {
            self.error
                .get_or_insert(RecordError::ReadTwice { device, tile });
            return false;
        }
        self.read |= b;
        true
    }

    /// Records the kind of a failure in entry `i` of [`Readings::error_kinds`].
    fn kind(&mut self, i: usize, e: ErrorKind) {
        if let Some(k) = self.readings.error_kinds.get_mut(i) {
            *k = e.code();
        }
    }

    /// Records the outcome of a command to actuator bit `b`.
    fn outcome(&mut self, b: u32, ok: bool) {
        let b = b as u16;
        if ok {
            self.accepted |= b;
        } else {
            self.refused |= b;
        }
    }
}

impl<B: TileBus> TileBus for Recorder<'_, B> {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        if tile >= TILES {
            return Err(ErrorKind::DeviceAbsent);
        }
        let r = self.bus.read_sun(tile);
        if self.first_read(bit(tile), "sun sensor", tile) {
            match r {
                Ok(seen) => {
                    self.readings.read_errors &= !bit(tile);
                    if let Some(angles) = seen {
                        self.readings.sun[tile] = angles;
                        self.readings.sun_seen |= bit(tile) as u16;
                    }
                }
                Err(e) => self.kind(tile, e),
            }
        }
        r
    }

    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        if tile >= TILES {
            return Err(ErrorKind::DeviceAbsent);
        }
        let r = self.bus.read_magnetometer(tile);
        if self.first_read(bit(8 + tile), "magnetometer", tile) {
            match r {
                Ok(xy) => {
                    self.readings.read_errors &= !bit(8 + tile);
                    self.readings.mag[tile] = xy;
                }
                Err(e) => self.kind(8 + tile, e),
            }
        }
        r
    }

    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        if tile >= TILES {
            return Err(ErrorKind::DeviceAbsent);
        }
        let r = self.bus.read_gyro(tile);
        if self.first_read(bit(16 + tile), "gyro", tile) {
            match r {
                Ok(w) => {
                    self.readings.read_errors &= !bit(16 + tile);
                    self.readings.gyro[tile] = w;
                }
                Err(e) => self.kind(16 + tile, e),
            }
        }
        r
    }

    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        if tile >= TILES {
            return Err(ErrorKind::DeviceAbsent);
        }
        let r = self.bus.set_wheel_momentum(tile, h_nms);
        self.outcome(bit(tile), r.is_ok());
        if r.is_ok() {
            self.commands.wheel_nms[tile] = h_nms;
        }
        r
    }

    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        if coil >= COILS {
            return Err(ErrorKind::DeviceAbsent);
        }
        let r = self.bus.set_dipole(coil, m_am2);
        self.outcome(bit(8 + coil), r.is_ok());
        if r.is_ok() {
            self.commands.dipole_am2[coil] = m_am2;
        }
        r
    }

    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        if tile >= TILES {
            return Err(ErrorKind::DeviceAbsent);
        }
        let r = self.bus.read_wheel_momentum(tile);
        if let Ok(Some(w)) = self.first_read_back(tile, "wheel read-back", r) {
            self.readings.wheel[tile] = w;
        }
        r
    }

    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        if coil >= COILS {
            return Err(ErrorKind::DeviceAbsent);
        }
        let r = self.bus.read_coil_dipole(coil);
        if let Ok(Some(m)) = self.first_read_back(8 + coil, "coil read-back", r) {
            self.readings.coil[coil] = m;
        }
        r
    }

    fn delay_us(&mut self, us: u32) {
        self.bus.delay_us(us);
    }
}

impl<B: TileBus> Recorder<'_, B> {
    /// Marks read-back bit `b` read and, if the bus gave a word, clears its error bit; the
    /// result to record (`Err` if it was read before: an error kept). A bus without the
    /// read-back (`Ok(None)`) leaves the error bit: the image's bus always has one.
    fn first_read_back(
        &mut self,
        b: usize,
        device: &'static str,
        r: Result<Option<i16>, ErrorKind>,
    ) -> Result<Option<i16>, ErrorKind> {
        let mask = bit(b) as u16;
        if self.read_back & mask != 0 {
            self.error.get_or_insert(RecordError::ReadTwice {
                device,
                tile: b % 8,
            });
            return Err(ErrorKind::Other);
        }
        self.read_back |= mask;
        match r {
            Ok(Some(_)) => self.readings.readback_errors &= !mask,
            Err(e) => self.kind(24 + b, e),
            Ok(None) => {}
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bus whose answers are set per device: tile 0 sees the Sun, tile 1 does not, tile 2's
    /// devices fail; wheel 3 refuses, coil 1 refuses values above 0.1.
    struct Fake;

    impl TileBus for Fake {
        fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
            match tile {
                0 => Ok(Some([123, -4567])),
                2 => Err(ErrorKind::Timeout),
                _ => Ok(None),
            }
        }
        fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
            if tile == 2 {
                return Err(ErrorKind::Bus);
            }
            Ok([tile as i16 * 100 - 250, -(tile as i16)])
        }
        fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
            if tile == 2 {
                return Err(ErrorKind::OutOfRange);
            }
            Ok(-7 * tile as i16)
        }
        fn set_wheel_momentum(&mut self, tile: usize, _h: f32) -> Result<(), ErrorKind> {
            if tile == 3 {
                Err(ErrorKind::DeviceAbsent)
            } else {
                Ok(())
            }
        }
        fn set_dipole(&mut self, coil: usize, m: f32) -> Result<(), ErrorKind> {
            if coil == 1 && m > 0.1 {
                Err(ErrorKind::OutOfRange)
            } else {
                Ok(())
            }
        }
        fn delay_us(&mut self, _: u32) {}
    }

    #[test]
    fn records_readings_errors_and_refusals_in_the_mailbox_format() {
        let mut fake = Fake;
        let mut commands = Commands::default();
        let mut rec = Recorder::new(&mut fake, &mut commands);
        for tile in 0..3 {
            let _ = rec.read_sun(tile);
            let _ = rec.read_magnetometer(tile);
            let _ = rec.read_gyro(tile);
        }
        // tiles 3..5 are not read: their devices stay in error
        assert_eq!(rec.set_wheel_momentum(0, 2.5e-4), Ok(()));
        assert!(rec.set_wheel_momentum(3, 1e-4).is_err());
        assert_eq!(rec.set_dipole(2, -0.15), Ok(()));
        assert_eq!(rec.read_sun(6), Err(ErrorKind::DeviceAbsent));
        let r = rec.finish().unwrap();
        assert_eq!(r.sun[0], [123, -4567]);
        assert_eq!(r.sun[1], [0, 0]);
        assert_eq!(r.sun_seen, 0b1);
        assert_eq!(r.mag[0], [-250, 0]);
        assert_eq!(r.mag[1], [-150, -1]);
        assert_eq!(r.gyro[1], -7);
        // read errors: tile 2 (all three devices) and tiles 3..5 (not read)
        let not_ok = 0b11_1100u32;
        assert_eq!(r.read_errors, not_ok | not_ok << 8 | not_ok << 16);
        assert_eq!(r.refuse, 1 << 3);
        assert_eq!(commands.wheel_nms, [2.5e-4, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert_eq!(commands.dipole_am2, [0.0, 0.0, -0.15]);

        let boxes = r.mailboxes();
        let bytes = |name: &str| boxes.iter().find(|(n, _)| *n == name).unwrap().1.clone();
        assert_eq!(&bytes("TILE_SUN")[..4], &[123, 0, 0x29, 0xee]);
        assert_eq!(bytes("TILE_SUN").len(), 24);
        assert_eq!(bytes("TILE_MAG").len(), 24);
        assert_eq!(bytes("TILE_GYRO"), i16_bytes([0, -7, 0, 0, 0, 0]));
        assert_eq!(bytes("TILE_SUN_SEEN"), vec![1, 0]);
        assert_eq!(bytes("TILE_READ_ERRORS"), vec![0x3c, 0x3c, 0x3c, 0]);
        assert_eq!(bytes("ACTUATOR_REFUSE"), vec![8, 0]);
        // tile 2's failures with their kinds (timeout, bus, out of range); the devices not
        // read, 0
        let mut kinds = vec![0u8; ERROR_KINDS_LEN];
        kinds[2] = ErrorKind::Timeout.code();
        kinds[8 + 2] = ErrorKind::Bus.code();
        kinds[16 + 2] = ErrorKind::OutOfRange.code();
        assert_eq!(bytes("ERROR_KINDS"), kinds);
    }

    #[test]
    fn a_step_the_mailboxes_cannot_hold_is_an_error() {
        let mut fake = Fake;
        let mut commands = Commands::default();
        let mut rec = Recorder::new(&mut fake, &mut commands);
        let _ = rec.read_gyro(4);
        let _ = rec.read_gyro(4);
        assert_eq!(
            rec.finish(),
            Err(RecordError::ReadTwice {
                device: "gyro",
                tile: 4
            })
        );
        let mut rec = Recorder::new(&mut fake, &mut commands);
        assert_eq!(rec.set_dipole(1, 0.0), Ok(()));
        assert!(rec.set_dipole(1, 0.2).is_err());
        assert_eq!(
            rec.finish(),
            Err(RecordError::MixedRefusal {
                actuator: "coil",
                index: 1
            })
        );
        // the refused command leaves the mailbox as it was
        assert_eq!(commands.dipole_am2[1], 0.0);
    }

    #[test]
    fn commands_read_back_from_mailbox_bytes() {
        let wheel: Vec<u8> = [1.0f32, -2.0, 0.5, 0.0, -0.0, 3e-4]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let dipole: Vec<u8> = [0.2f32, -0.2, 1e-3]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let c = Commands::from_le_bytes(&wheel, &dipole).unwrap();
        assert_eq!(c.wheel_nms[5].to_bits(), 3e-4f32.to_bits());
        assert_eq!(c.wheel_nms[4].to_bits(), (-0.0f32).to_bits());
        assert_eq!(c.dipole_am2, [0.2, -0.2, 1e-3]);
        assert_eq!(Commands::from_le_bytes(&wheel[..20], &dipole), None);
    }
}
