//! Fault injection (issue 19 item 4): faults the simulated tiles suffer from a given time, for a
//! given duration or until cleared, flown by the unchanged flight loop through the same
//! [`crate::hal::TileBus`] calls. `tests/faults.rs` flies one case per fault and
//! `docs/faults.md` tabulates what the loop reports and how it recovers.
//!
//! | fault | what the bus does while it is active |
//! |---|---|
//! | [`Fault::NanReading`] | the sensor's reading is NaN where the float enters (the device model's value, before the driver's `i16` word): the word cannot be formed, the read fails with [`ErrorKind::OutOfRange`] |
//! | [`Fault::OutOfRange`] | the raw word is pinned at the `i16` extremes (`i16::MAX`, and `i16::MIN` for a second component), delivered as a valid reading (a driver that does not check saturation) |
//! | [`Fault::Stuck`] | the sensor repeats the first reading it gave after the fault began (a constant value) |
//! | [`Fault::DeadTile`] | the tile does not answer: every read and every wheel command fails with [`ErrorKind::DeviceAbsent`]; its wheel keeps the last set-point it accepted |
//! | [`Fault::BusErrors`] | every transaction on the bus (reads, wheel and coil commands) fails with [`ErrorKind::Bus`]; the actuators keep the last command they accepted |
//! | [`Fault::WheelStopped`] | the wheel accepts commands (`Ok`) but its drive brings it to rest: its speed loop's set-point is zero whatever is commanded |
//! | [`Fault::WheelRefuses`] | the wheel's commands fail with [`ErrorKind::Other`]; it keeps the last set-point it accepted |
//! | [`Fault::CoilOpen`] | the coil accepts commands (`Ok`) and gives no dipole (open circuit) |
//! | [`Fault::CoilLeftOn`] | the coil stays at a fixed dipole whatever is commanded (also through the loop's coils-off before the reads): its field reaches the magnetometers (realistic truth) and its torque the body |
//! | [`Fault::SunSensorsDark`] | every Sun sensor answers "no Sun" (`Ok(None)`) |
//!
//! Ground-side faults (a corrupt element set, a jump of the on-board clock, a tile marked
//! failed and restored) are not the truth's: the tests apply them to the loop through
//! [`crate::uplink::apply`] and the clock they pass it.
//!
//! An injection is active while `from_s ≤ t < until_s`, `t` the simulator's time (s from the
//! start) at the call (both ends [`TIME_TOLERANCE_S`] early). The faults draw no random number: a run with an injection that never
//! becomes active is bit for bit the run without it.

use super::ErrorKind;

/// How early an injection's ends take effect, s (far below a control period).
pub const TIME_TOLERANCE_S: f64 = 1e-6;

/// A tile's sensor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sensor {
    /// The Sun sensor.
    Sun,
    /// The magnetometer.
    Magnetometer,
    /// The gyro.
    Gyro,
}

/// A fault of the simulated tiles (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fault {
    /// The sensor's reading is NaN before it becomes a word: the read fails (out of range).
    NanReading {
        /// Tile index.
        tile: usize,
        /// Which sensor.
        sensor: Sensor,
    },
    /// The sensor's raw word is pinned at the `i16` extremes, delivered as a valid reading.
    OutOfRange {
        /// Tile index.
        tile: usize,
        /// Which sensor.
        sensor: Sensor,
    },
    /// The sensor repeats the first reading it gave after the fault began.
    Stuck {
        /// Tile index.
        tile: usize,
        /// Which sensor.
        sensor: Sensor,
    },
    /// The tile does not answer: reads and wheel commands fail.
    DeadTile {
        /// Tile index.
        tile: usize,
    },
    /// Every bus transaction fails.
    BusErrors,
    /// The wheel accepts commands and comes to rest.
    WheelStopped {
        /// Tile index.
        tile: usize,
    },
    /// The wheel refuses its commands.
    WheelRefuses {
        /// Tile index.
        tile: usize,
    },
    /// The coil accepts commands and gives no dipole.
    CoilOpen {
        /// Coil index.
        coil: usize,
    },
    /// The coil stays at `dipole_am2` whatever is commanded.
    CoilLeftOn {
        /// Coil index.
        coil: usize,
        /// The dipole it stays at, A·m².
        dipole_am2: f64,
    },
    /// Every Sun sensor answers "no Sun".
    SunSensorsDark,
}

/// A reading held by a [`Fault::Stuck`] sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Held {
    /// A Sun sensor's answer.
    Sun(Option<[i16; 2]>),
    /// A magnetometer's words.
    Magnetometer([i16; 2]),
    /// A gyro's word.
    Gyro(i16),
}

/// A fault and when it is active.
#[derive(Clone, Debug, PartialEq)]
pub struct Injection {
    /// The fault.
    pub fault: Fault,
    /// Start, s from the simulator's start.
    pub from_s: f64,
    /// End (exclusive), s; `f64::INFINITY`: until cleared.
    pub until_s: f64,
    /// What a stuck sensor repeats (set at its first read while active).
    pub held: Option<Held>,
}

impl Injection {
    /// True while active at `t_s` (both ends [`TIME_TOLERANCE_S`] early: the simulator's clock
    /// is a sum of substeps, 1 s after the start may read 0.999 999 999 s).
    pub fn active(&self, t_s: f64) -> bool {
        t_s >= self.from_s - TIME_TOLERANCE_S && t_s < self.until_s - TIME_TOLERANCE_S
    }
}

/// The injections of one simulator.
#[derive(Clone, Debug, Default)]
pub struct Injections {
    list: Vec<Injection>,
}

