//! Sun models against JPL DE421 (`tests/data/sun/sun_de421.csv`) and the thesis's numbers.
//!
//! Run with `cargo test --test sun -- --nocapture` to read the error statistics quoted in
//! `docs/accuracy.md`.

mod common;
mod figures;

use acs::env::sun::{precise, schlyter, SunError};
use acs::time::{Calendar, Epoch, TimeError, Tt, Utc};
use common::data_path;

/// Parses `YYYY-MM-DDTHH:MM:SS[.fff]Z`.
fn parse_utc(s: &str) -> Epoch<Utc> {
    let s = s.trim().trim_end_matches('Z');
    let (date, time) = s.split_once('T').unwrap();
    let mut d = date.split('-').map(|x| x.parse::<i64>().unwrap());
    let (year, month, day) = (d.next().unwrap(), d.next().unwrap(), d.next().unwrap());
    let mut t = time.split(':');
    let hour: u8 = t.next().unwrap().parse().unwrap();
    let minute: u8 = t.next().unwrap().parse().unwrap();
    let sec = t.next().unwrap();
    let (whole, frac) = sec.split_once('.').unwrap_or((sec, ""));
    let nano = if frac.is_empty() {
        0
    } else {
        let digits = format!("{frac:0<9}");
        digits[..9].parse::<u32>().unwrap()
    };
    Epoch::from_calendar(Calendar {
        year: year as i32,
        month: month as u8,
        day: day as u8,
        hour,
        minute,
        second: whole.parse().unwrap(),
        nano,
    })
    .unwrap()
}

struct Row {
    utc: Epoch<Utc>,
    label: String,
    dir: [f64; 3],
    dist_au: f64,
    thesis_ra_deg: f64,
    thesis_dec_deg: f64,
}

fn rows() -> Vec<Row> {
    let path = data_path("sun/sun_de421.csv");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with('#') || line.starts_with("utc") || line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| f[i].parse::<f64>().unwrap();
        out.push(Row {
            utc: parse_utc(f[0]),
            label: f[0].to_string(),
            dir: [num(1), num(2), num(3)],
            dist_au: num(4),
            thesis_ra_deg: num(5),
            thesis_dec_deg: num(6),
        });
    }
    assert_eq!(out.len(), 400, "reference rows");
    out
}

/// Angle between two vectors, arcseconds (atan2 form, accurate for tiny angles).
fn angle_arcsec(a: [f64; 3], b: [f64; 3]) -> f64 {
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let c = (cross[0].powi(2) + cross[1].powi(2) + cross[2].powi(2)).sqrt();
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    c.atan2(d).to_degrees() * 3600.0
}

