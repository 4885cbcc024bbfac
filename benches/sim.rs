//! Simulator speed: one orbit (5 676 control periods) of the `tracking` scenario, the flight
//! loop flying the simulated tiles, against the ideal and the realistic truth.
//!
//! `cargo bench --bench sim`; issue #18 keeps the simulator within 3× of its speed before the
//! realistic truth (the ideal truth is that simulator, bit for bit).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};

use acs::host::sim::realistic::TruthLevel;
use acs::host::sim::scenarios;

fn one_orbit_of_tracking(c: &mut Criterion) {
    let mut group = c.benchmark_group("sim");
    group.sample_size(20);
    for truth in [TruthLevel::Ideal, TruthLevel::Realistic] {
        let scenario = scenarios::tracking(None)
            .expect("scenario")
            .with_truth(truth);
        group.bench_function(format!("tracking one orbit, {} truth", truth.name()), |b| {
            b.iter(|| black_box(scenario.run().expect("run")).len())
        });
    }
    group.finish();
}

criterion_group!(benches, one_orbit_of_tracking);
criterion_main!(benches);
