//! The exact solution by characteristics in bounded memory (issue 22, D1): a march over
//! c·t_end/L crossings used to keep every piece it made (4 GB for a stiff bar over three steps,
//! 850 MB for a 1 m steel bar over 1000 s). The store now keeps the whole march only up to
//! `StoreLimits::DEFAULT.resident` pieces, beyond that checkpoints and windows
//! (`src/characteristics/store.rs`); the numbers are those of the whole march, bit for bit.

mod common;

use massredist::characteristics::{BarData, Characteristics, FarEnd, InitialData, StoreLimits};
use massredist::exact::ImpactingBar;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};

#[global_allocator]
static GLOBAL: common::alloc::CountingAlloc = common::alloc::CountingAlloc;

fn paper_bar(l: f64) -> BarData {
    BarData { length: l, density: 1.0, modulus: 1.0, far_end: FarEnd::Clamped, gap: 0.0 }
}

/// The paper's benchmark on two nodes, up to `t_end`, and the peak bytes its construction and
/// one evaluation at t_end took.
fn paper_until(t_end: f64) -> (Characteristics, usize) {
    let (x, u, v) = ([0.0, 1.0], [0.5, 0.0], [0.0, 0.0]);
    let mut made = None;
    let peak = common::alloc::peak_bytes(|| {
        let c =
            Characteristics::new(&paper_bar(1.0), InitialData::PiecewiseLinear { x: &x, u: &u, v: &v }, t_end).unwrap();
        std::hint::black_box(c.u(0.5, t_end));
        made = Some(c);
    });
    (made.unwrap(), peak)
}

/// Memory does not grow with t_end: 10⁵ and 4·10⁵ crossings (each past the resident limit)
/// peak alike, under 16 MB, and the far end of the march still agrees with the closed form
/// of the paper's benchmark (period 3L/c), to the round-off of arguments of size c·t.
///
/// Before the fix the peak grew in proportion to t_end, and this test failed on the ratio (run
/// on the unfixed commit a8ddfb4: 16.3 MB at 10⁵, 65.0 MB at 4·10⁵; fixed: 10.8 MB at both).
#[test]
fn memory_does_not_grow_with_the_horizon() {
    let (short, p1) = paper_until(1e5);
    let (long, p2) = paper_until(4e5);
    eprintln!("peak bytes: {p1} at t_end = 1e5, {p2} at t_end = 4e5");
    assert!(short.is_windowed() && long.is_windowed(), "both horizons are past the resident limit");
    // Equal but for a few checkpoints and the contact list (16 bytes a phase up to 2¹⁶ phases):
    // ×1.5 leaves room for those, a linear growth is ×4.
    assert!((p2 as f64) < 1.5 * p1 as f64, "peak {p2} B at 4e5 vs {p1} B at 1e5");
    assert!(p2 < 16 << 20, "peak {p2} B");
    let e = ImpactingBar { length: 1.0 };
    for t in [4e5 - 2.5, 4e5 - 1.3, 4e5 - 0.4, 4e5] {
        // Arguments x ± ct carry an error of ε·ct per reflection chain; 64ε·ct is generous.
        let tol = 64.0 * f64::EPSILON * t;
        for x in [0.0, 0.25, 0.5, 0.9, 1.0] {
            assert!(
                approx::relative_eq!(long.u(x, t), e.u(x, t), epsilon = tol, max_relative = 0.0),
                "u({x}, {t}) = {} vs {}",
                long.u(x, t),
                e.u(x, t)
            );
        }
    }
    // One contact phase [1 + 3k, 2 + 3k) per period: k = 0 … ⌊(4e5 − 1)/3⌋.
    assert_eq!(long.contact_count(), 133_333);
    assert_eq!(long.contact_intervals().len(), massredist::characteristics::MAX_LISTED_CONTACTS);
}

