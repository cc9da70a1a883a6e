//! Criterion micro-benchmarks: one time step of each scheme and one bare tridiagonal solve
//! (LDLᵀ and two-sided) at m = 10³ and 10⁴ on the paper's benchmark (Δt = h).
//!
//! 2D and 3D: set-up (assembly, factorisation, contact operator) and one Crank–Nicolson step,
//! free and in contact, of the Q1 plate (40 × 40), the plane-strain solid (30 × 30) and the hex
//! solid (8³), mod3, the paper's data, Δt = 0.02 (small sizes, so `cargo bench --no-run` and a
//! run stay cheap; the large sizes and the scipy ratios are `massredist bench`).
//!
//! `cargo bench --bench step`; throughput is reported in node-steps (elements) per second.
//! The work–precision sweep and the ratio tables are `massredist bench` (src/bench/).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use massredist::fem::Cell;
use massredist::mass::MassKind;
use massredist::models::{PaperBar, PaperPlate, PlaneWaveSolid};
use massredist::scene::SchemeSpec;
use massredist::schemes::Scheme;
use massredist_study::bench::perf::floor_matrix;
use massredist_study::bench::sweep::scheme_cases;
use std::hint::black_box;
use std::time::{Duration, Instant};

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
            let problem = PaperBar::unit(m).problem(&mass).unwrap();
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

/// The 2D/3D cases: label, and a builder of the problem's scheme (the whole set-up).
type Build = Box<dyn Fn() -> Box<dyn Scheme>>;

fn multid_cases() -> Vec<(&'static str, Build)> {
    let cn = SchemeSpec::CRANK_NICOLSON;
    let plate = move || PaperPlate::square(40, Cell::Quad).problem(&MassKind::Mod3).unwrap().scheme(&cn, DT).unwrap();
    let solid = move |dim: usize, n: usize| {
        move || {
            let solid = PlaneWaveSolid { dim, cells: [n; 3] };
            solid.problem(&MassKind::Mod3, 2.0).unwrap().scheme(&cn, DT).unwrap()
        }
    };
    vec![
        ("plate-q1-40x40", Box::new(plate)),
        ("solid-2d-30x30", Box::new(solid(2, 30))),
        ("solid-3d-hex-8", Box::new(solid(3, 8))),
    ]
}

const DT: f64 = 0.02;

fn multid(c: &mut Criterion) {
    let mut g = c.benchmark_group("multid");
    g.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(2));
    for (label, build) in multid_cases() {
        g.bench_function(BenchmarkId::new("setup", label), |bch| bch.iter(|| black_box(build())));
        // Free steps from t = 0, contact steps from t = 1.1 (the face is in contact on (1, 2)):
        // chunks of at most 40 steps, each on a fresh scheme advanced untimed to its start.
        for (phase, skip) in [("free-step", 0usize), ("contact-step", 55)] {
            g.bench_function(BenchmarkId::new(phase, label), |bch| {
                bch.iter_custom(|iters| {
                    let (mut total, mut left) = (Duration::ZERO, iters);
                    while left > 0 {
                        let mut s = build();
                        for _ in 0..skip {
                            s.step().unwrap();
                        }
                        let k = left.min(40);
                        let t = Instant::now();
                        for _ in 0..k {
                            s.step().unwrap();
                        }
                        total += t.elapsed();
                        left -= k;
                    }
                    total
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, solves, steps, multid);
criterion_main!(benches);
