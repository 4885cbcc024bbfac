//! The satellite's tile bus built from per-device drivers: [`DeviceBus`].
//!
//! The ACS loop speaks [`TileBus`]: sensors and wheels by tile index, coils by coil index,
//! errors reduced to an [`ErrorKind`]. A board has drivers, one per device: a sun sensor, a
//! magnetometer, a gyro and a wheel on some tiles, and the satellite's coils. [`DeviceBus`]
//! holds them and is the [`TileBus`]:
//!
//! | [`TileBus`] call | goes to | error |
//! |---|---|---|
//! | `read_sun(i)` | tile `i`'s [`SunSensor::read_sun_raw`] | the driver's [`Error::kind`]; no such tile or no sensor: [`ErrorKind::DeviceAbsent`] |
//! | `read_magnetometer(i)` | tile `i`'s [`Magnetometer::read_field_raw`] | as above |
//! | `read_gyro(i)` | tile `i`'s [`Gyro::read_rate_raw`] | as above |
//! | `set_wheel_momentum(i, h)` | tile `i`'s [`ReactionWheel::set_momentum`] | as above |
//! | `set_dipole(c, m)` | coil `c`'s [`Magnetorquer::set_dipole`] | as above (no such coil) |
//! | `read_wheel_momentum(i)` | tile `i`'s [`ReactionWheel::read_momentum_raw`] | as above |
//! | `read_coil_dipole(c)` | coil `c`'s [`Magnetorquer::read_dipole_raw`] | as above |
//! | `delay_us(t)` | the board's timer, `embedded_hal::delay::DelayNs::delay_us` | none |
//!
//! The devices are any types implementing the device traits: the drivers of
//! [`super::drivers`], a board's own, or `&mut` borrows of either (the traits forward through
//! `&mut T`, so a board can lend its drivers and keep them). All the tiles' sun sensors have
//! one type `S`, and so on per device kind; parts of different types on one bus go in an enum
//! of the board's, or as `&mut dyn SunSensor<Error = E>`. A device kind the satellite does not
//! have at all is [`NoDevice`]. The raw words pass unchanged: a part's resolution is its
//! driver's configuration ([`super::drivers::Scale`]).
//!
//! The host simulator and the MSP430 firmware implement [`TileBus`] directly (the
//! [module docs](super), "Who implements `TileBus` how"); this adapter is the path of a board
//! whose devices have drivers: the attitude node's flight image flies one
//! ([`super::msp430::tile_bus`]).
//!
//! ```
//! use acs::hal::bus::{DeviceBus, NoDevice, TileDevices};
//! use acs::hal::{CoilIndex, ErrorKind, ErrorType, Magnetometer, TileBus, TileIndex};
//!
//! use embedded_hal::delay::DelayNs;
//!
//! /// A magnetometer that always reads the same words (a board's driver in real life).
//! struct Fixed([i16; 2]);
//! impl ErrorType for Fixed {
//!     type Error = ErrorKind;
//! }
//! impl Magnetometer for Fixed {
//!     fn read_field_raw(&mut self) -> Result<[i16; 2], ErrorKind> {
//!         Ok(self.0)
//!     }
//! }
//!
//! /// The board's timer (a HAL's `DelayNs` in real life; this one only counts).
//! struct Timer(u64);
//! impl DelayNs for Timer {
//!     fn delay_ns(&mut self, ns: u32) {
//!         self.0 += u64::from(ns);
//!     }
//! }
//!
//! // two tiles: the first without devices, the second with a magnetometer; no coil
//! let tiles = [
//!     TileDevices::none(),
//!     TileDevices::none().with_magnetometer(Fixed([1603, -467])),
//! ];
//! let mut bus: DeviceBus<NoDevice, Fixed, NoDevice, NoDevice, NoDevice, Timer, 2, 0> =
//!     DeviceBus::new(tiles, [], Timer(0));
//! assert_eq!(bus.read_magnetometer(1), Ok([1603, -467]));
//! assert_eq!(bus.read_magnetometer(0), Err(ErrorKind::DeviceAbsent));
//! assert_eq!(bus.set_dipole(0, 0.1), Err(ErrorKind::DeviceAbsent));
//! assert!(bus.tile(TileIndex(1)).is_some_and(|t| t.magnetometer.is_some()));
//! assert!(bus.coil(CoilIndex(0)).is_none());
//! ```

