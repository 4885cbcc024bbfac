//! Tile geometry, equipment, state and raw sensor formats (seed 000 §1.2, §6.2, class `Tile`;
//! note 000 §1.2–§1.3).
//!
//! # Frames
//! - **Body frame UVW**: fixed to the structure, origin at the geometric centre.
//! - **Tile frame XYZ**: origin at the tile centre, **ẑ normal to the tile, pointing outward**,
//!   x̂ × ŷ = ẑ. The magnetometer measures along x̂ and ŷ, the gyro and the reaction wheel act
//!   about ẑ, the Sun sensor's angles are measured in this frame.
//! - The tile's orientation is the constant matrix `A_m` whose **rows are x̂, ŷ, ẑ of the tile
//!   in UVW**: `v_xyz = A_m · v_uvw`. It is stored as a [`Dcm`] with "reference" = body and
//!   "body" = tile (see [`crate::attitude`]).
//!
//! # Raw formats (note 000 §1.3)
//! | sensor | raw | unit | conversion |
//! |---|---|---|---|
//! | Sun sensor | 2 × i16 `(a, b)` | 1e-4 rad | [`RawSunAngles::to_rad`] |
//! | magnetometer | 2 × i16 `(Bx, By)` | 10 nT | [`RawMagnetometer::to_nt`] (nT, not the thesis's 10 nT) |
//! | gyro | 1 × i16 `ω_z` | 1e-4 rad/s | [`RawGyro::to_radps`] |
//!
//! Sun angles: `a` is measured in the tile's Z–Y plane from Z, positive toward Y; `b` from the
//! Z–Y plane toward the Sun, positive toward X (the `Tile` class's convention; chapter 8's "b
//! positive clockwise" contradicts it, note 000 §7 item 1). The Sun direction in the tile frame
//! is then `s_xyz = (sin b, cos b·sin a, cos b·cos a)` ([`sun_direction_tile`]).
//!
//! # Presets
//! [`cube_thesis`] (the 6 tiles A0..A5 of the chapter-12 tests), [`cube_4_per_face`] (24
//! tiles), [`hexagonal_prism`] (8 tiles) and [`octagonal_prism`] (10 tiles). The prisms' matrices
//! are defined here (the thesis's text and figures disagree, note 000 §7 item 12): the prism axis
//! is **V**; side face k has the outward normal `ẑ = (cos φ_k, 0, sin φ_k)` (angle φ_k measured
//! from U toward W), `ŷ = +V`, `x̂ = ŷ × ẑ`; the two end caps are `ẑ = ±V` with `x̂ = −W`. For the
//! cube this rule gives exactly the thesis's A0 (+U), A1 (+V), A2 (+W), A4 (−V) and A5 (−W),
//! and a different (equally valid) rotation about the normal for −U (A3); the cube presets use
//! the thesis's own matrices.

use crate::attitude::Dcm;
use crate::fmath;
use crate::linalg::{Mat3, Vec2, Vec3};

/// The largest number of tiles a [`Tiles`] set holds.
pub const MAX_TILES: usize = 24;

/// A set of tiles (fixed capacity, no allocation).
pub type Tiles = heapless::Vec<Tile, MAX_TILES>;

/// Unit of the raw Sun-sensor angles, rad per LSB.
pub const SUN_LSB_RAD: f32 = 1.0e-4;
/// Unit of the raw magnetometer components, nT per LSB.
pub const MAGNETOMETER_LSB_NT: f32 = 10.0;
/// Unit of the raw gyro rate, rad/s per LSB.
pub const GYRO_LSB_RADPS: f32 = 1.0e-4;
/// Unit of a wheel's momentum read-back, kg·m²/s per LSB: ±3.3e-3, 3.3 times the flight
/// limit ([`crate::flight::WHEEL_LIMIT_NMS`]); the realistic wheel's tachometer quantum (1 rpm,
/// 1.7e-6 kg·m²/s) is 17 LSB.
pub const WHEEL_LSB_NMS: f32 = 1.0e-7;
/// Unit of a coil's dipole read-back, A·m² per LSB: ±0.33 A·m², 1.6 times the flight limit
/// ([`crate::flight::COIL_LIMIT_AM2`]).
pub const COIL_LSB_AM2: f32 = 1.0e-5;