/// Data with many phase switches: rough piecewise-linear data on a bar with a gap, both far
/// ends, and a smooth case.
fn rough(l: f64) -> ([f64; 7], [f64; 7], [f64; 7]) {
    let x = [0.0, 0.11, 0.3, 0.42, 0.6, 0.83, 1.0].map(|s| s * l);
    let u = [0.2, 0.15, 0.17, 0.05, -0.02, 0.04, 0.0].map(|s| s * l);
    let v = [-0.9, -0.4, 0.3, -0.2, 0.6, 0.1, -0.5];
    (x, u, v)
}

/// Every evaluation of `a` and `b` agrees bit for bit at the given times.
fn assert_same(a: &Characteristics, b: &Characteristics, times: &[f64], what: &str) {
    let nodes: Vec<f64> = (0..=13).map(|i| a.length() * i as f64 / 13.0).collect();
    let values: Vec<f64> = nodes.iter().map(|x| (x * 3.1).sin() * 0.1).collect();
    let (mut ka, mut kb) = (Vec::new(), Vec::new());
    for &t in times {
        for &x in &nodes {
            let same = |p: f64, q: f64| p.to_bits() == q.to_bits();
            assert!(same(a.u(x, t), b.u(x, t)), "{what}: u({x}, {t})");
            assert!(same(a.u_t(x, t), b.u_t(x, t)), "{what}: u_t({x}, {t})");
            assert!(same(a.u_x(x, t), b.u_x(x, t)), "{what}: u_x({x}, {t})");
        }
        assert_eq!(a.lambda(t).to_bits(), b.lambda(t).to_bits(), "{what}: λ({t})");
        assert_eq!(a.in_contact(t), b.in_contact(t), "{what}: in contact at {t}");
        assert_eq!(a.energy(t).to_bits(), b.energy(t).to_bits(), "{what}: energy({t})");
        let (ea, eb) = (a.l2_error_p1(&nodes, &values, t), b.l2_error_p1(&nodes, &values, t));
        assert_eq!(ea.to_bits(), eb.to_bits(), "{what}: L² error at {t}");
        a.kinks(t, &mut ka);
        b.kinks(t, &mut kb);
        assert_eq!(ka, kb, "{what}: kinks at {t}");
    }
}

/// The windowed store (forced by tiny limits: every window a few pieces, checkpoints thinned
/// many times) gives every value of the resident one, bit for bit, at times visited forwards,
/// backwards and at random, including every contact switch and the ends.
///
/// Mutation that made it fail: a window trimmed past its own start (`m.trim(s, margin)` →
/// `m.trim(s + margin, 0.0)` in `Store::cut`) → "Clamped forwards: u(0, 6.656…)". (Keeping one
/// piece fewer in `Marcher::trim`, `self.a[1].lo` → `self.a[0].lo`, did not fail it: the margin
/// of one bar length covers that piece.)
#[test]
fn windows_give_the_whole_marchs_numbers_bit_for_bit() {
    let tiny = StoreLimits { resident: 0, window: 3, checkpoints: 4 };
    let mut rng = rand::rngs::StdRng::seed_from_u64(22);
    for far_end in [FarEnd::Clamped, FarEnd::Free] {
        let (l, rho, e, gap) = (1.7, 2.3, 0.6, 0.07);
        let b = BarData { length: l, density: rho, modulus: e, far_end, gap };
        let t_end = 20.0 * l / (e / rho).sqrt();
        let (x, u, v) = rough(l);
        let data = InitialData::PiecewiseLinear { x: &x, u: &u, v: &v };
        let whole = Characteristics::new(&b, data, t_end).unwrap();
        let windowed = Characteristics::with_limits(&b, data, t_end, tiny).unwrap();
        assert!(!whole.is_windowed() && windowed.is_windowed());
        assert_eq!(whole.contact_intervals(), windowed.contact_intervals());
        assert_eq!(whole.contact_count(), windowed.contact_count());
        assert!(whole.contact_count() >= 1, "{far_end:?}: the data must hit the obstacle");
        let mut times: Vec<f64> = (0..=400).map(|i| t_end * i as f64 / 400.0).collect();
        for &(s, e) in whole.contact_intervals() {
            times.extend([s, e, s.next_up(), e.next_down()].into_iter().filter(|t| (0.0..=t_end).contains(t)));
        }
        assert_same(&whole, &windowed, &times, &format!("{far_end:?} forwards"));
        times.reverse();
        assert_same(&whole, &windowed, &times, &format!("{far_end:?} backwards"));
        times.shuffle(&mut rng);
        assert_same(&whole, &windowed, &times, &format!("{far_end:?} shuffled"));
        let random: Vec<f64> = (0..200).map(|_| rng.random_range(0.0..=t_end)).collect();
        assert_same(&whole, &windowed.clone(), &random, &format!("{far_end:?} random, a clone"));
    }
    // Smooth data (Chebyshev panels, several per wave).
    let b = BarData { length: 1.0, density: 1.0, modulus: 1.0, far_end: FarEnd::Free, gap: 0.05 };
    let (uf, vf) = (|x: f64| 0.1 * (3.0 * x).cos(), |x: f64| -0.5 + 0.3 * (7.0 * x).sin());
    let data = InitialData::Smooth { u: &uf, v: &vf };
    let whole = Characteristics::new(&b, data, 30.0).unwrap();
    let windowed = Characteristics::with_limits(&b, data, 30.0, tiny).unwrap();
    let mut times: Vec<f64> = (0..=300).map(|i| 30.0 * i as f64 / 300.0).collect();
    times.shuffle(&mut rng);
    assert_same(&whole, &windowed, &times, "smooth");
}

