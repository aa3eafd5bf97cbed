//! Whole-engine throughput: elastic hard disks and spheres in a periodic box, events per second
//! (criterion reports elements/s = pair collisions/s). The table over N and φ is `make bench`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use edmd::{Elastic, InitParams, Periodic, Stop};

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("engine");
    group.sample_size(10);
    let n = 10_000;
    let per_particle = 20.0;
    group.throughput(Throughput::Elements((n as f64 * per_particle) as u64));
    for (d, phi) in [(2usize, 0.3), (3, 0.45)] {
        group.bench_function(BenchmarkId::new(format!("{d}d_phi{phi}"), n), |b| {
            if d == 2 {
                let mut sim = InitParams::<2>::with_packing(n, phi)
                    .unwrap()
                    .build::<Periodic, _>(Elastic)
                    .unwrap();
                b.iter(|| sim.run(Stop::Tau(sim.tau() + per_particle)));
            } else {
                let mut sim = InitParams::<3>::with_packing(n, phi)
                    .unwrap()
                    .build::<Periodic, _>(Elastic)
                    .unwrap();
                b.iter(|| sim.run(Stop::Tau(sim.tau() + per_particle)));
            }
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
