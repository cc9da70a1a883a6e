//! Criterion micro-benchmarks: one time step of each scheme and one bare tridiagonal solve
//! (LDLᵀ and two-sided) at m = 10³ and 10⁴ on the paper's benchmark (Δt = h).
//!
//! `cargo bench --bench step`; throughput is reported in node-steps (elements) per second.
//! The work–precision sweep and the ratio tables are `massredist bench` (src/bench/).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use massredist::bench::perf::floor_matrix;
use massredist::bench::sweep::scheme_cases;
use massredist::mass::MassKind;
use massredist::run::Problem;
use std::hint::black_box;

const SIZES: [usize; 2] = [1_000, 10_000];
/// Steps per timed iteration.
const STEPS: u64 = 64;

fn solves(c: &mut Criterion) {
    let mut g = c.benchmark_group("solve");
    for m in SIZES {
        let a = floor_matrix(m);
        let b: Vec<f64> = (0..m).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut x = b.clone();
        g.throughput(Throughput::Elements(m as u64));
        let ldlt = a.factor().unwrap();
        g.bench_with_input(BenchmarkId::new("ldlt", m), &m, |bch, _| {
            bch.iter(|| {
                x.copy_from_slice(&b);
                ldlt.solve_in_place(black_box(&mut x));
            })
        });
        let twisted = a.factor_twisted().unwrap();
        g.bench_with_input(BenchmarkId::new("twisted", m), &m, |bch, _| {
            bch.iter(|| {
                x.copy_from_slice(&b);
                twisted.solve_in_place(black_box(&mut x));
            })
        });
    }
    g.finish();
}

fn steps(c: &mut Criterion) {
    let mut g = c.benchmark_group("step");
    for case in scheme_cases() {
        // The reduced formulation and the hybrid scheme need a massless contact node.
        let mass = if case.needs_massless { MassKind::Mod3 } else { MassKind::Standard };
        for m in SIZES {
            let problem = Problem::benchmark(1.0, m, &mass).unwrap();
            let dt = problem.system.h();
            g.throughput(Throughput::Elements(STEPS * m as u64));
            g.bench_with_input(BenchmarkId::new(format!("{}/{}", case.label, mass.name()), m), &m, |bch, _| {
                // A fresh scheme per batch keeps the state within the first period.
                bch.iter_batched_ref(
                    || problem.scheme(&case.spec, dt).unwrap(),
                    |s| {
                        for _ in 0..STEPS {
                            s.step().unwrap();
                        }
                    },
                    criterion::BatchSize::LargeInput,
                )
            });
        }
    }
    g.finish();
}

criterion_group!(benches, solves, steps);
criterion_main!(benches);