/// Issue 22, D1 (time): the march costs ~0.5 µs per crossing, so a 6-element bar with wave
/// speed c = 10¹⁰ over three steps of 0.01 (3·10⁸ crossings) spent minutes in `check` (E = 10¹⁶,
/// T = 1, 10⁸ crossings: 54 s on ec19309). Such a horizon is now refused at once, by `check` and
/// `run`, with exit 2 naming the crossings, the limit and `time.end`; 10⁷ crossings still pass
/// (c = 10⁶, T = 1: 10⁶). The run is timed out at 60 s, so the unfixed code fails here.
#[test]
fn a_horizon_of_too_many_crossings_is_refused_at_once() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = |modulus: &str, end: &str| {
        let p = tmp.path().join(format!("s{modulus}.toml"));
        let text = format!(
            "[bar]\nelements = 6\nmodulus = {modulus}\ninitial = {{ displacement = \"(1-x)/2\", velocity = \"0\" }}\n[time]\ndt = 0.01\nend = {end}\n"
        );
        std::fs::write(&p, text).unwrap();
        p
    };
    let bin = env!("CARGO_BIN_EXE_massredist");
    let timed = |args: &[&std::ffi::OsStr]| {
        let mut child = std::process::Command::new(bin)
            .args(args)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let start = std::time::Instant::now();
        while child.try_wait().unwrap().is_none() {
            if start.elapsed().as_secs() > 60 {
                child.kill().unwrap();
                panic!("{args:?} still running after 60 s");
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        child.wait_with_output().unwrap()
    };
    let stiff = scene("1e20", "0.03");
    let out = tmp.path().join("out");
    for args in [
        vec![std::ffi::OsStr::new("check"), stiff.as_os_str()],
        vec!["run".as_ref(), stiff.as_os_str(), "--out".as_ref(), out.as_os_str()],
    ] {
        let o = timed(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("3.000e8 crossings") && err.contains("at most 1e7") && err.contains("time.end"), "{err}");
    }
    assert!(!out.exists());
    let fine = timed(&["check".as_ref(), scene("1e12", "1").as_os_str()]);
    assert_eq!(fine.status.code(), Some(0), "{}", String::from_utf8_lossy(&fine.stderr));
}
