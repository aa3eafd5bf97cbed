//! The event calendar alone: Paul's bucket calendar against the `BinaryHeap` baseline, under the
//! traffic of an event loop (pop the earliest, reschedule it and one other particle a random mean
//! free time ahead).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use edmd::{Calendar, HeapCalendar, PaulCalendar, Standalone};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

fn churn<C: Calendar>(
    cal: &mut Standalone<C>,
    rng: &mut Xoshiro256PlusPlus,
    n: usize,
    steps: usize,
) -> f64 {
    let mut now = 0.0;
    for _ in 0..steps {
        let (i, t) = cal.pop().expect("never empty");
        now = t;
        // Exponential waiting times with mean n/2 events of width 1/n.
        let dt = -rng.random::<f64>().max(1e-300).ln() * 0.5;
        cal.schedule(i, now + dt);
        let j = rng.random_range(0..n as u32);
        cal.schedule(j, now + -rng.random::<f64>().max(1e-300).ln() * 0.5);
    }
    now
}

fn setup<C: Calendar>(n: usize, seed: u64) -> (Standalone<C>, Xoshiro256PlusPlus) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut cal = Standalone::<C>::with_capacity(n);
    cal.reset(0.0, 2.0 / n as f64);
    for i in 0..n as u32 {
        cal.schedule(i, rng.random::<f64>());
    }
    (cal, rng)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("calendar");
    let steps = 100_000;
    group.throughput(Throughput::Elements(steps as u64));
    for n in [10_000usize, 100_000, 1_000_000] {
        group.bench_with_input(BenchmarkId::new("paul", n), &n, |b, &n| {
            let (mut cal, mut rng) = setup::<PaulCalendar>(n, 1);
            b.iter(|| churn(&mut cal, &mut rng, n, steps))
        });
        group.bench_with_input(BenchmarkId::new("binary_heap", n), &n, |b, &n| {
            let (mut cal, mut rng) = setup::<HeapCalendar>(n, 1);
            b.iter(|| churn(&mut cal, &mut rng, n, steps))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
