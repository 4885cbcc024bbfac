//! Propagations per second: this crate's f32 SGP4 against the `sgp4` crate (f64, the
//! neuromorphicsystems port of Vallado's code) on the same element sets and times.
//!
//! `cargo bench --bench sgp4`; the README quotes the ratio of the two, not wall times.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

use acs::orbit::sgp4::{Gravity, Sgp4};
use acs::time::TimeSpan;
use acs::tle::Tle;

/// The near-Earth element sets of `tests/data/sgp4/catalogue.tle` plus DTUSAT.
fn element_sets() -> Vec<(String, String)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/sgp4");
    let mut sets = Vec::new();
    for file in ["catalogue.tle", "dtusat.tle"] {
        let text = std::fs::read_to_string(dir.join(file)).expect("reference TLE file");
        let lines: Vec<&str> = text.lines().collect();
        for pair in lines.windows(2) {
            if pair[0].starts_with("1 ") && pair[1].starts_with("2 ") {
                sets.push((pair[0].to_string(), pair[1].to_string()));
            }
        }
    }
    sets
}

/// Times since epoch, minutes: every 37 min over −1 to +3 days.
fn times_min() -> Vec<f64> {
    (0..)
        .map(|k| -1440.0 + 37.0 * k as f64)
        .take_while(|t| *t <= 4320.0)
        .collect()
}

fn bench(c: &mut Criterion) {
    let sets = element_sets();
    let times = times_min();
    let ours: Vec<Sgp4> = sets
        .iter()
        .map(|(l1, l2)| Sgp4::new(&Tle::parse(l1, l2).expect("TLE"), Gravity::Wgs72).expect("SGP4"))
        .collect();
    let spans: Vec<TimeSpan> = times
        .iter()
        .map(|t| TimeSpan::from_minutes_f64(*t).expect("time"))
        .collect();
    let theirs: Vec<sgp4::Constants> = sets
        .iter()
        .map(|(l1, l2)| {
            let e = sgp4::Elements::from_tle(None, l1.as_bytes(), l2.as_bytes()).expect("TLE");
            sgp4::Constants::from_elements_afspc_compatibility_mode(&e).expect("SGP4")
        })
        .collect();

    let mut group = c.benchmark_group("sgp4 propagation");
    group.throughput(Throughput::Elements((sets.len() * times.len()) as u64));
    group.bench_function("acs f32", |b| {
        b.iter(|| {
            for s in &ours {
                for t in &spans {
                    let _ = black_box(s.propagate(black_box(*t)));
                }
            }
        })
    });
    group.bench_function("sgp4 crate f64", |b| {
        b.iter(|| {
            for s in &theirs {
                for t in &times {
                    let _ = black_box(s.propagate(sgp4::MinutesSinceEpoch(black_box(*t))));
                }
            }
        })
    });
    group.finish();

    let mut init = c.benchmark_group("sgp4 initialisation");
    let tles: Vec<Tle> = sets
        .iter()
        .map(|(l1, l2)| Tle::parse(l1, l2).expect("TLE"))
        .collect();
    let elements: Vec<sgp4::Elements> = sets
        .iter()
        .map(|(l1, l2)| sgp4::Elements::from_tle(None, l1.as_bytes(), l2.as_bytes()).expect("TLE"))
        .collect();
    init.throughput(Throughput::Elements(sets.len() as u64));
    init.bench_function("acs (double-f32 init)", |b| {
        b.iter(|| {
            for t in &tles {
                let _ = black_box(Sgp4::new(black_box(t), Gravity::Wgs72));
            }
        })
    });
    init.bench_function("sgp4 crate", |b| {
        b.iter(|| {
            for e in &elements {
                let _ = black_box(sgp4::Constants::from_elements_afspc_compatibility_mode(
                    black_box(e),
                ));
            }
        })
    });
    init.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
