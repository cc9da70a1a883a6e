#![cfg(feature = "python")]
//! Live checks of the FEniCSx / scikit-fem bridge: both backends against the paper's closed-form
//! matrices (section 3) and each other, 2D identities, the independent steppers' invariants
//! (u_0 = (u_1)^+ and complementarity, eq. (3.3); the hybrid scheme's energy decay, section 5
//! lemma), drift of the stored fixtures, and the error paths.
//! Run with `cargo test --features python --test bridge_live` after `bash python/install-deps.sh`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use massredist_study::bridge::{self, Backend, BridgeError, Csr};
use serde_json::Value;

const EPS: f64 = f64::EPSILON;

/// Vertices x_i = i h of the bar (0, L) (h = L/m, i = 0..=m) and its elements [x_j, x_{j+1}].
fn bar(length: f64, m: usize) -> (Vec<f64>, Vec<usize>) {
    let h = length / m as f64;
    let points = (0..=m).map(|i| i as f64 * h).collect();
    let cells = (0..m).flat_map(|j| [j, j + 1]).collect();
    (points, cells)
}

/// The paper's masses (section 3) for m elements: standard (no redistribution), Mod 1–3.
fn masses(m: usize) -> Vec<(&'static str, Vec<f64>)> {
    let mut mod1 = vec![1.0; m];
    mod1[0] = 0.0;
    let mut mod2 = vec![m as f64 / (m - 1) as f64; m];
    mod2[0] = 0.0;
    let mut mod3 = mod1.clone();
    mod3[1] = 2.0;
    vec![("standard", vec![1.0; m]), ("mod1", mod1), ("mod2", mod2), ("mod3", mod3)]
}

/// Closed-form M and S over all m + 1 vertices (section 3; vertex m: M_mm = h w_{m−1}/3,
/// S_mm = 1/h, as no Dirichlet condition is applied here).
fn closed_form(length: f64, w: &[f64]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let m = w.len();
    let h = length / m as f64;
    let mut mass = vec![vec![0.0; m + 1]; m + 1];
    let mut stiff = vec![vec![0.0; m + 1]; m + 1];
    for i in 0..=m {
        let left = if i > 0 { w[i - 1] } else { 0.0 };
        let right = if i < m { w[i] } else { 0.0 };
        mass[i][i] = h / 3.0 * (left + right);
        stiff[i][i] = if i == 0 || i == m { 1.0 / h } else { 2.0 / h };
        if i < m {
            mass[i][i + 1] = h / 6.0 * w[i];
            mass[i + 1][i] = mass[i][i + 1];
            stiff[i][i + 1] = -1.0 / h;
            stiff[i + 1][i] = -1.0 / h;
        }
    }
    (mass, stiff)
}

fn max_abs_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter().flatten().zip(b.iter().flatten()).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn versions_and_interpreter() {
    let start = Instant::now();
    let v = bridge::versions().expect("bridge start-up");
    eprintln!("bridge start-up (or wait for it): {:.3} s; {v:?}", start.elapsed().as_secs_f64());
    assert_eq!(v.executable, "/usr/bin/python3");
    assert!(v.python.starts_with("3."), "python {}", v.python);
    assert_eq!(v.dolfinx, "0.5.2");
    assert_eq!(v.skfem, "12.0.2");
    assert!(!v.numpy.is_empty());
}