fn to_f64(v: &acs::linalg::Vec3) -> [f64; 3] {
    [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
}

fn ra_dec_deg(v: [f64; 3]) -> (f64, f64) {
    let ra = v[1].atan2(v[0]).to_degrees().rem_euclid(360.0);
    let dec = v[2].atan2(v[0].hypot(v[1])).to_degrees();
    (ra, dec)
}

/// Difference of two angles in degrees, wrapped to −180..180.
fn dangle_deg(a: f64, b: f64) -> f64 {
    (a - b + 540.0).rem_euclid(360.0) - 180.0
}

struct Stats {
    max: f64,
    sum_sq: f64,
    n: usize,
    worst: String,
}

impl Stats {
    fn new() -> Self {
        Self {
            max: 0.0,
            sum_sq: 0.0,
            n: 0,
            worst: String::new(),
        }
    }
    fn add(&mut self, e: f64, label: &str) {
        if e > self.max {
            self.max = e;
            self.worst = label.to_string();
        }
        self.sum_sq += e * e;
        self.n += 1;
    }
    fn rms(&self) -> f64 {
        (self.sum_sq / self.n as f64).sqrt()
    }
}

/// The usual low-precision formula (Astronomical Almanac, "Low precision formulas for the Sun",
/// section C; also Meeus ch. 25 "low accuracy"), in f64: apparent Sun, equator and equinox of date.
fn low_precision(utc: &Epoch<Utc>) -> [f64; 3] {
    let (jd0, fr) = utc.jd_split();
    let n = (jd0 - 2_451_545.0) + fr;
    let l = 280.460 + 0.985_647_4 * n;
    let g = (357.528 + 0.985_600_3 * n).to_radians();
    let lam = (l + 1.915 * g.sin() + 0.020 * (2.0 * g).sin()).to_radians();
    let eps = (23.439 - 0.000_000_4 * n).to_radians();
    [lam.cos(), lam.sin() * eps.cos(), lam.sin() * eps.sin()]
}

#[test]
fn precise_within_15_arcsec_of_de421_on_every_row() {
    let mut dir = Stats::new();
    let mut dist = Stats::new();
    for row in rows() {
        let sun = precise::sun(&row.utc).unwrap();
        assert_eq!(
            sun,
            precise::sun_tt(&row.utc.to_tt_extrapolated().unwrap()).unwrap()
        );
        let e = angle_arcsec(to_f64(&sun.direction), row.dir);
        dir.add(e, &row.label);
        dist.add((f64::from(sun.distance_au) - row.dist_au).abs(), &row.label);
        let norm = to_f64(&sun.direction)
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        assert!((norm - 1.0).abs() < 1e-6, "{}: |s| = {norm}", row.label);
        assert!(e <= 15.0, "{}: precise Sun off by {e:.2}″", row.label);
        assert!(
            (f64::from(sun.distance_au) - row.dist_au).abs() <= 2e-5,
            "{}: distance {} vs {}",
            row.label,
            sun.distance_au,
            row.dist_au
        );
    }
    figures::figure("sun.precise.n", dir.n);
    figures::figure("sun.precise.max_arcsec", dir.max);
    figures::figure("sun.precise.rms_arcsec", dir.rms());
    figures::figure("sun.precise.distance_max_au", dist.max);
    println!(
        "precise vs DE421 (TEME of date, {} rows): max {:.2}″ (at {}), RMS {:.2}″; distance max {:.2e} AU, RMS {:.2e} AU",
        dir.n, dir.max, dir.worst, dir.rms(), dist.max, dist.rms()
    );
}

#[test]
fn thesis_model_matches_its_f64_values_in_the_csv() {
    let mut ra = Stats::new();
    let mut dec = Stats::new();
    let mut vs_de421 = Stats::new();
    let mut low = Stats::new();
    for row in rows() {
        let sun = schlyter::sun(&row.utc).unwrap();
        let (r, d) = ra_dec_deg(to_f64(&sun.direction));
        let e_ra = dangle_deg(r, row.thesis_ra_deg).abs();
        let e_dec = (d - row.thesis_dec_deg).abs();
        ra.add(e_ra, &row.label);
        dec.add(e_dec, &row.label);
        // f32 evaluation of Schlyter's formula: its angles near 2π carry 5e-7 rad rounding.
        assert!(
            e_ra < 1e-4 && e_dec < 1e-4,
            "{}: RA {e_ra}°, Dec {e_dec}°",
            row.label
        );
        vs_de421.add(angle_arcsec(to_f64(&sun.direction), row.dir), &row.label);
        low.add(angle_arcsec(low_precision(&row.utc), row.dir), &row.label);
    }
    figures::figure("sun.thesis.f64_ra_max_deg", ra.max);
    figures::figure("sun.thesis.f64_dec_max_deg", dec.max);
    figures::figure("sun.thesis.max_arcsec", vs_de421.max);
    figures::figure("sun.thesis.rms_arcsec", vs_de421.rms());
    figures::figure("sun.almanac.max_arcsec", low.max);
    figures::figure("sun.almanac.rms_arcsec", low.rms());
    println!(
        "thesis f32 vs thesis f64 (CSV): RA max {:.2e}° RMS {:.2e}°, Dec max {:.2e}° RMS {:.2e}°",
        ra.max,
        ra.rms(),
        dec.max,
        dec.rms()
    );
    println!(
        "thesis vs DE421: max {:.2}″ (at {}), RMS {:.2}″",
        vs_de421.max,
        vs_de421.worst,
        vs_de421.rms()
    );
    println!(
        "low-precision formula (Astronomical Almanac, f64, no TEME rotation) vs DE421: max {:.2}″ (at {}), RMS {:.2}″",
        low.max,
        low.worst,
        low.rms()
    );
}

/// Seed 000 §7.1.2 / note 000 §4.1 and §4.2: the thesis's printed values.
#[test]
fn thesis_values() {
    // 14 Aug 2009 00:00 UT: RA 9h34m56.76s, Dec 14°22′57.1″ (thesis algorithm, note 000 §4.1).
    let sun = schlyter::sun(&parse_utc("2009-08-14T00:00:00Z")).unwrap();
    let (ra, dec) = ra_dec_deg(to_f64(&sun.direction));
    let ra_expected = (9.0 + 34.0 / 60.0 + 56.76 / 3600.0) * 15.0;
    let dec_expected = 14.0 + 22.0 / 60.0 + 57.1 / 3600.0;
    println!("almanac check: RA {ra:.6}° (thesis {ra_expected:.6}°), Dec {dec:.6}° (thesis {dec_expected:.6}°)");
    assert!(dangle_deg(ra, ra_expected).abs() < 2e-4);
    assert!((dec - dec_expected).abs() < 2e-4);
    // Chapter 12, 16 Jun 2009 00:00 UT: RA 84.553993°, Dec 23.343618° (note 000 §4.2).
    let sun = schlyter::sun(&parse_utc("2009-06-16T00:00:00Z")).unwrap();
    let (ra, dec) = ra_dec_deg(to_f64(&sun.direction));
    println!("chapter 12: RA {ra:.6}° (thesis 84.553993°), Dec {dec:.6}° (thesis 23.343618°)");
    assert!(dangle_deg(ra, 84.553_993).abs() < 2e-4);
    assert!((dec - 23.343_618).abs() < 2e-4);
    // Ŝ = [0.087139019396207, 0.914000557233585, 0.396244586935094] (note 000 §4.2).
    let s = to_f64(&sun.direction);
    let expected = [
        0.087_139_019_396_207,
        0.914_000_557_233_585,
        0.396_244_586_935_094,
    ];
    assert!(angle_arcsec(s, expected) < 1.0, "{s:?}");
}

#[test]
fn out_of_range_years_are_errors_not_panics() {
    let tt = |y: i32| Epoch::<Tt>::from_parts(acs::time::days_from_civil(y, 6, 1), 0, 0).unwrap();
    assert_eq!(precise::sun_tt(&tt(1949)), Err(SunError::Year(1949)));
    assert_eq!(precise::sun_tt(&tt(2101)), Err(SunError::Year(2101)));
    assert!(precise::sun_tt(&tt(1950)).is_ok());
    assert!(precise::sun_tt(&tt(2100)).is_ok());
    for day in [i32::MIN, i32::MIN + 1, -1_000_000, 1_000_000, i32::MAX] {
        for second in [0, 43_200, 86_400] {
            let e = Epoch::<Tt>::from_parts(day, second, 999_999_999).unwrap();
            assert!(matches!(precise::sun_tt(&e), Err(SunError::Year(_))));
            let u = Epoch::<Utc>::from_parts(day, second, 999_999_999).unwrap();
            assert!(matches!(schlyter::sun(&u), Err(SunError::Year(_))));
        }
    }
    let u = |y: i32| Epoch::<Utc>::from_parts(acs::time::days_from_civil(y, 1, 1), 0, 0).unwrap();
    // UTC input: no leap-second UTC before 1972; after 2100 the model's range ends.
    assert!(matches!(
        precise::sun(&u(1971)),
        Err(SunError::Time(TimeError::BeforeLeapSeconds(_)))
    ));
    assert!(precise::sun(&u(1972)).is_ok());
    assert!(precise::sun(&u(2100)).is_ok());
    assert_eq!(precise::sun(&u(2101)), Err(SunError::Year(2101)));
    let not_leap = Epoch::<Utc>::from_parts(acs::time::days_from_civil(2010, 3, 1), 86_400, 0);
    assert!(matches!(
        precise::sun(&not_leap.unwrap()),
        Err(SunError::Time(_))
    ));
    assert_eq!(schlyter::sun(&u(1899)), Err(SunError::Year(1899)));
    assert!(schlyter::sun(&u(2100)).is_ok());
}

/// Every instant of the valid range at a coarse step gives a unit vector and a sane distance.
#[test]
fn whole_range_is_finite() {
    let start = acs::time::days_from_civil(1950, 1, 1);
    let stop = acs::time::days_from_civil(2100, 12, 31);
    let mut day = start;
    while day <= stop {
        let e = Epoch::<Tt>::from_parts(day, 86_400, 0).unwrap();
        let s = precise::sun_tt(&e).unwrap();
        assert!((s.direction.norm() - 1.0).abs() < 1e-6);
        assert!(
            (0.98..1.02).contains(&s.distance_au),
            "{day}: {}",
            s.distance_au
        );
        let s = schlyter::sun(&e.relabel()).unwrap();
        assert!((s.direction.norm() - 1.0).abs() < 1e-6);
        day += 37;
    }
}

/// `acs sun` end to end: the CSV's timestamps in, the contract's CSV out, within the bound.
#[cfg(feature = "host")]
#[test]
fn cli_acs_sun() {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let run = |args: &[&str], input: &str| {
        let mut child = Command::new(env!("CARGO_BIN_EXE_acs"))
            .arg("sun")
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        child
            .stdin
            .take()
            .unwrap()
            .write_all(input.as_bytes())
            .unwrap();
        let out = child.wait_with_output().unwrap();
        (
            out.status.code().unwrap(),
            String::from_utf8(out.stdout).unwrap(),
            String::from_utf8(out.stderr).unwrap(),
        )
    };
    let rows = rows();
    let input: String = std::iter::once("# comment\n\n".to_string())
        .chain(rows.iter().map(|r| format!("{}\n", r.label)))
        .collect();
    let (code, stdout, stderr) = run(&[], &input);
    assert_eq!(code, 0, "{stderr}");
    let mut lines = stdout.lines();
    assert_eq!(lines.next(), Some("utc,x,y,z,dist_au"));
    let mut n = 0;
    for (line, row) in lines.zip(&rows) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f[0], row.label);
        for x in &f[1..] {
            let mantissa = x.split('e').next().unwrap().replace(['-', '.'], "");
            assert!(mantissa.len() >= 9, "{x}: fewer than 9 significant digits");
        }
        let v: Vec<f64> = f[1..].iter().map(|x| x.parse().unwrap()).collect();
        assert!(angle_arcsec([v[0], v[1], v[2]], row.dir) <= 15.0, "{line}");
        assert!((v[3] - row.dist_au).abs() <= 2e-5);
        n += 1;
    }
    assert_eq!(n, rows.len());
    // The thesis model gives the CSV's thesis RA/Dec.
    let (code, stdout, _) = run(&["--model", "thesis"], "2009-08-14T00:00:00Z\n");
    assert_eq!(code, 0);
    let v: Vec<f64> = stdout
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    let (ra, _) = ra_dec_deg([v[0], v[1], v[2]]);
    assert!(dangle_deg(ra, 143.7365).abs() < 2e-4);
    // --frame j2000: the TEME output rotated by crate::frames' TEME → J2000 matrix.
    let (code, stdout, _) = run(&["--frame", "j2000"], &input);
    assert_eq!(code, 0);
    for (line, row) in stdout.lines().skip(1).zip(&rows) {
        let v: Vec<f64> = line
            .split(',')
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect();
        let tt = row.utc.to_tt_extrapolated().unwrap();
        let m = acs::frames::teme_to_j2000_matrix::<f64>(&tt);
        let teme = m.transpose() * acs::linalg::Vec3d::new(v[0], v[1], v[2]);
        assert!(
            angle_arcsec([teme.x, teme.y, teme.z], row.dir) <= 15.0,
            "{line}"
        );
    }
    // Bad input: exit 2 naming the line; out of range: exit 3.
    let (code, _, stderr) = run(&[], "2009-06-16T00:00:00Z\n2009-13-01T00:00:00Z\n");
    assert_eq!(code, 2);
    assert!(stderr.contains("line 2"), "{stderr}");
    let (code, _, stderr) = run(&[], "1965-01-01T00:00:00Z\n");
    assert_eq!(code, 3, "{stderr}");
    let (code, _, _) = run(&["--model", "bogus"], "");
    assert_eq!(code, 2);
}