use embedded_hal::delay::DelayNs;

use super::{
    CoilIndex, Error, ErrorKind, ErrorType, Gyro, Magnetometer, Magnetorquer, ReactionWheel,
    SunSensor, TileBus, TileIndex,
};

/// A device kind the satellite does not have (no value exists: `Option<NoDevice>` is always
/// `None`). It implements every device trait, so a [`DeviceBus`] whose tiles have, say, no
/// reaction wheel names `NoDevice` as its wheel type.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum NoDevice {}

impl ErrorType for NoDevice {
    type Error = ErrorKind;
}

impl SunSensor for NoDevice {
    fn read_sun_raw(&mut self) -> Result<Option<[i16; 2]>, ErrorKind> {
        match *self {}
    }
}

impl Magnetometer for NoDevice {
    fn read_field_raw(&mut self) -> Result<[i16; 2], ErrorKind> {
        match *self {}
    }
}

impl Gyro for NoDevice {
    fn read_rate_raw(&mut self) -> Result<i16, ErrorKind> {
        match *self {}
    }
}

impl ReactionWheel for NoDevice {
    fn set_momentum(&mut self, _: f32) -> Result<(), ErrorKind> {
        match *self {}
    }
}

impl Magnetorquer for NoDevice {
    fn set_dipole(&mut self, _: f32) -> Result<(), ErrorKind> {
        match *self {}
    }
}

/// The devices of one tile, each optional (a telecom tile has none; a tile may lack a wheel or
/// a sensor). What the loop reads of a tile is set by its configuration
/// ([`crate::tiles::Equipment`]): a device the configuration gives the tile and the bus lacks
/// reads as [`ErrorKind::DeviceAbsent`] (and the loop marks the tile failed).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TileDevices<S, M, G, W> {
    /// The sun sensor.
    pub sun_sensor: Option<S>,
    /// The two-axis magnetometer.
    pub magnetometer: Option<M>,
    /// The one-axis gyro.
    pub gyro: Option<G>,
    /// The reaction wheel.
    pub wheel: Option<W>,
}

impl<S, M, G, W> TileDevices<S, M, G, W> {
    /// A tile with no device.
    pub const fn none() -> Self {
        Self {
            sun_sensor: None,
            magnetometer: None,
            gyro: None,
            wheel: None,
        }
    }

    /// A tile with all four devices (a power tile).
    pub const fn new(sun_sensor: S, magnetometer: M, gyro: G, wheel: W) -> Self {
        Self {
            sun_sensor: Some(sun_sensor),
            magnetometer: Some(magnetometer),
            gyro: Some(gyro),
            wheel: Some(wheel),
        }
    }

    /// The same tile with `sun_sensor`.
    pub fn with_sun_sensor(self, sun_sensor: S) -> Self {
        Self {
            sun_sensor: Some(sun_sensor),
            ..self
        }
    }

    /// The same tile with `magnetometer`.
    pub fn with_magnetometer(self, magnetometer: M) -> Self {
        Self {
            magnetometer: Some(magnetometer),
            ..self
        }
    }

    /// The same tile with `gyro`.
    pub fn with_gyro(self, gyro: G) -> Self {
        Self {
            gyro: Some(gyro),
            ..self
        }
    }

    /// The same tile with `wheel`.
    pub fn with_wheel(self, wheel: W) -> Self {
        Self {
            wheel: Some(wheel),
            ..self
        }
    }
}