#[test]
fn one_d_matrices_match_the_closed_form() {
    let mut cases: Vec<(f64, String, Vec<f64>)> = vec![];
    for m in [2, 6, 37] {
        cases.extend(masses(m).into_iter().map(|(name, w)| (1.0, format!("m{m} {name}"), w)));
    }
    cases.push((2.5, "m6 mod3 L=2.5".into(), masses(6)[3].1.clone()));
    let mut worst_between = 0.0_f64;
    for (length, name, w) in &cases {
        let m = w.len();
        let h = length / m as f64;
        let (points, cells) = bar(*length, m);
        let (mass, stiff) = closed_form(*length, w);
        let wmax = w.iter().copied().fold(0.0, f64::max);
        // x_i = i h is rounded, so each element length is h (1 + δ) with |δ| ≤ m eps (the
        // coordinate error eps L relative to h); 4 m eps times the entry scale covers it.
        let (mass_tol, stiff_tol) = (4.0 * m as f64 * EPS * h * wmax, 4.0 * m as f64 * EPS / h);
        let mut dense = vec![];
        for backend in Backend::ALL {
            let (mb, sb) = bridge::assemble(backend, &points, 1, &cells, 2, w).unwrap();
            let (md, sd) = (mb.to_dense(), sb.to_dense());
            let (dm, ds) = (max_abs_diff(&md, &mass), max_abs_diff(&sd, &stiff));
            assert!(dm <= mass_tol, "{name} {}: mass off by {dm:e} > {mass_tol:e}", backend.name());
            assert!(ds <= stiff_tol, "{name} {}: stiffness off by {ds:e} > {stiff_tol:e}", backend.name());
            assert_eq!(mb.get(0, 0), md[0][0]);
            dense.push((md, sd));
        }
        // Same coordinates, same element integrals: the backends differ by summation order only.
        let dm = max_abs_diff(&dense[0].0, &dense[1].0) / (h * wmax);
        let ds = max_abs_diff(&dense[0].1, &dense[1].1) * h;
        worst_between = worst_between.max(dm).max(ds);
        assert!(dm <= 4.0 * EPS && ds <= 4.0 * EPS, "{name}: backends differ by {dm:e}, {ds:e} (relative)");
    }
    eprintln!("1D: dolfinx vs scikit-fem, max relative difference {worst_between:e}");
}

/// A 2D test mesh: `verts_per_cell` vertex indices per cell, one weight and one area per cell.
struct Mesh2d {
    name: &'static str,
    points: Vec<f64>,
    cells: Vec<usize>,
    verts_per_cell: usize,
    weights: Vec<f64>,
    areas: Vec<f64>,
}

/// A 4×3 structured triangle mesh of (0,1)² and a 3×3 quadrilateral mesh of (0,2)×(0,1)
/// (counter-clockwise), with per-cell weights.
fn two_d_meshes() -> Vec<Mesh2d> {
    let grid = |nx: usize, ny: usize, lx: f64| -> Vec<f64> {
        (0..=ny).flat_map(|j| (0..=nx).flat_map(move |i| [lx * i as f64 / nx as f64, j as f64 / ny as f64])).collect()
    };
    let (nx, ny) = (4, 3);
    let mut tri = vec![];
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            tri.extend([a, a + 1, a + nx + 2, a, a + nx + 2, a + nx + 1]);
        }
    }
    let quad: Vec<usize> = (0..3)
        .flat_map(|j| (0..3).flat_map(move |i| [4 * j + i, 4 * j + i + 1, 4 * j + i + 5, 4 * j + i + 4]))
        .collect();
    let tri_w: Vec<f64> = (0..24).map(|c| 0.5 + 0.25 * (c % 7) as f64).collect();
    let quad_w: Vec<f64> = (0..9).map(|c| 2.0 - 0.125 * c as f64).collect();
    vec![
        Mesh2d {
            name: "triangles",
            points: grid(nx, ny, 1.0),
            cells: tri,
            verts_per_cell: 3,
            weights: tri_w,
            areas: vec![1.0 / 24.0; 24],
        },
        Mesh2d {
            name: "quadrilaterals",
            points: grid(3, 3, 2.0),
            cells: quad,
            verts_per_cell: 4,
            weights: quad_w,
            areas: vec![2.0 / 9.0; 9],
        },
    ]
}