/// What a tile carries (the thesis's `sun`, `magnetometer`, `gyroscope`, `RW` flags).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Equipment {
    /// A two-angle Sun sensor.
    pub sun_sensor: bool,
    /// A two-axis magnetometer (tile x and y).
    pub magnetometer: bool,
    /// A one-axis gyro (tile z).
    pub gyro: bool,
    /// A reaction wheel (spin axis tile z).
    pub reaction_wheel: bool,
}

impl Equipment {
    /// A Power Management tile: all four ACS devices.
    pub const POWER: Self = Self {
        sun_sensor: true,
        magnetometer: true,
        gyro: true,
        reaction_wheel: true,
    };
    /// A Telecommunication tile: no ACS device.
    pub const TELECOM: Self = Self {
        sun_sensor: false,
        magnetometer: false,
        gyro: false,
        reaction_wheel: false,
    };
}

/// Whether a tile is in service.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TileState {
    /// In service: its sensors and actuators are used.
    Working,
    /// Failed or switched off: ignored by the determination and the control.
    Failed,
}

/// One tile: orientation, equipment, state.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tile {
    /// `A_m`: rows = tile x̂, ŷ, ẑ in the body frame; `v_tile = A_m · v_body`.
    pub body_to_tile: Dcm,
    /// What it carries.
    pub equipment: Equipment,
    /// In service or not.
    pub state: TileState,
}

impl Tile {
    /// A working tile with orientation `A_m` (rows = tile x̂, ŷ, ẑ in the body frame).
    pub const fn new(body_to_tile: Mat3, equipment: Equipment) -> Self {
        Self {
            body_to_tile: Dcm::from_matrix_unchecked(body_to_tile),
            equipment,
            state: TileState::Working,
        }
    }

    /// The tile's x̂ axis (first magnetometer axis) in the body frame: row 1 of `A_m`. Out of
    /// line on the MSP430, as [`Tile::y_body`] and [`Tile::normal_body`]: a row of the
    /// column-major matrix is three strided copies, about 50 B inlined at each use.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn x_body(&self) -> Vec3 {
        let m = self.body_to_tile.matrix();
        Vec3::new(m.m11, m.m12, m.m13)
    }

    /// The tile's ŷ axis (second magnetometer axis) in the body frame: row 2 of `A_m`.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn y_body(&self) -> Vec3 {
        let m = self.body_to_tile.matrix();
        Vec3::new(m.m21, m.m22, m.m23)
    }

    /// The tile's outward normal ẑ (gyro and wheel axis) in the body frame: row 3 of `A_m`
    /// (eq. 8.4).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn normal_body(&self) -> Vec3 {
        self.normal_body_inline()
    }

    /// [`Tile::normal_body`] inlined: for the reference node's albedo loop
    /// ([`crate::env::albedo::seen_by_lit_sensors`], its only use there), whose bytes and cycles
    /// it keeps.
    #[inline(always)]
    pub(crate) fn normal_body_inline(&self) -> Vec3 {
        let m = self.body_to_tile.matrix();
        Vec3::new(m.m31, m.m32, m.m33)
    }

    /// Whether the tile is working.
    pub fn is_working(&self) -> bool {
        self.state == TileState::Working
    }

    /// Working and carrying a Sun sensor.
    pub fn has_working_sun_sensor(&self) -> bool {
        self.is_working() && self.equipment.sun_sensor
    }

    /// Working and carrying a magnetometer.
    pub fn has_working_magnetometer(&self) -> bool {
        self.is_working() && self.equipment.magnetometer
    }

    /// Working and carrying a gyro.
    pub fn has_working_gyro(&self) -> bool {
        self.is_working() && self.equipment.gyro
    }

    /// Working and carrying a reaction wheel.
    pub fn has_working_wheel(&self) -> bool {
        self.is_working() && self.equipment.reaction_wheel
    }

    /// A vector measured in the tile frame, expressed in the body frame: `A_mᵀ · v_tile`.
    pub fn tile_to_body(&self, v_tile: &Vec3) -> Vec3 {
        self.body_to_tile.to_reference(v_tile)
    }
}