/// The full abridged VSOP87D of Meeus (appendix III, `tests/data/vsop87_meeus_earth.csv`, good
/// to about 1″ over millennia) with the same nutation, aberration and TEME rotation, in f64.
fn full_series_teme(tt: &Epoch<Tt>, table: &[(String, f64, f64, f64)]) -> [f64; 3] {
    let t = tt.julian_centuries_since_j2000_f64();
    let tau = t / 10.0;
    let series = |prefix: char| -> f64 {
        let mut total = 0.0;
        for power in 0..6 {
            let name = format!("{prefix}{power}");
            let sum: f64 = table
                .iter()
                .filter(|r| r.0 == name)
                .map(|r| r.1 * (r.2 + r.3 * tau).cos())
                .sum();
            total += sum * tau.powi(power);
        }
        total * 1e-8
    };
    let (l, b, r) = (series('L'), series('B'), series('R'));
    let arcsec = std::f64::consts::PI / 648_000.0;
    let nut = acs::frames::nutation::nutation(t);
    let lam = l + std::f64::consts::PI - 0.090_33 * arcsec + nut.dpsi_rad - 20.4898 * arcsec / r;
    let beta = -b;
    let eps = nut.true_obliquity_rad();
    let (x, y, z) = (
        beta.cos() * lam.cos(),
        beta.cos() * lam.sin() * eps.cos() - beta.sin() * eps.sin(),
        beta.cos() * lam.sin() * eps.sin() + beta.sin() * eps.cos(),
    );
    let e = nut.equation_of_equinoxes_rad();
    [x * e.cos() + y * e.sin(), -x * e.sin() + y * e.cos(), z]
}