#[test]
fn two_d_backends_agree_and_satisfy_identities() {
    for Mesh2d { name, points, cells, verts_per_cell: nv, weights: w, areas } in two_d_meshes() {
        let n = points.len() / 2;
        let out: Vec<(Csr, Csr)> =
            Backend::ALL.iter().map(|&b| bridge::assemble(b, &points, 2, &cells, nv, &w).unwrap()).collect();
        let (md, sd) = (out[0].0.to_dense(), out[0].1.to_dense());
        let (ms, ss) = (out[1].0.to_dense(), out[1].1.to_dense());
        let (mass_scale, stiff_scale) = (md[0][0].abs().max(ms[4][4]), sd[4][4].abs());
        let (dm, ds) = (max_abs_diff(&md, &ms), max_abs_diff(&sd, &ss));
        eprintln!("2D {name}: dolfinx vs scikit-fem: mass {dm:e}, stiffness {ds:e}");
        // Different quadrature rules and summation orders, both exact: round-off of a 4-term sum.
        assert!(dm <= 16.0 * EPS * mass_scale, "{name}: mass differs by {dm:e}");
        assert!(ds <= 16.0 * EPS * stiff_scale, "{name}: stiffness differs by {ds:e}");
        let total_w: f64 = w.iter().zip(&areas).map(|(w, a)| w * a).sum();
        for (backend, (mass, stiff)) in ["dolfinx", "skfem"].iter().zip([(&md, &sd), (&ms, &ss)]) {
            // S·1 = 0: constants have no gradient; each row sums at most 9 entries of size |S_ii|.
            let row_sum = stiff.iter().map(|r| r.iter().sum::<f64>().abs()).fold(0.0, f64::max);
            assert!(row_sum <= 16.0 * EPS * stiff_scale, "{name} {backend}: S row sum {row_sum:e}");
            // Σ_ij M_ij = ∫ w dx (Σ_i φ_i = 1); n² terms of which ~9n nonzero.
            let total: f64 = mass.iter().flatten().sum();
            let tol = 16.0 * (9 * n) as f64 * EPS * total_w;
            assert!((total - total_w).abs() <= tol, "{name} {backend}: Σ M = {total} ≠ ∫ w = {total_w}");
        }
    }
}

#[test]
fn the_scene_reader_gives_the_fixture_mesh() {
    // The gmsh fixture through the scene's edge reader (meshio, its boundary lines and geometry
    // points dropped): the fixture's points and cells, already counter-clockwise.
    let root = massredist_study::repo::root().join("fixtures");
    let mesh = massredist::scene::mesh_file::read("plate.mesh", &root.join("meshes/square_4x3_tri.msh")).unwrap();
    let (points, cells) = (mesh.flat_points(), mesh.cells);
    let fixture = load(&root.join("matrices/2d_square_4x3_tri__dolfinx.json"));
    assert_eq!(mesh.kind, massredist::fem::Cell::Triangle);
    let stored = flat_f64(&fixture["points"]);
    assert_eq!(points.len(), stored.len());
    // gmsh keeps 17 digits (exact); serde_json without `float_roundtrip` may be 1 ulp off.
    assert!(points.iter().zip(&stored).all(|(a, b)| (a - b).abs() <= EPS * b.abs()), "{points:?}");
    assert_eq!(cells, flat_f64(&fixture["cells"]).iter().map(|&c| c as usize).collect::<Vec<_>>());
}

