//! SGP4 initialisation: the element set to the propagator's constants and phases (Vallado's
//! `twoline2rv` conversions, `initl` and `sgp4init`, near-Earth part).

use super::{finite32, FullDrag, Gravity, Sgp4, Sgp4Error};
use crate::fmath;
use crate::orbit::{Df, Phase};
use crate::tle::Tle;

/// Vallado's near-Earth limit: period below 225 min.
const DEEP_SPACE_PERIOD_MIN: f32 = 225.0;

/// A TLE field as double-f32 (its f64 bits split with integer operations).
fn element(x: f64, field: &'static str) -> Result<Df, Sgp4Error> {
    Df::from_f64(x).ok_or(Sgp4Error::Element { field })
}

/// cos of an angle in degrees, 0 ≤ x ≤ 180, in double length: sin(90° − x) (the subtraction in
/// degrees is exact), by its Taylor series.
fn cos_degrees(x_deg: &Df) -> Df {
    const DEG: Df = Df::from_f64_const(core::f64::consts::PI / 180.0);
    (&(90.0 - x_deg) * &DEG).sin_pi_2()
}

/// sin and cos (f32) of an angle given in degrees (double-f32, any finite value): reduced
/// modulo 360° in double length, then `fmath::sincos`.
fn sincos_degrees(x_deg: &Df) -> (f32, f32) {
    let r = turns_of_degrees(x_deg);
    let r = &r - crate::fmath::floor(r.hi());
    crate::fmath::sincos(r.to_f32() * core::f32::consts::TAU)
}

/// A TLE angle in degrees as turns, modulo one turn (double-f32).
fn turns_of_degrees(x_deg: &Df) -> Df {
    let turns = x_deg / 360.0;
    &turns - crate::fmath::floor(turns.hi())
}