impl Injections {
    /// Adds an injection; returns its index (for [`Injections::clear`]).
    pub fn add(&mut self, fault: Fault, from_s: f64, until_s: f64) -> usize {
        self.list.push(Injection {
            fault,
            from_s,
            until_s,
            held: None,
        });
        self.list.len() - 1
    }

    /// Ends injection `index` at `t_s` (if it was to last longer).
    pub fn clear(&mut self, index: usize, t_s: f64) {
        if let Some(i) = self.list.get_mut(index) {
            i.until_s = i.until_s.min(t_s);
        }
    }

    /// Every injection.
    pub fn list(&self) -> &[Injection] {
        &self.list
    }

    /// True if a fault matching `f` is active at `t_s`.
    pub fn any(&self, t_s: f64, f: impl Fn(&Fault) -> bool) -> bool {
        self.list.iter().any(|i| i.active(t_s) && f(&i.fault))
    }

    /// The error every transaction with tile `tile` fails with at `t_s`, if any (a bus burst,
    /// a dead tile).
    pub fn tile_error(&self, t_s: f64, tile: usize) -> Option<ErrorKind> {
        if self.any(t_s, |f| matches!(f, Fault::BusErrors)) {
            return Some(ErrorKind::Bus);
        }
        self.any(
            t_s,
            |f| matches!(f, Fault::DeadTile { tile: t } if *t == tile),
        )
        .then_some(ErrorKind::DeviceAbsent)
    }

    /// True if `sensor` of `tile` reads NaN at `t_s`.
    pub fn nan(&self, t_s: f64, tile: usize, sensor: Sensor) -> bool {
        self.any(
            t_s,
            |f| matches!(f, Fault::NanReading { tile: t, sensor: s } if *t == tile && *s == sensor),
        )
    }

    /// `value`, or NaN if `sensor` of `tile` reads NaN at `t_s`.
    pub fn poison(&self, t_s: f64, tile: usize, sensor: Sensor, value: f64) -> f64 {
        if self.nan(t_s, tile, sensor) {
            f64::NAN
        } else {
            value
        }
    }

    /// The reading `sensor` of `tile` delivers at `t_s` instead of `reading` (a stuck or
    /// out-of-range sensor), if any; a stuck sensor remembers its first reading.
    pub fn replace(&mut self, t_s: f64, tile: usize, sensor: Sensor, reading: Held) -> Held {
        let mut out = reading;
        for i in self.list.iter_mut().filter(|i| i.active(t_s)) {
            match i.fault {
                Fault::Stuck { tile: t, sensor: s } if t == tile && s == sensor => {
                    out = *i.held.get_or_insert(out);
                }
                Fault::OutOfRange { tile: t, sensor: s } if t == tile && s == sensor => {
                    out = match sensor {
                        Sensor::Sun => Held::Sun(Some([i16::MAX, i16::MIN])),
                        Sensor::Magnetometer => Held::Magnetometer([i16::MAX, i16::MIN]),
                        Sensor::Gyro => Held::Gyro(i16::MAX),
                    };
                }
                _ => {}
            }
        }
        out
    }

    /// The wheel command of `tile` at `t_s`: `Err` if refused, else the set-point it becomes
    /// (zero for a stopped wheel).
    pub fn wheel(&self, t_s: f64, tile: usize, h_nms: f64) -> Result<f64, ErrorKind> {
        if let Some(e) = self.tile_error(t_s, tile) {
            return Err(e);
        }
        if self.any(
            t_s,
            |f| matches!(f, Fault::WheelRefuses { tile: t } if *t == tile),
        ) {
            return Err(ErrorKind::Other);
        }
        Ok(if self.wheel_stopped(t_s, tile) {
            0.0
        } else {
            h_nms
        })
    }

    /// True if `tile`'s wheel is stopped at `t_s`.
    pub fn wheel_stopped(&self, t_s: f64, tile: usize) -> bool {
        self.any(
            t_s,
            |f| matches!(f, Fault::WheelStopped { tile: t } if *t == tile),
        )
    }

    /// The dipole coil `coil` takes at `t_s` when commanded `m_am2`: `Err` if the bus fails,
    /// else the dipole it gives (zero if open, the stuck value if left on).
    pub fn coil(&self, t_s: f64, coil: usize, m_am2: f64) -> Result<f64, ErrorKind> {
        if self.bus_burst(t_s) {
            return Err(ErrorKind::Bus);
        }
        Ok(self.coil_forced(t_s, coil).unwrap_or(m_am2))
    }

    /// True if every bus transaction fails at `t_s` ([`Fault::BusErrors`]).
    pub fn bus_burst(&self, t_s: f64) -> bool {
        self.any(t_s, |f| matches!(f, Fault::BusErrors))
    }

    /// The dipole coil `coil` is forced to at `t_s` (open: zero; left on: its value), if any.
    pub fn coil_forced(&self, t_s: f64, coil: usize) -> Option<f64> {
        let mut out = None;
        for i in self.list.iter().filter(|i| i.active(t_s)) {
            match i.fault {
                Fault::CoilOpen { coil: c } if c == coil => out = Some(0.0),
                Fault::CoilLeftOn {
                    coil: c,
                    dipole_am2,
                } if c == coil => out = Some(dipole_am2),
                _ => {}
            }
        }
        out
    }

    /// True if the Sun sensors are dark at `t_s`.
    pub fn dark(&self, t_s: f64) -> bool {
        self.any(t_s, |f| matches!(f, Fault::SunSensorsDark))
    }
}