#[test]
fn crank_nicolson_keeps_contact_complementarity() {
    for (m, wi) in [(6, 3), (37, 1)] {
        let w = masses(m)[wi].1.clone(); // Mod 3 and Mod 1: w_0 = 0
        let (u, lam) = bridge::trajectory_1d(Backend::Dolfinx, 1.0, m, &w, "crank-nicolson", 0.01, 300).unwrap();
        assert_eq!((u.len(), lam.len(), u[0].len()), (301, 301, m));
        let scale = u.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
        // u_0 and u_1 come out of one Cholesky solve: rounding error ∝ m eps |U|.
        let tol = 16.0 * m as f64 * EPS * scale;
        let mut contacts = 0;
        // n = 0 is the interpolated initial data u0(0) = 1/2 ≠ (u_1)^+; from n = 1 on the
        // massless contact node obeys the contact row (u_0 − u_1)/h = −λ, i.e. u_0 = (u_1)^+.
        for n in 1..u.len() {
            let (u0, u1) = (u[n][0], u[n][1]);
            assert!((u0 - u1.max(0.0)).abs() <= tol, "m={m} n={n}: u_0 = {u0}, u_1 = {u1}");
            assert!(u0 >= 0.0 && lam[n] <= 0.0 && u0 * lam[n] == 0.0, "m={m} n={n}: u_0 = {u0}, λ = {}", lam[n]);
            contacts += usize::from(lam[n] < 0.0);
        }
        assert!(contacts > 50, "m={m}: the bar must be in contact during t ∈ (1, 2), got {contacts} steps");
        let (us, _) = bridge::trajectory_1d(Backend::Skfem, 1.0, m, &w, "crank-nicolson", 0.01, 300).unwrap();
        let d = us.iter().flatten().zip(u.iter().flatten()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        eprintln!("CN m={m}: dolfinx vs scikit-fem trajectories differ by {d:e}");
        // The matrices differ by ulps (summation order); 300 steps with contact switches amplify
        // that to ~1e-12 here; 1e-10 leaves room and still catches any modelling difference.
        assert!(d <= 1e-10 * scale, "m={m}: backends' trajectories differ by {d:e}");
    }
}

/// Rows 0..m of the (m+1)-vertex matrix: the m free dofs, Dirichlet vertex m dropped.
fn free_block(a: &Csr, m: usize) -> Vec<Vec<f64>> {
    a.to_dense().into_iter().take(m).map(|row| row[..m].to_vec()).collect()
}

fn quad_form(a: &[Vec<f64>], x: &[f64], y: &[f64]) -> f64 {
    a.iter().zip(x).map(|(row, xi)| xi * row.iter().zip(y).map(|(a, y)| a * y).sum::<f64>()).sum()
}

#[test]
fn hybrid_energy_never_increases() {
    let (m, dt, steps) = (6, 0.01, 300);
    let h = 1.0 / m as f64;
    for (name, w) in masses(m).into_iter().skip(1) {
        let (points, cells) = bar(1.0, m);
        let (mb, sb) = bridge::assemble(Backend::Skfem, &points, 1, &cells, 2, &w).unwrap();
        let (mass, stiff) = (free_block(&mb, m), free_block(&sb, m));
        let (u, lam) = bridge::trajectory_1d(Backend::Skfem, 1.0, m, &w, "hybrid", dt, steps).unwrap();
        // V from the scheme's own trapezoid rule V^{n+1} = 2 (U^{n+1} − U^n)/dt − V^n, V^0 = 0;
        // the contact column carries no mass (w_0 = 0), so its velocity does not matter.
        let mut v = vec![vec![0.0; m]];
        for n in 0..steps {
            let next = (0..m).map(|i| 2.0 * (u[n + 1][i] - u[n][i]) / dt - v[n][i]).collect();
            v.push(next);
        }
        // E = ½ VᵀMV + ½ UᵀSU on the full free system with u_0 = (u_1)^+ (section 3, eq. (3.4)).
        let energy: Vec<f64> =
            (0..=steps).map(|n| 0.5 * quad_form(&mass, &v[n], &v[n]) + 0.5 * quad_form(&stiff, &u[n], &u[n])).collect();
        // Rebuilding V multiplies each rounding of U by 2/dt and accumulates it over the steps.
        let tol = 16.0 * EPS * steps as f64 / dt * energy[0];
        let rise = energy.windows(2).map(|e| e[1] - e[0]).fold(f64::NEG_INFINITY, f64::max);
        eprintln!("hybrid {name}: E0 = {}, E_end = {}, max rise {rise:e} (tol {tol:e})", energy[0], energy[steps]);
        assert!(rise <= tol, "{name}: energy rose by {rise:e}");
        for n in 0..=steps {
            assert_eq!(u[n][0], u[n][1].max(0.0));
            assert_eq!(lam[n], u[n][1].min(0.0) / h);
        }
    }
}

fn load(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

fn flat_f64(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(flat_f64).collect(),
        other => vec![other.as_f64().unwrap()],
    }
}

fn fixture_dir() -> PathBuf {
    massredist_study::repo::root().join("fixtures")
}

#[test]
fn stored_fixtures_match_a_fresh_regeneration() {
    for (file, backend) in
        [("1d_m6_mod3_L1__dolfinx.json", Backend::Dolfinx), ("2d_rect_3x3_quad__skfem.json", Backend::Skfem)]
    {
        let f = load(&fixture_dir().join("matrices").join(file));
        assert_eq!(f["backend"], backend.name());
        let dim = f["dim"].as_u64().unwrap() as usize;
        let nv = f["cells"][0].as_array().unwrap().len();
        let cells: Vec<usize> = flat_f64(&f["cells"]).iter().map(|&c| c as usize).collect();
        let (mass, stiff) =
            bridge::assemble(backend, &flat_f64(&f["points"]), dim, &cells, nv, &flat_f64(&f["weights"])).unwrap();
        for (fresh, stored) in [(mass, &f["mass"]), (stiff, &f["stiffness"])] {
            let ints = |k: &str| flat_f64(&stored[k]).iter().map(|&x| x as usize).collect::<Vec<_>>();
            assert_eq!(fresh.nrows as u64, stored["nrows"].as_u64().unwrap(), "{file}");
            assert_eq!(fresh.indptr, ints("indptr"), "{file}: pattern drifted");
            assert_eq!(fresh.indices, ints("indices"), "{file}: pattern drifted");
            for (a, b) in fresh.data.iter().zip(flat_f64(&stored["data"])) {
                // Python writes shortest round-trip floats; serde_json without `float_roundtrip`
                // may parse them 1 ulp off, so allow one ulp.
                assert!((a - b).abs() <= EPS * b.abs(), "{file}: {a} drifted from {b}");
            }
        }
    }
    let f = load(&fixture_dir().join("trajectories/m6_mod3__hybrid.json"));
    let w = flat_f64(&f["weights"]);
    let (u, lam) = bridge::trajectory_1d(Backend::Dolfinx, 1.0, 6, &w, "hybrid", 0.01, 300).unwrap();
    assert_eq!((f["dt"].as_f64(), f["steps"].as_u64(), f["record_every"].as_u64()), (Some(0.01), Some(300), Some(1)));
    let stored = flat_f64(&f["U"]);
    let scale = stored.iter().map(|x| x.abs()).fold(0.0, f64::max);
    for (a, b) in u.iter().flatten().chain(&lam).zip(stored.iter().chain(&flat_f64(&f["lam"]))) {
        // LAPACK kernels differ between CPUs and 300 steps amplify ulp-level differences (matrices
        // an ulp apart give trajectories ~1e-12 apart, see the CN test), hence 1e-10, not 1 ulp.
        assert!((a - b).abs() <= 1e-10 * scale.max(b.abs()), "trajectory drifted: {a} vs {b}");
    }
}

#[test]
fn errors_are_reported_clearly() {
    match bridge::module_version("definitely_not_installed") {
        Err(BridgeError::MissingModule { module, hint }) => {
            assert_eq!(module, "definitely_not_installed");
            assert!(hint.contains("python/install-deps.sh"), "{hint}");
        }
        other => panic!("expected MissingModule, got {other:?}"),
    }
    assert_eq!(bridge::module_version("skfem").unwrap(), "12.0.2");
    // The hybrid scheme needs a massless contact node; Python's ValueError comes back whole.
    match bridge::trajectory_1d(Backend::Skfem, 1.0, 6, &[1.0; 6], "hybrid", 0.01, 3) {
        Err(BridgeError::Python { traceback }) => {
            assert!(traceback.starts_with("Traceback"), "{traceback}");
            assert!(traceback.contains("ValueError: the hybrid scheme needs w_0 = 0"), "{traceback}");
        }
        other => panic!("expected a Python error, got {other:?}"),
    }
    let bad = bridge::trajectory_1d(Backend::Skfem, 1.0, 6, &[1.0; 6], "leapfrog", 0.01, 3);
    assert!(matches!(bad, Err(BridgeError::InvalidInput { .. })), "{bad:?}");
    let bad = bridge::assemble(Backend::Dolfinx, &[0.0, 1.0], 1, &[0, 1], 2, &[]);
    assert!(matches!(bad, Err(BridgeError::InvalidInput { .. })), "{bad:?}");
}

#[test]
fn elastic_matrices_of_both_backends_satisfy_the_identities() {
    // Independently of the Rust assembly, on every cell type (2D plane strain and 3D), both
    // backends give: symmetric M and S; S r = 0 for the rigid motions r (d translations and the
    // infinitesimal rotations x_k e_l − x_l e_k: ε(r) = 0); 1ᵀ M_i 1 = ρ Σ_c w_c |c| for each
    // component i (the basis sums to 1); no coupling of components in M; and the two backends
    // agree. Round-off: 64 ε · max|entry| · entries per row (at most 3·27).
    // mutation: python/crosscheck/fem_skfem.py using `linear_elasticity(lam, lam)` -> fails with "triangle:
    // backends differ by 2.8e-17, 5.8e0"; fem_dolfinx.py with ε = ∇u (not sym) -> fails with
    // "dolfinx triangle: S r = 0" (the rotations are no longer in the kernel).
    use massredist::fem::{Cell, Mesh};
    use massredist::solid::Lame;
    use massredist_study::bridge::MeshArrays;
    let lame = Lame { lambda: 1.3, mu: 0.45, density: 2.0 };
    let meshes = [
        Mesh::structured_2d(1.0, 0.5, 3, 2, Cell::Triangle).unwrap(),
        Mesh::structured_2d(1.0, 0.5, 3, 2, Cell::Quad).unwrap(),
        Mesh::structured_3d([1.0, 0.5, 0.5], [2, 2, 1], Cell::Tet).unwrap(),
        Mesh::structured_3d([1.0, 0.5, 0.5], [2, 2, 1], Cell::Hex).unwrap(),
    ];
    for mesh in &meshes {
        let d = mesh.dim;
        let n = mesh.n_nodes() * d;
        let weights: Vec<f64> = (0..mesh.n_cells()).map(|c| 0.5 + (c % 3) as f64).collect();
        let total: f64 = (0..mesh.n_cells()).map(|c| weights[c] * mesh.measure(c)).sum::<f64>() * lame.density;
        let arrays: MeshArrays = MeshArrays::of(mesh);
        let mut dense = vec![];
        for backend in Backend::ALL {
            let (m, s) = bridge::assemble_elastic(backend, &arrays, &weights, &lame).unwrap();
            let (m, s) = (m.to_dense(), s.to_dense());
            let tol = |a: &[Vec<f64>]| 64.0 * EPS * 81.0 * a.iter().flatten().fold(0.0f64, |x, y| x.max(y.abs()));
            let label = format!("{} {}", backend.name(), mesh.kind.name());
            for a in [&m, &s] {
                let asym = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| (a[i][j] - a[j][i]).abs());
                assert!(asym.fold(0.0, f64::max) <= tol(a), "{label}: symmetry");
            }
            let mut rigid: Vec<Vec<f64>> =
                (0..d).map(|i| (0..n).map(|g| f64::from(u8::from(g % d == i))).collect()).collect();
            for (k, l) in [(0, 1), (0, 2), (1, 2)].into_iter().filter(|&(_, l)| l < d) {
                let p = |g: usize| mesh.points[g / d];
                rigid.push(
                    (0..n)
                        .map(|g| {
                            if g % d == l {
                                p(g)[k]
                            } else if g % d == k {
                                -p(g)[l]
                            } else {
                                0.0
                            }
                        })
                        .collect(),
                );
            }
            for r in &rigid {
                let sr = s.iter().map(|row| row.iter().zip(r).map(|(a, b)| a * b).sum::<f64>());
                assert!(sr.fold(0.0f64, |x, y| x.max(y.abs())) <= 4.0 * tol(&s), "{label}: S r = 0");
            }
            for (i, r) in rigid.iter().take(d).enumerate() {
                let mass: f64 = (0..n).map(|g| r[g] * m[g].iter().zip(r).map(|(a, b)| a * b).sum::<f64>()).sum();
                assert!((mass - total).abs() <= 64.0 * EPS * n as f64 * total, "{label}: mass of component {i}");
            }
            let coupled = (0..n).flat_map(|g| (0..n).map(move |h| (g, h))).filter(|&(g, h)| g % d != h % d);
            assert!(coupled.into_iter().all(|(g, h)| m[g][h] == 0.0), "{label}: M couples components");
            dense.push((m, s));
        }
        let (dm, ds) = (max_abs_diff(&dense[0].0, &dense[1].0), max_abs_diff(&dense[0].1, &dense[1].1));
        let tol = 64.0 * EPS * 81.0 * dense[0].1.iter().flatten().fold(0.0f64, |x, y| x.max(y.abs()));
        assert!(dm <= tol && ds <= tol, "{}: backends differ by {dm:e}, {ds:e}", mesh.kind.name());
    }
    let bad = bridge::assemble_elastic(
        Backend::Skfem,
        &MeshArrays { dim: 3, verts_per_cell: 3, ..MeshArrays::of(&meshes[0]) },
        &[1.0],
        &lame,
    );
    assert!(matches!(bad, Err(BridgeError::InvalidInput { .. })), "{bad:?}");
}