/// The truncation of `precise` against the full abridged series over its whole range
/// (1950–2100, every 5 days), and the full series against DE421 (the model's floor).
#[test]
fn precise_truncation_over_1950_2100() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/vsop87_meeus_earth.csv"
    ))
    .unwrap();
    let table: Vec<(String, f64, f64, f64)> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("series"))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].to_string(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect();
    assert_eq!(table.len(), 195);
    let mut floor = Stats::new();
    for row in rows() {
        let tt = row.utc.to_tt_extrapolated().unwrap();
        floor.add(
            angle_arcsec(full_series_teme(&tt, &table), row.dir),
            &row.label,
        );
    }
    let mut trunc = Stats::new();
    let start = acs::time::days_from_civil(1950, 1, 1);
    let stop = acs::time::days_from_civil(2100, 12, 31);
    let mut day = start;
    while day <= stop {
        let tt = Epoch::<Tt>::from_parts(day, (day.rem_euclid(17) as u32) * 5000, 0).unwrap();
        let got = to_f64(&precise::sun_tt(&tt).unwrap().direction);
        trunc.add(
            angle_arcsec(got, full_series_teme(&tt, &table)),
            &format!("day {day}"),
        );
        day += 5;
    }
    figures::figure("sun.vsop87_vs_de421.max_arcsec", floor.max);
    figures::figure("sun.precise_vs_vsop87.max_arcsec", trunc.max);
    figures::figure("sun.precise_vs_vsop87.rms_arcsec", trunc.rms());
    println!(
        "full abridged VSOP87 (f64) vs DE421: max {:.2}″, RMS {:.2}″; precise (f32) vs full series 1950–2100: max {:.2}″ ({}), RMS {:.2}″",
        floor.max,
        floor.rms(),
        trunc.max,
        trunc.worst,
        trunc.rms()
    );
    assert!(floor.max < 1.0);
    assert!(trunc.max < 6.0, "{}″ at {}", trunc.max, trunc.worst);
}