/// Raw Sun-sensor output: two angles in units of [`SUN_LSB_RAD`].
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RawSunAngles {
    /// `a`: in the tile Z–Y plane, from Z toward Y.
    pub a: i16,
    /// `b`: from the Z–Y plane toward the Sun, positive toward X.
    pub b: i16,
}

impl RawSunAngles {
    /// `(a, b)` in radians.
    pub fn to_rad(&self) -> SunAngles {
        SunAngles {
            a_rad: f32::from(self.a) * SUN_LSB_RAD,
            b_rad: f32::from(self.b) * SUN_LSB_RAD,
        }
    }
}

/// Sun-sensor angles in radians (convention in the [module docs](self)).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SunAngles {
    /// `a`, rad.
    pub a_rad: f32,
    /// `b`, rad.
    pub b_rad: f32,
}

/// Raw magnetometer output: the field on the tile's x̂ and ŷ, units of [`MAGNETOMETER_LSB_NT`].
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RawMagnetometer {
    /// Component along tile x̂.
    pub x: i16,
    /// Component along tile ŷ.
    pub y: i16,
}

impl RawMagnetometer {
    /// `(B_x, B_y)` in nT (range ±327 670 nT).
    pub fn to_nt(&self) -> Vec2 {
        Vec2::new(
            f32::from(self.x) * MAGNETOMETER_LSB_NT,
            f32::from(self.y) * MAGNETOMETER_LSB_NT,
        )
    }
}

/// Raw gyro output: the rate about the tile's ẑ, units of [`GYRO_LSB_RADPS`].
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RawGyro(pub i16);

impl RawGyro {
    /// The rate in rad/s (range ±3.2767 rad/s).
    pub fn to_radps(&self) -> f32 {
        f32::from(self.0) * GYRO_LSB_RADPS
    }
}

/// The unit Sun direction in the tile frame from the sensor angles (note 000 §7 item 1):
/// `s_xyz = (sin b, cos b·sin a, cos b·cos a)`.
pub fn sun_direction_tile(angles: &SunAngles) -> Vec3 {
    let (sa, ca) = fmath::sincos(angles.a_rad);
    let (sb, cb) = fmath::sincos(angles.b_rad);
    Vec3::new(sb, cb * sa, cb * ca)
}

/// The tile's sensor angles of a Sun direction given in the tile frame (inverse of
/// [`sun_direction_tile`]): `a = atan2(s_y, s_z)`, `b = atan2(s_x, √(s_y² + s_z²))`. Used by the
/// simulator and the tests.
pub fn sun_angles_of_direction(s_tile: &Vec3) -> SunAngles {
    SunAngles {
        a_rad: fmath::atan2(s_tile.y, s_tile.z),
        b_rad: fmath::atan2(
            s_tile.x,
            fmath::sqrt(s_tile.y * s_tile.y + s_tile.z * s_tile.z),
        ),
    }
}