impl<S, M, G, W> Default for TileDevices<S, M, G, W> {
    fn default() -> Self {
        Self::none()
    }
}

/// The satellite's [`TileBus`] over per-device drivers: `N` tiles (in the configuration's tile
/// order) with sun sensors `S`, magnetometers `M`, gyros `G` and wheels `W`, and `K`
/// magnetorquer coils `C` (in the order of `AcsConfig::coils`), and the board's timer `D`
/// ([`TileBus::delay_us`]). See the [module docs](self).
#[derive(Clone, Debug)]
pub struct DeviceBus<S, M, G, W, C, D, const N: usize, const K: usize> {
    tiles: [TileDevices<S, M, G, W>; N],
    coils: [Option<C>; K],
    delay: D,
}

/// A device's error as the bus reports it.
fn kind<E: Error>(e: E) -> ErrorKind {
    e.kind()
}

impl<S, M, G, W, C, D, const N: usize, const K: usize> DeviceBus<S, M, G, W, C, D, N, K> {
    /// The bus over `tiles` (tile `i` = [`TileIndex`]`(i)`) and `coils` (coil `c` =
    /// [`CoilIndex`]`(c)`; `None`: a coil the satellite lacks or that is not fitted), waiting
    /// on `delay` (the board's timer: it must wait at least what it is asked).
    pub fn new(tiles: [TileDevices<S, M, G, W>; N], coils: [Option<C>; K], delay: D) -> Self {
        Self {
            tiles,
            coils,
            delay,
        }
    }

    /// The devices of tile `tile`, if it exists.
    pub fn tile(&self, tile: TileIndex) -> Option<&TileDevices<S, M, G, W>> {
        self.tiles.get(tile.0)
    }

    /// The devices of tile `tile`, mutably (to call a driver, or replace one).
    pub fn tile_mut(&mut self, tile: TileIndex) -> Option<&mut TileDevices<S, M, G, W>> {
        self.tiles.get_mut(tile.0)
    }

    /// Coil `coil`, if fitted.
    pub fn coil(&self, coil: CoilIndex) -> Option<&C> {
        self.coils.get(coil.0).and_then(Option::as_ref)
    }

    /// Coil `coil`, mutably, if fitted.
    pub fn coil_mut(&mut self, coil: CoilIndex) -> Option<&mut C> {
        self.coils.get_mut(coil.0).and_then(Option::as_mut)
    }

    /// Gives the devices back: the tiles', the coils' and the timer.
    #[allow(clippy::type_complexity, reason = "what `new` takes")]
    pub fn release(self) -> ([TileDevices<S, M, G, W>; N], [Option<C>; K], D) {
        (self.tiles, self.coils, self.delay)
    }

    /// Tile `tile`'s device picked by `pick`, or [`ErrorKind::DeviceAbsent`].
    fn device<T>(
        &mut self,
        tile: TileIndex,
        pick: impl FnOnce(&mut TileDevices<S, M, G, W>) -> Option<&mut T>,
    ) -> Result<&mut T, ErrorKind> {
        self.tile_mut(tile)
            .and_then(pick)
            .ok_or(ErrorKind::DeviceAbsent)
    }
}

impl<S, M, G, W, C, D, const N: usize, const K: usize> DeviceBus<S, M, G, W, C, D, N, K>
where
    W: ReactionWheel,
    C: Magnetorquer,
{
    /// Switches every fitted coil off ([`Magnetorquer::off`]); the first error, after trying
    /// them all. (The loop's own safe state, [`crate::acs_loop::AcsLoop::safe`], commands the
    /// configured coils to zero through the bus.)
    pub fn coils_off(&mut self) -> Result<(), ErrorKind> {
        let mut first = Ok(());
        for coil in self.coils.iter_mut().flatten() {
            if let Err(e) = coil.off() {
                first = first.and(Err(kind(e)));
            }
        }
        first
    }

    /// Stops every fitted wheel ([`ReactionWheel::stop`]); the first error, after trying them
    /// all. Not the loop's safe state (it holds the wheels' momentum): for a power-up or a
    /// ground-commanded stop.
    pub fn stop_wheels(&mut self) -> Result<(), ErrorKind> {
        let mut first = Ok(());
        for wheel in self.tiles.iter_mut().filter_map(|t| t.wheel.as_mut()) {
            if let Err(e) = wheel.stop() {
                first = first.and(Err(kind(e)));
            }
        }
        first
    }
}

