//! SGP4 propagation: position and velocity at a time since the element set's epoch (Vallado's
//! `sgp4`, near-Earth).

use super::{finite32, Sgp4, Sgp4Error};
use crate::fmath;
use crate::linalg::Vec3;
use crate::orbit::{split_span, TemeState};
use crate::time::TimeSpan;

/// Largest |time since epoch| accepted by [`Sgp4::propagate_split`], minutes.
const MAX_TSINCE_MIN: f32 = 1.0e9;
/// Newton tolerance of Kepler's equation: a few f32 ulps of an angle of order π.
const KEPLER_TOLERANCE: f32 = 1.0e-6;
/// Newton iterations at most (Vallado's cap).
const KEPLER_MAX_ITERATIONS: usize = 10;

impl Sgp4 {
    /// Position and velocity `since_epoch` after the element set's epoch (UTC days of 86 400 s,
    /// as SGP4 counts them).
    ///
    /// # Errors
    /// [`Sgp4Error::Eccentricity`], [`Sgp4Error::SemiLatusRectum`], [`Sgp4Error::Decayed`] as
    /// Vallado's `sgp4`; [`Sgp4Error::Diverged`] if the result is not finite.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn propagate(&self, since_epoch: TimeSpan) -> Result<TemeState, Sgp4Error> {
        let (whole, frac) = split_span(since_epoch, 60);
        self.propagate_whole_frac(whole, frac)
    }

    /// As [`Sgp4::propagate`], for a time since epoch given as an f32 split pair
    /// `whole_min + frac_min` (such as [`TimeSpan::split_minutes`] returns; `whole_min` should be
    /// an integer for full precision, any fractional part is moved into `frac_min`).
    ///
    /// # Errors
    /// [`Sgp4Error::Time`] for a non-finite pair or |`whole_min`| > 10⁹; otherwise as
    /// [`Sgp4::propagate`].
    pub fn propagate_split(&self, whole_min: f32, frac_min: f32) -> Result<TemeState, Sgp4Error> {
        let t = whole_min + frac_min;
        if !t.is_finite() || fmath::abs(whole_min) > MAX_TSINCE_MIN {
            return Err(Sgp4Error::Time { tsince_min: t });
        }
        let w = fmath::floor(whole_min);
        let frac = (whole_min - w) + frac_min;
        let w2 = fmath::floor(frac);
        // |w| ≤ 1e9 and |frac| is finite but may be large: saturating conversions
        let whole = (w as i32).saturating_add(w2 as i32);
        self.propagate_whole_frac(whole, frac - w2)
    }

    /// The propagation proper (Vallado's `sgp4`, near-Earth), `t = whole + frac` minutes.
    pub(super) fn propagate_whole_frac(
        &self,
        whole: i32,
        frac: f32,
    ) -> Result<TemeState, Sgp4Error> {
        let t = whole as f32 + frac;
        let t2 = t * t;

        // Secular gravity and drag: angles from their exact phases (−π..π)
        let xmdf = self.mean_anomaly.radians(whole, frac);
        let argpdf = self.arg_perigee.radians(whole, frac);
        let nodedf = self.node.radians(whole, frac);
        // Ω = Ω₀ + Ω̇t + nodecf·t²
        let nodem = nodedf + self.nodecf * t2;
        let mut tempa = 1.0 - self.cc1 * t;
        let mut tempe = self.bstar * self.cc4 * t;
        let mut templ = self.t2cof * t2;
        let mut argpm = argpdf;
        if let Some(d) = &self.full_drag {
            // δω = ω-cof·t; δM = M-cof·((1 + η cos M_df)³ − (1 + η cos M₀)³)
            let delomg = d.omgcof * t;
            // `sincos` rather than `cos` (bit-identical, see `fmath::sincos`): SGP4 was the only
            // caller of `cos` in the flight image: 954 B of code for ≈ 2 900 cycles
            let delm = d.xmcof * (cube32(1.0 + d.eta * fmath::sincos(xmdf).1) - d.delmo);
            let temp = delomg + delm;
            let mm = xmdf + temp;
            argpm = argpdf - temp;
            let t3 = t2 * t;
            let t4 = t3 * t;
            tempa = tempa - d.d2 * t2 - d.d3 * t3 - d.d4 * t4;
            tempe += self.bstar * d.cc5 * (fmath::sin(mm) - d.sinmao);
            templ += d.t3cof * t3 + t4 * (d.t4cof + t * d.t5cof);
        }
        // a = a₀″·tempa², n = kₑ/a^1.5 = n₀″/|tempa|³
        let am = self.ao * tempa * tempa;
        let nm = self.no / fmath::abs(tempa * tempa * tempa);
        let mut em = self.ecco - tempe;
        if !(em >= -0.001) || em >= 1.0 {
            return Err(Sgp4Error::Eccentricity {
                eccentricity: em,
                tsince_min: t,
            });
        }
        if !(em >= 1.0e-6) {
            em = 1.0e-6;
        }

        // Long-period periodics
        let (sin_argp, cos_argp) = fmath::sincos(argpm);
        let axnl = em * cos_argp;
        let temp = 1.0 / (am * (1.0 - em * em));
        let aynl = em * sin_argp + temp * self.aycof;
        // u = M + ω + n₀″·templ + xlcof-term, from the exact M + ω phase (δω and δM cancel)
        let u = self.arg_latitude.radians(whole, frac) + self.no * templ + temp * self.xlcof * axnl;

        // Kepler's equation for E + ω, Newton with steps clamped to ±0.95 rad
        let mut eo1 = u;
        let (mut sineo1, mut coseo1) = fmath::sincos(eo1);
        for _ in 0..KEPLER_MAX_ITERATIONS {
            let denom = 1.0 - coseo1 * axnl - sineo1 * aynl;
            let step = fmath::max(
                fmath::min((u - aynl * coseo1 + axnl * sineo1 - eo1) / denom, 0.95),
                -0.95,
            );
            eo1 += step;
            if !(fmath::abs(step) >= KEPLER_TOLERANCE) {
                // sin and cos of eo1 to first order in the (tiny) last step
                let s = sineo1 + coseo1 * step;
                coseo1 -= sineo1 * step;
                sineo1 = s;
                break;
            }
            (sineo1, coseo1) = fmath::sincos(eo1);
        }

        // Short-period preliminary quantities
        let ecose = axnl * coseo1 + aynl * sineo1;
        let esine = axnl * sineo1 - aynl * coseo1;
        let el2 = axnl * axnl + aynl * aynl;
        let pl = am * (1.0 - el2);
        if !(pl >= 0.0) {
            return Err(Sgp4Error::SemiLatusRectum { tsince_min: t });
        }
        let rl = am * (1.0 - ecose);
        let rdotl = fmath::sqrt(am) * esine / rl;
        let rvdotl = fmath::sqrt(pl) / rl;
        let betal = fmath::sqrt(1.0 - el2);
        let temp = esine / (1.0 + betal);
        let sinu = am / rl * (sineo1 - aynl - axnl * temp);
        let cosu = am / rl * (coseo1 - axnl + aynl * temp);
        let sin2u = (cosu + cosu) * sinu;
        let cos2u = 1.0 - 2.0 * sinu * sinu;
        let temp = 1.0 / pl;
        let temp1 = 0.5 * self.j2 * temp;
        let temp2 = temp1 * temp;

        // Short-period periodics
        // r_k = r_l(1 − 1.5·temp2·β_l·con41) + ½·temp1·x1mth2·cos 2u, in km with r_l = a(1 − e cos E)
        // and a = a₀″·tempa² scaled by the once-rounded a₀″ in km
        let r_km =
            self.ao_km * tempa * tempa * (1.0 - ecose) * (1.0 - 1.5 * temp2 * betal * self.con41)
                + 0.5 * temp1 * self.x1mth2 * cos2u * self.radius_km;
        // u_k = u − ¼·temp2·(7cos²i₀ − 1)·sin 2u, applied as a rotation of (sin u, cos u) (no
        // atan2, and u is never rounded to an f32 angle); (sinu, cosu) has unit norm to rounding,
        // restored by one Newton step of 1/√
        let dsu = -0.25 * temp2 * self.x7thm1 * sin2u;
        let norm = 1.5 - 0.5 * (sinu * sinu + cosu * cosu);
        let (sin_d, cos_d) = small_sincos(dsu);
        let sinsu = norm * (sinu * cos_d + cosu * sin_d);
        let cossu = norm * (cosu * cos_d - sinu * sin_d);
        let xnode = nodem + 1.5 * temp2 * self.cosio * sin2u;
        let xinc_delta = 1.5 * temp2 * self.cosio * self.sinio * cos2u;
        let mvt = rdotl - nm * temp1 * self.x1mth2 * sin2u / self.xke;
        let rvdot = rvdotl + nm * temp1 * (self.x1mth2 * cos2u + 1.5 * self.con41) / self.xke;

        // Orientation vectors
        let (snod, cnod) = fmath::sincos(xnode);
        // sin and cos of i = i₀ + δi from those of i₀ (δi is of order J₂)
        let (sdi, cdi) = small_sincos(xinc_delta);
        let sini = self.sinio * cdi + self.cosio * sdi;
        let cosi = self.cosio * cdi - self.sinio * sdi;
        let xmx = -snod * cosi;
        let xmy = cnod * cosi;
        let ux = xmx * sinsu + cnod * cossu;
        let uy = xmy * sinsu + snod * cossu;
        let uz = sini * sinsu;
        let vx = xmx * cossu - cnod * sinsu;
        let vy = xmy * cossu - snod * sinsu;
        let vz = sini * cossu;

        let v_scale = self.v_scale_kmps;
        let state = TemeState {
            r_teme_km: Vec3::new(ux, uy, uz) * r_km,
            v_teme_kmps: Vec3::new(
                mvt * ux + rvdot * vx,
                mvt * uy + rvdot * vy,
                mvt * uz + rvdot * vz,
            ) * v_scale,
        };
        // component by component from the bits (the iterators were two loops on the MSP430)
        let (r, v) = (&state.r_teme_km, &state.v_teme_kmps);
        if !(finite32(r.x)
            && finite32(r.y)
            && finite32(r.z)
            && finite32(v.x)
            && finite32(v.y)
            && finite32(v.z))
        {
            return Err(Sgp4Error::Diverged { tsince_min: t });
        }
        // mrt < 1 (radius below one Earth radius)
        if !(r_km >= self.radius_km) {
            return Err(Sgp4Error::Decayed {
                tsince_min: t,
                radius_km: r_km,
            });
        }
        Ok(state)
    }
}

/// `(sin x, cos x)` of a small angle: a Taylor series to x³ for |x| < 0.01 rad (exact in f32,
/// the short-period corrections are of order J₂ ≈ 1e-3), `fmath::sincos` otherwise.
fn small_sincos(x: f32) -> (f32, f32) {
    if !(fmath::abs(x) >= 0.01) {
        let x2 = x * x;
        (x * (1.0 - x2 / 6.0), 1.0 - 0.5 * x2)
    } else {
        fmath::sincos(x)
    }
}

fn cube32(x: f32) -> f32 {
    x * x * x
}