/// The thesis's six tile matrices A0..A5 (note 000 §1.2), rows = tile x̂, ŷ, ẑ in UVW.
pub const CUBE_THESIS_MATRICES: [Mat3; 6] = [
    // A0: ẑ = +U (UVW rotated 90° about V)
    Mat3::new(0.0, 0.0, -1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0),
    // A1: ẑ = +V
    Mat3::new(0.0, 0.0, -1.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0),
    // A2: ẑ = +W
    Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
    // A3: ẑ = −U
    Mat3::new(0.0, 0.0, -1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 0.0),
    // A4: ẑ = −V
    Mat3::new(0.0, 0.0, -1.0, 1.0, 0.0, 0.0, 0.0, -1.0, 0.0),
    // A5: ẑ = −W
    Mat3::new(-1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0),
];

/// The chapter-12 cube: tiles 0..5 with A0..A5; tile 0 is a Telecommunication tile (no ACS
/// device), tiles 1–5 Power Management tiles (note 000 §4.2).
pub fn cube_thesis() -> Tiles {
    CUBE_THESIS.iter().copied().collect()
}

/// The tiles of [`cube_thesis`] as a constant (for a flight configuration sized to six tiles).
pub const CUBE_THESIS: [Tile; 6] = [
    Tile::new(CUBE_THESIS_MATRICES[0], Equipment::TELECOM),
    Tile::new(CUBE_THESIS_MATRICES[1], Equipment::POWER),
    Tile::new(CUBE_THESIS_MATRICES[2], Equipment::POWER),
    Tile::new(CUBE_THESIS_MATRICES[3], Equipment::POWER),
    Tile::new(CUBE_THESIS_MATRICES[4], Equipment::POWER),
    Tile::new(CUBE_THESIS_MATRICES[5], Equipment::POWER),
];

/// A cube with 4 tiles per face (24 Power Management tiles): tiles `4f..4f+3` are on face `f`
/// and share the thesis's matrix `A_f` (their normals are parallel, so their measurements are
/// averaged by the least squares).
pub fn cube_4_per_face() -> Tiles {
    CUBE_THESIS_MATRICES
        .iter()
        .flat_map(|a| core::iter::repeat_n(Tile::new(*a, Equipment::POWER), 4))
        .collect()
}

/// The tile of a prism side face with outward normal at angle `phi_rad` from U toward W:
/// `ẑ = (cos φ, 0, sin φ)`, `ŷ = V`, `x̂ = ŷ × ẑ = (sin φ, 0, −cos φ)`.
fn side_tile(phi_rad: f32) -> Tile {
    let (s, c) = fmath::sincos(phi_rad);
    Tile::new(
        Mat3::new(s, 0.0, -c, 0.0, 1.0, 0.0, c, 0.0, s),
        Equipment::POWER,
    )
}

/// The prism end caps: `ẑ = +V` (A1 of the cube) and `ẑ = −V` (A4).
fn caps() -> [Tile; 2] {
    [
        Tile::new(
            Mat3::new(0.0, 0.0, -1.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0),
            Equipment::POWER,
        ),
        Tile::new(
            Mat3::new(0.0, 0.0, -1.0, 1.0, 0.0, 0.0, 0.0, -1.0, 0.0),
            Equipment::POWER,
        ),
    ]
}

/// The hexagonal prism (seed 000 Figs. 6.2, 6.4): prism axis V; six side tiles with normals at
/// φ = 30°, 90°, 150°, 210°, 270°, 330° from U toward W (so the two faces next to +U are at
/// ±30° from U and **no wheel spins about U**); then the caps +V, −V. 8 Power tiles.
///
/// Explicitly, side tile k (k = 0..5, φ = 30° + 60°k) has
/// `A = [[sin φ, 0, −cos φ], [0, 1, 0], [cos φ, 0, sin φ]]`.
pub fn hexagonal_prism() -> Tiles {
    let deg = core::f32::consts::PI / 180.0;
    let mut tiles: Tiles = (0..6u8)
        .map(|k| side_tile((30.0 + 60.0 * f32::from(k)) * deg))
        .collect();
    for cap in caps() {
        // 6 + 2 ≤ MAX_TILES: cannot fail.
        let _ = tiles.push(cap);
    }
    tiles
}