impl Sgp4 {
    /// Initialises the propagator from an element set (Vallado's `twoline2rv` conversions,
    /// `initl` and `sgp4init`, near-Earth part), then checks it by propagating to the epoch as
    /// Vallado's `sgp4init` does.
    ///
    /// f32 and double-f32 operations only (module docs, "Precision"): no f64 arithmetic, so
    /// the MSP430 build carries no f64 soft float. The TLE's f64 fields are split into
    /// double-f32 from their bits.
    ///
    /// # Errors
    /// [`Sgp4Error::Element`] for a non-finite element (or one beyond the f32 range),
    /// [`Sgp4Error::Eccentricity`] outside 0..1, [`Sgp4Error::MeanMotion`],
    /// [`Sgp4Error::DeepSpace`], [`Sgp4Error::SubOrbital`], or any error of the propagation to
    /// the epoch.
    pub fn new(tle: &Tle, gravity: Gravity) -> Result<Self, Sgp4Error> {
        /// rev/day → rad/min: 2π/1440.
        const REV_PER_DAY: Df = Df::from_f64_const(core::f64::consts::TAU / 1440.0);
        /// rad → turns.
        const INV_TAU: Df = Df::from_f64_const(1.0 / core::f64::consts::TAU);
        /// 1/3.
        const X1O3: Df = Df::from_f64_const(1.0 / 3.0);
        let g = gravity.constants();
        let radius_km = g.radius_km;
        // twoline2rv: rev/day → rad/min, degrees → rad (angles kept in degrees here)
        let n_rev_day = element(tle.mean_motion_rev_per_day, "mean motion")?;
        let ecco = element(tle.eccentricity, "eccentricity")?;
        let inclo_deg = element(tle.inclination_deg, "inclination")?;
        let nodeo_deg = element(tle.raan_deg, "right ascension of the node")?;
        let argpo_deg = element(tle.arg_perigee_deg, "argument of perigee")?;
        let mo_deg = element(tle.mean_anomaly_deg, "mean anomaly")?;
        let bstar = element(tle.bstar, "B*")?;
        // 0 ≤ i ≤ 180°, on hi + lo
        let (ih, il) = (inclo_deg.hi(), inclo_deg.lo());
        let above_0 = ih > 0.0 || (ih == 0.0 && il >= 0.0);
        let below_180 = !(ih >= 180.0) || (ih == 180.0 && !(il > 0.0));
        if !(above_0 && below_180) {
            return Err(Sgp4Error::Element {
                field: "inclination",
            });
        }
        let no_kozai = &n_rev_day * &REV_PER_DAY;
        if !(no_kozai.hi() > 0.0) {
            return Err(Sgp4Error::MeanMotion {
                rad_per_min: no_kozai.to_f32(),
            });
        }
        if !(ecco.hi() >= 0.0) || ecco.hi() >= 1.0 {
            return Err(Sgp4Error::Eccentricity {
                eccentricity: ecco.to_f32(),
                tsince_min: 0.0,
            });
        }

        // initl: recover the un-Kozai'd mean motion
        // (double-f32 operators take references: see `dfloat`)
        let eccsq = &ecco * &ecco;
        let omeosq = 1.0 - &eccsq;
        let rteosq = omeosq.sqrt();
        let cosio = cos_degrees(&inclo_deg);
        let cosio2 = &cosio * &cosio;
        // (in a block: its temporaries leave the stack frame, ≈ 100 B on the MSP430)
        let no = {
            let ak = two_thirds_power(&(&g.xke / &no_kozai));
            // d1 = 0.75·J₂·(3cos²i₀ − 1)/(√(1 − e₀²)·(1 − e₀²))
            let d1 = &(&(0.75 * &g.j2) * &(&(3.0 * &cosio2) - 1.0)) / &(&rteosq * &omeosq);
            let del = &d1 / &(&ak * &ak);
            // adel = ak·(1 − δ² − δ·(1/3 + 134δ²/81))
            let del2 = &del * &del;
            let series = &X1O3 + &(&(&(134.0 * &del) * &del) / 81.0);
            let adel = &ak * &(&(1.0 - &del2) - &(&del * &series));
            let del = &d1 / &(&adel * &adel);
            &no_kozai / &(1.0 + &del)
        };
        if !(finite32(no.hi()) && no.hi() > 0.0) {
            return Err(Sgp4Error::MeanMotion {
                rad_per_min: no.to_f32(),
            });
        }
        let period_min = core::f32::consts::TAU / no.to_f32();
        if period_min >= DEEP_SPACE_PERIOD_MIN {
            return Err(Sgp4Error::DeepSpace { period_min });
        }
        let ao = two_thirds_power(&(&g.xke / &no));
        let alta = &(&ao * &(1.0 + &ecco)) - 1.0;
        if !(alta.hi() >= 0.0) {
            return Err(Sgp4Error::SubOrbital {
                apogee_km: (&alta * &radius_km).to_f32(),
            });
        }

        // sgp4init, secular rates (double-f32: they multiply the time, up to 10⁴ min a week)
        let po = &ao * &omeosq;
        let pinvsq = 1.0 / &(&po * &po);
        let con42 = 1.0 - &(5.0 * &cosio2);
        let con41 = &(&-&con42 - &cosio2) - &cosio2;
        let temp1 = &(&(1.5 * &g.j2) * &pinvsq) * &no;
        let xhdot1 = &-&temp1 * &cosio;
        // the O(J₂²) and J₄ terms, 10⁻⁶ of n₀″, in f32 (below 10⁻¹³ rad/min)
        let (c2, no32, pinvsq32) = (cosio2.to_f32(), no.to_f32(), pinvsq.to_f32());
        let c4 = c2 * c2;
        let temp2 = 0.5 * temp1.to_f32() * g.j2.to_f32() * pinvsq32;
        let temp3 = -0.46875 * g.j4.to_f32() * pinvsq32 * pinvsq32 * no32;
        let rteosq32 = rteosq.to_f32();
        let mdot = &(&no + &(&(&(0.5 * &temp1) * &rteosq) * &con41))
            + 0.0625 * temp2 * rteosq32 * (13.0 - 78.0 * c2 + 137.0 * c4);
        let argpdot = &(&(-0.5 * &temp1) * &con42)
            + (0.0625 * temp2 * (7.0 - 114.0 * c2 + 395.0 * c4)
                + temp3 * (3.0 - 36.0 * c2 + 49.0 * c4));
        let nodedot = &xhdot1
            + (0.5 * temp2 * (4.0 - 19.0 * c2) + 2.0 * temp3 * (3.0 - 7.0 * c2)) * cosio.to_f32();

        // drag reference height and the perigee-relative quantities, double-f32: a − s and
        // 1 − η² cancel for low perigees (f32 there puts 22312 160 m off)
        // (in a block, returning f32: its double-f32 temporaries leave the stack frame)
        let (isimp, sfour, tsi, eta, etasq, eeta, psisq, coef, coef1, cc1) = {
            let rp = &ao * &(1.0 - &ecco);
            let isimp = !((&rp - &(&(220.0 / &radius_km) + 1.0)).hi() >= 0.0);
            let perige = &(&rp - 1.0) * &radius_km;
            let (sfour, qzms24) = if !(perige.hi() >= 156.0) {
                let s = if !(perige.hi() >= 98.0) {
                    Df::from_f32(20.0)
                } else {
                    &perige - 78.0
                };
                (
                    &(&s / &radius_km) + 1.0,
                    fourth_power(&(&(120.0 - &s) / &radius_km)),
                )
            } else {
                (
                    &(78.0 / &radius_km) + 1.0,
                    fourth_power(&((120.0 - 78.0) / &radius_km)),
                )
            };
            let tsi = 1.0 / &(&ao - &sfour);
            let eta = &(&ao * &ecco) * &tsi;
            let etasq = &eta * &eta;
            let eeta = &ecco * &eta;
            let psisq = (1.0 - &etasq).to_f32();
            let psisq = Df::from_f32(fmath::abs(psisq)); // |1 − η²|
            let coef = &qzms24 * &fourth_power(&tsi);
            // C₁ = B*·C₂ scales the mean-longitude drag t²·(3/2)C₁ (radians after a day for a
            // decaying orbit): double-f32 too. psisq^3.5 as psisq³·√psisq.
            let coef1 = &coef / &(&(&(&psisq * &psisq) * &psisq) * &psisq.sqrt());
            // C₂ = coef1·n₀″·(a₀″(1 + 1.5η² + eη(4 + η²)) + 0.375J₂·ξ/ψ²·con41·(8 + 3η²(8 + η²)))
            let a_term = &ao * &(&(1.0 + &(1.5 * &etasq)) + &(&eeta * &(4.0 + &etasq)));
            let j2_term = &(&(&(&(0.375 * &g.j2) * &tsi) / &psisq) * &con41)
                * &(8.0 + &(&(3.0 * &etasq) * &(8.0 + &etasq)));
            let cc2 = &(&coef1 * &no) * &(&a_term + j2_term.to_f32());
            let cc1 = (&bstar * &cc2).to_f32();
            (
                isimp,
                sfour.to_f32(),
                tsi.to_f32(),
                eta.to_f32(),
                etasq.to_f32(),
                eeta.to_f32(),
                psisq.to_f32(),
                coef.to_f32(),
                coef1.to_f32(),
                cc1,
            )
        };

        // sgp4init, drag and periodic coefficients: f32 (they multiply small terms)
        let re = radius_km.to_f32();
        let j2 = g.j2.to_f32();
        let j3oj2 = (&g.j3 / &g.j2).to_f32();
        let ao_km = (&ao * &radius_km).to_f32();
        let one_plus_cosio = (&cosio + 1.0).to_f32(); // no cancellation near i₀ = 180°
        let (ao, ecco, bstar) = (ao.to_f32(), ecco.to_f32(), bstar.to_f32());
        let (cosio, omeosq, con41) = (cosio.to_f32(), omeosq.to_f32(), con41.to_f32());
        let sinio = fmath::sqrt(fmath::abs((1.0 - &cosio2).to_f32())); // ≥ 0 for 0 ≤ i₀ ≤ 180°
        let large_ecc = ecco > 1.0e-4;
        let cc3 = if large_ecc {
            -2.0 * coef * tsi * j3oj2 * no32 * sinio / ecco
        } else {
            0.0
        };
        let x1mth2 = 1.0 - c2;
        let (sin_argpo, cos_argpo) = sincos_degrees(&argpo_deg);
        let cos_2argpo = 1.0 - 2.0 * sin_argpo * sin_argpo;
        let cc4 = 2.0
            * no32
            * coef1
            * ao
            * omeosq
            * (eta * (2.0 + 0.5 * etasq) + ecco * (0.5 + 2.0 * etasq)
                - j2 * tsi / (ao * psisq)
                    * (-3.0 * con41 * (1.0 - 2.0 * eeta + etasq * (1.5 - 0.5 * eeta))
                        + 0.75 * x1mth2 * (2.0 * etasq - eeta * (1.0 + etasq)) * cos_2argpo));
        let cc5 = 2.0 * coef1 * ao * omeosq * (1.0 + 2.75 * (etasq + eeta) + eeta * etasq);
        let omgcof = bstar * cc3 * cos_argpo;
        let xmcof = if large_ecc {
            -2.0 / 3.0 * coef * bstar / eeta
        } else {
            0.0
        };
        let nodecf = 3.5 * omeosq * xhdot1.to_f32() * cc1;
        let t2cof = 1.5 * cc1;
        // Vallado's guard against division by zero at i = 180°
        let one_plus_cosio = if fmath::abs(one_plus_cosio) > 1.5e-12 {
            one_plus_cosio
        } else {
            1.5e-12
        };
        let xlcof = -0.25 * j3oj2 * sinio * (3.0 + 5.0 * cosio) / one_plus_cosio;
        let aycof = -0.5 * j3oj2 * sinio;
        let (sinmao, cos_mo) = sincos_degrees(&mo_deg);
        let delmo = cube(1.0 + eta * cos_mo);
        let x7thm1 = 7.0 * c2 - 1.0;
        let full_drag = if isimp {
            None
        } else {
            let cc1sq = cc1 * cc1;
            let d2 = 4.0 * ao * tsi * cc1sq;
            let temp = d2 * tsi * cc1 / 3.0;
            let d3 = (17.0 * ao + sfour) * temp;
            let d4 = 0.5 * temp * ao * tsi * (221.0 * ao + 31.0 * sfour) * cc1;
            Some(FullDrag {
                d2,
                d3,
                d4,
                t3cof: d2 + 2.0 * cc1sq,
                t4cof: 0.25 * (3.0 * d3 + cc1 * (12.0 * d2 + 10.0 * cc1sq)),
                t5cof: 0.2
                    * (3.0 * d4
                        + 12.0 * cc1 * d3
                        + 6.0 * d2 * d2
                        + 15.0 * cc1sq * (2.0 * d2 + cc1sq)),
                cc5,
                omgcof,
                xmcof,
                eta,
                delmo,
                sinmao,
            })
        };

        // secular angles as exact phases, in turns
        let mo = turns_of_degrees(&mo_deg);
        let argpo = turns_of_degrees(&argpo_deg);
        let sgp4 = Self {
            epoch: tle.epoch,
            radius_km: re,
            xke: g.xke.to_f32(),
            j2,
            ao_km,
            v_scale_kmps: (&(&radius_km * &g.xke) / 60.0).to_f32(),
            mean_anomaly: Phase::from_turns(&mo, &(&mdot * &INV_TAU)),
            arg_perigee: Phase::from_turns(&argpo, &(&argpdot * &INV_TAU)),
            node: Phase::from_turns(&turns_of_degrees(&nodeo_deg), &(&nodedot * &INV_TAU)),
            arg_latitude: Phase::from_turns(&(&mo + &argpo), &(&(&mdot + &argpdot) * &INV_TAU)),
            no: no32,
            ao,
            ecco,
            bstar,
            cosio,
            sinio,
            con41,
            x1mth2,
            x7thm1,
            cc1,
            cc4,
            nodecf,
            t2cof,
            xlcof,
            aycof,
            full_drag,
        };
        if !sgp4.coefficients_finite() {
            // e.g. η = 1 exactly (perigee at the drag reference height): a singular model
            return Err(Sgp4Error::Element {
                field: "eccentricity and perigee (singular drag coefficients)",
            });
        }
        sgp4.propagate_whole_frac(0, 0.0)?;
        Ok(sgp4)
    }

    /// Whether the stored coefficients are finite (field by field: no copy into an array).
    fn coefficients_finite(&self) -> bool {
        let common = finite32(self.no)
            && finite32(self.ao)
            && finite32(self.cc1)
            && finite32(self.cc4)
            && finite32(self.nodecf)
            && finite32(self.t2cof)
            && finite32(self.xlcof)
            && finite32(self.aycof);
        common
            && self.full_drag.as_ref().is_none_or(|d| {
                finite32(d.d2)
                    && finite32(d.d3)
                    && finite32(d.d4)
                    && finite32(d.t3cof)
                    && finite32(d.t4cof)
                    && finite32(d.t5cof)
                    && finite32(d.cc5)
                    && finite32(d.omgcof)
                    && finite32(d.xmcof)
                    && finite32(d.eta)
                    && finite32(d.delmo)
                    && finite32(d.sinmao)
            })
    }
}

/// `x^(2/3)` for x > 0, as `cbrt(x)²` (double-f32).
fn two_thirds_power(x: &Df) -> Df {
    let c = x.cbrt();
    &c * &c
}

fn fourth_power(x: &Df) -> Df {
    let s = x * x;
    &s * &s
}

fn cube(x: f32) -> f32 {
    x * x * x
}