impl<S, M, G, W, C, D, const N: usize, const K: usize> TileBus for DeviceBus<S, M, G, W, C, D, N, K>
where
    S: SunSensor,
    M: Magnetometer,
    G: Gyro,
    W: ReactionWheel,
    C: Magnetorquer,
    D: DelayNs,
{
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        self.device(TileIndex(tile), |t| t.sun_sensor.as_mut())?
            .read_sun_raw()
            .map_err(kind)
    }

    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        self.device(TileIndex(tile), |t| t.magnetometer.as_mut())?
            .read_field_raw()
            .map_err(kind)
    }

    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        self.device(TileIndex(tile), |t| t.gyro.as_mut())?
            .read_rate_raw()
            .map_err(kind)
    }

    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        self.device(TileIndex(tile), |t| t.wheel.as_mut())?
            .set_momentum(h_nms)
            .map_err(kind)
    }

    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        self.coil_mut(CoilIndex(coil))
            .ok_or(ErrorKind::DeviceAbsent)?
            .set_dipole(m_am2)
            .map_err(kind)
    }

    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        self.device(TileIndex(tile), |t| t.wheel.as_mut())?
            .read_momentum_raw()
            .map_err(kind)
    }

    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        self.coil_mut(CoilIndex(coil))
            .ok_or(ErrorKind::DeviceAbsent)?
            .read_dipole_raw()
            .map_err(kind)
    }

    fn delay_us(&mut self, us: u32) {
        self.delay.delay_us(us);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A device that records its commands and answers with a fixed result.
    #[derive(Debug, Default)]
    struct Fake {
        fail: Option<ErrorKind>,
        commands: heapless::Vec<f32, 8>,
    }

    impl ErrorType for Fake {
        type Error = ErrorKind;
    }

    impl SunSensor for Fake {
        fn read_sun_raw(&mut self) -> Result<Option<[i16; 2]>, ErrorKind> {
            self.fail.map_or(Ok(Some([1, 2])), Err)
        }
    }

    impl Magnetorquer for Fake {
        fn set_dipole(&mut self, m: f32) -> Result<(), ErrorKind> {
            let _ = self.commands.push(m);
            self.fail.map_or(Ok(()), Err)
        }
    }

    impl ReactionWheel for Fake {
        fn set_momentum(&mut self, h: f32) -> Result<(), ErrorKind> {
            let _ = self.commands.push(h);
            self.fail.map_or(Ok(()), Err)
        }
    }

    /// A timer that adds up what it is asked to wait, ns.
    #[derive(Debug, Default)]
    struct Waited(u64);

    impl DelayNs for Waited {
        fn delay_ns(&mut self, ns: u32) {
            self.0 += u64::from(ns);
        }
    }

    type Bus = DeviceBus<Fake, NoDevice, NoDevice, Fake, Fake, Waited, 2, 3>;

    fn bus() -> Bus {
        let failing = Fake {
            fail: Some(ErrorKind::Timeout),
            ..Fake::default()
        };
        DeviceBus::new(
            [
                TileDevices::none().with_sun_sensor(Fake::default()),
                TileDevices::none().with_wheel(Fake::default()),
            ],
            [Some(Fake::default()), None, Some(failing)],
            Waited::default(),
        )
    }

    #[test]
    fn calls_reach_their_device_by_index() {
        let mut bus = bus();
        assert_eq!(bus.read_sun(0), Ok(Some([1, 2])));
        assert_eq!(bus.read_sun(1), Err(ErrorKind::DeviceAbsent));
        assert_eq!(bus.read_sun(2), Err(ErrorKind::DeviceAbsent));
        assert_eq!(bus.read_gyro(0), Err(ErrorKind::DeviceAbsent));
        assert_eq!(bus.set_wheel_momentum(1, 2e-4), Ok(()));
        assert_eq!(
            bus.set_wheel_momentum(0, 2e-4),
            Err(ErrorKind::DeviceAbsent)
        );
        assert_eq!(bus.set_dipole(0, 0.1), Ok(()));
        assert_eq!(bus.set_dipole(1, 0.1), Err(ErrorKind::DeviceAbsent));
        assert_eq!(bus.set_dipole(2, 0.1), Err(ErrorKind::Timeout));
        assert_eq!(bus.set_dipole(3, 0.1), Err(ErrorKind::DeviceAbsent));
        assert_eq!(bus.coils_off(), Err(ErrorKind::Timeout));
        assert_eq!(bus.stop_wheels(), Ok(()));
        let wheel = bus.tile(TileIndex(1)).and_then(|t| t.wheel.as_ref());
        assert_eq!(wheel.map(|w| w.commands.as_slice()), Some(&[2e-4, 0.0][..]));
        let coil = bus.coil(CoilIndex(0)).map(|c| c.commands.as_slice());
        assert_eq!(coil, Some(&[0.1, 0.0][..]));
        // the failing coil was tried by coils_off too
        let coil = bus.coil(CoilIndex(2)).map(|c| c.commands.as_slice());
        assert_eq!(coil, Some(&[0.1, 0.0][..]));
        // the bus waits on its timer
        bus.delay_us(5_000);
        assert_eq!(bus.release().2 .0, 5_000_000);
    }

    #[test]
    fn borrowed_drivers_are_drivers() {
        let mut sun = Fake::default();
        let mut coil = Fake::default();
        {
            let mut bus: DeviceBus<
                &mut Fake,
                NoDevice,
                NoDevice,
                NoDevice,
                &mut dyn Magnetorquer<Error = ErrorKind>,
                Waited,
                1,
                1,
            > = DeviceBus::new(
                [TileDevices::none().with_sun_sensor(&mut sun)],
                [Some(&mut coil)],
                Waited::default(),
            );
            assert_eq!(bus.read_sun(0), Ok(Some([1, 2])));
            assert_eq!(bus.set_dipole(0, -0.05), Ok(()));
            // and a bus borrowed mutably is a bus
            let mut borrowed = &mut bus;
            assert_eq!(TileBus::set_dipole(&mut borrowed, 0, 0.0), Ok(()));
        }
        assert_eq!(coil.commands.as_slice(), &[-0.05, 0.0]);

        // a driver's own `stop` is the one a borrow calls (not the default zero command)
        struct Brake(bool);
        impl ErrorType for Brake {
            type Error = ErrorKind;
        }
        impl ReactionWheel for Brake {
            fn set_momentum(&mut self, _: f32) -> Result<(), ErrorKind> {
                Err(ErrorKind::Other)
            }
            fn stop(&mut self) -> Result<(), ErrorKind> {
                self.0 = true;
                Ok(())
            }
        }
        let mut brake = Brake(false);
        let mut bus: DeviceBus<NoDevice, NoDevice, NoDevice, &mut Brake, NoDevice, Waited, 1, 0> =
            DeviceBus::new(
                [TileDevices::none().with_wheel(&mut brake)],
                [],
                Waited::default(),
            );
        assert_eq!(bus.stop_wheels(), Ok(()));
        assert!(brake.0);
        assert_eq!(
            sun.read_sun_angles(),
            Ok(Some(crate::tiles::RawSunAngles { a: 1, b: 2 }.to_rad()))
        );
    }
}