/// The octagonal prism (seed 000 Fig. 6.3): prism axis V; eight side tiles with normals at
/// φ = 0°, 45°, …, 315° from U toward W (every body axis has a wheel: U at 0°/180°, W at
/// 90°/270°, V on the caps); then the caps +V, −V. 10 Power tiles. Side tile matrices as in
/// [`hexagonal_prism`] with φ = 45°k.
pub fn octagonal_prism() -> Tiles {
    let deg = core::f32::consts::PI / 180.0;
    let mut tiles: Tiles = (0..8u8)
        .map(|k| side_tile(45.0 * f32::from(k) * deg))
        .collect();
    for cap in caps() {
        let _ = tiles.push(cap);
    }
    tiles
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_proper_rotations_with_outward_normals() {
        for tiles in [
            cube_thesis(),
            cube_4_per_face(),
            hexagonal_prism(),
            octagonal_prism(),
        ] {
            for t in &tiles {
                let a = t.body_to_tile;
                assert!((a.determinant() - 1.0).abs() < 1e-6);
                assert!(a.orthogonality_error() < 1e-6);
                assert!((t.x_body().cross(&t.y_body()) - t.normal_body()).norm() < 1e-6);
            }
        }
        assert_eq!(cube_4_per_face().len(), 24);
        assert_eq!(hexagonal_prism().len(), 8);
        assert_eq!(octagonal_prism().len(), 10);
        // Hexagon: no normal along ±U.
        assert!(hexagonal_prism()
            .iter()
            .all(|t| t.normal_body().x.abs() < 0.9));
        // The side rule reproduces the thesis's A0 (+U) and A2 (+W).
        let a0 = side_tile(0.0).body_to_tile;
        assert!((a0.matrix() - CUBE_THESIS_MATRICES[0]).amax() < 1e-7);
        let a2 = side_tile(core::f32::consts::FRAC_PI_2).body_to_tile;
        assert!((a2.matrix() - CUBE_THESIS_MATRICES[2]).amax() < 1e-7);
        let a5 = side_tile(1.5 * core::f32::consts::PI).body_to_tile;
        assert!((a5.matrix() - CUBE_THESIS_MATRICES[5]).amax() < 1e-6);
        let [cap_plus, cap_minus] = caps();
        assert_eq!(*cap_plus.body_to_tile.matrix(), CUBE_THESIS_MATRICES[1]);
        assert_eq!(*cap_minus.body_to_tile.matrix(), CUBE_THESIS_MATRICES[4]);
    }

    #[test]
    fn raw_conversions() {
        let s = RawSunAngles { a: 10000, b: -5 }.to_rad();
        assert_eq!(s.a_rad, 1.0);
        assert!((s.b_rad + 5e-4).abs() < 1e-10);
        assert_eq!(
            RawMagnetometer {
                x: -32768,
                y: 32767
            }
            .to_nt(),
            Vec2::new(-327_680.0, 327_670.0)
        );
        assert!((RawGyro(-12345).to_radps() + 1.2345).abs() < 1e-6);
    }

    #[test]
    fn sun_angles_round_trip() {
        for (a, b) in [(0.3f32, -0.2f32), (-1.0, 0.7), (0.0, 0.0), (1.4, 1.2)] {
            let s = sun_direction_tile(&SunAngles { a_rad: a, b_rad: b });
            assert!((s.norm() - 1.0).abs() < 1e-6);
            let back = sun_angles_of_direction(&s);
            assert!((back.a_rad - a).abs() < 1e-6 && (back.b_rad - b).abs() < 1e-6);
        }
        // Sun on the normal: a = b = 0; toward +Y: a > 0; toward +X: b > 0.
        let s = sun_direction_tile(&SunAngles {
            a_rad: 0.1,
            b_rad: 0.2,
        });
        assert!(s.x > 0.0 && s.y > 0.0 && s.z > 0.0);
    }
}
