//! The elastic candidates for the paper's 2D table (`massredist_study::paper::elastic_table`): the
//! λ = 0 Q1 rows are the scalar plate's Q1 rows, and the new exact error on triangles agrees with
//! the plate's independent exact rule (cells clipped at the kinks of the closed form).

use massredist::exact::ImpactingBar;
use massredist::fem::Cell;
use massredist::fem::Mesh;
use massredist::fem::columns::Columns;
use massredist::mass::MassKind;
use massredist::plate::PlateProblem;
use massredist::scene::{Formulation, PlateInitial, PlateSpec, SchemeSpec};
use massredist_study::paper::elastic_table::{Material, linf_l2_errors, simplex_l2_error, spec};
use massredist_study::paper::plate_table;

#[test]
fn lambda_zero_quad_rows_are_the_scalar_plate_q1_rows() {
    // With λ = 0, μ = ½ the solid's x-rows on x-only fields are the plate's and its transverse
    // rows vanish (crate::solid docs), so both codes step the same numbers; their L² errors are
    // integrated by different exact rules (the solid: Gauss across each row of cells over the 1D
    // error; the plate: cells clipped at the kinks). The trajectories agree to steps · 64 ε
    // (tests/solid.rs), so the errors do too (the L² norm over the unit square is at most the
    // nodal maximum), plus 64 ε for the two integration rules' round-off.
    // mutation: Material::LambdaZeroFree given λ = 1e-3 -> fails (CN mod1: solid 2.511e-2, plate 2.466e-2).
    let cn = SchemeSpec::CrankNicolson { formulation: Formulation::Full };
    for (scheme, dt, end) in [(cn, 0.01, 3.0), (SchemeSpec::BackwardEuler, 0.05, 3.0)] {
        let steps = (end / dt as f64).round();
        let tol = (steps + 1.0) * 64.0 * f64::EPSILON;
        for mass in [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3] {
            let solid = linf_l2_errors(Cell::Quad, Material::LambdaZeroFree, &mass, &scheme, dt, &[end]).unwrap();
            let solid = solid[0].expect("the run reaches T");
            let plate = plate_table::linf_l2_error(Cell::Quad, 20, &mass, &scheme, dt, end).unwrap();
            assert!(
                (solid - plate).abs() <= tol,
                "{} {}: solid {solid:e}, plate {plate:e}, tolerance {tol:e}",
                scheme.name(),
                mass.name()
            );
        }
    }
}

/// A seeded linear congruential generator (Knuth's MMIX constants), values in [−1, 1).
fn noise(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

#[test]
fn triangle_error_agrees_with_the_plate_s_clipping_rule_on_random_fields() {
    // A random vector field on the P1 triangle mesh: its error against (u(x, t), 0) by the new
    // rule equals sqrt(plate_error(u_x)² + ‖u_y‖²) with the plate's exact clip rule
    // (plate::norms::l2_error, an independent algorithm) and the plate's unit mass on the same
    // mesh (same node and cell numbering, same eliminated face x = 1). Both are exact: they agree
    // to round-off, 64 ε times the number of cells (800) relative.
    // mutation: the cut integral's e_lo·e_hi term dropped -> fails at t = 0 (5.441e-3 against 5.598e-3).
    let solid = spec(Cell::Triangle, Material::LambdaZeroFree).problem(&MassKind::Mod3, 10.0).unwrap().system;
    let plate_spec = PlateSpec::structured(1.0, 1.0, 20, 20, Cell::Triangle, PlateInitial::Paper);
    let plate = PlateProblem::new(&plate_spec, &MassKind::Mod3).unwrap().system;
    let columns = Columns::new(&Mesh::structured_2d(1.0, 1.0, 20, 20, Cell::Triangle).unwrap());
    let closed = ImpactingBar { length: 1.0 };
    let (x, u, v) = massredist::exact::paper_data(1.0);
    let data = massredist::characteristics::InitialData::PiecewiseLinear { x: &x, u: &u, v: &v };
    let unit = massredist::material::Material { density: 1.0, modulus: 1.0 };
    let far = massredist::material::FarEnd::Clamped;
    let wave = massredist::exact::by_characteristics(1.0, unit, far, 0.0, data, 10.0).unwrap();
    let mut rnd = noise(7);
    let n = solid.mesh.points.len();
    for (k, t) in [0.0, 0.37, 1.0, 1.3, 1.5, 1.83, 2.5, 3.0, 7.21].into_iter().enumerate() {
        // Near the exact solution (scale 0.5) plus noise, so that the kinks matter.
        let amp = if k % 2 == 0 { 1e-2 } else { 1.0 };
        let field: Vec<[f64; 2]> =
            (0..n).map(|v| [closed.u(solid.mesh.points[v][0], t) + amp * rnd(), amp * rnd()]).collect();
        let u: Vec<f64> = solid.dofs.iter().map(|&g| field[g / 2][g % 2]).collect();
        let mut ux = vec![0.0; plate.dofs.len()];
        let mut uy = vec![0.0; plate.dofs.len()];
        for (v, d) in plate.node_dof.iter().enumerate() {
            if let Some(d) = *d {
                (ux[d], uy[d]) = (field[v][0], field[v][1]);
            }
        }
        let ex = massredist::plate::norms::l2_error(&plate, &ux, &closed, t);
        let ey = massredist::plate::norms::l2_norm(&plate, &uy);
        let want = (ex * ex + ey * ey).sqrt();
        let got = simplex_l2_error(&solid, &columns, &u, &wave, t);
        let tol = 800.0 * 64.0 * f64::EPSILON * want;
        assert!((got - want).abs() <= tol, "t = {t}: {got:e} against {want:e} (tolerance {tol:e})");
    }
}

/// `u` at (x, y) for a nodal field on a structured 2D mesh of (0, 1)² with `n` cells per side,
/// found through the mesh's own cells: bilinear on quads, barycentric on the triangle that
/// contains the point (independent of `elastic_reference`'s hand-written basis).
fn evaluate(mesh: &Mesh, n: usize, field: &[f64], x: f64, y: f64) -> f64 {
    let (i, j) = (((x * n as f64) as usize).min(n - 1), ((y * n as f64) as usize).min(n - 1));
    let square = j * n + i;
    let cells: Vec<usize> = if mesh.kind == Cell::Quad { vec![square] } else { vec![2 * square, 2 * square + 1] };
    for c in cells {
        let v = mesh.cell(c);
        let p = |k: usize| mesh.points[v[k]];
        if mesh.kind == Cell::Quad {
            let (s, t) = ((x - p(0)[0]) / (p(1)[0] - p(0)[0]), (y - p(0)[1]) / (p(3)[1] - p(0)[1]));
            let f = |k: usize| field[v[k]];
            return (1.0 - s) * (1.0 - t) * f(0) + s * (1.0 - t) * f(1) + s * t * f(2) + (1.0 - s) * t * f(3);
        }
        let (a, b, c3) = (p(0), p(1), p(2));
        let det = (b[0] - a[0]) * (c3[1] - a[1]) - (c3[0] - a[0]) * (b[1] - a[1]);
        let l1 = ((x - a[0]) * (c3[1] - a[1]) - (c3[0] - a[0]) * (y - a[1])) / det;
        let l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
        if l1 >= -1e-12 && l2 >= -1e-12 && l1 + l2 <= 1.0 + 1e-12 {
            return (1.0 - l1 - l2) * field[v[0]] + l1 * field[v[1]] + l2 * field[v[2]];
        }
    }
    panic!("({x}, {y}) in no cell");
}

#[test]
fn the_nested_distance_is_the_integral_of_the_squared_difference() {
    // ‖c − f‖² from (‖c‖², (φ, f), ‖f‖²) against a brute-force integral of (c − f)² over the
    // fine mesh: every fine square split along its diagonal into two triangles, each integrated
    // by the collapsed 4×4 Gauss rule (exact for degree 7 in the collapsed variables; (c − f)²
    // is of degree ≤ 4 on each half, since the coarse diagonal follows fine diagonals), c and f
    // evaluated through the meshes' own cells. Both are exact: they agree to round-off, 1e-13
    // of ‖c‖² + ‖f‖² (a few hundred terms of size ≤ 1 over 10⁴ points).
    // mutation: the triangles' diagonal squares integrated by 2×2 Gauss like the others (no
    // split in `Nested::new`) -> fails for the triangle coarse mesh (0.28160 against 0.28141).
    use massredist_study::paper::elastic_reference::{Nested, q1_square};
    let g4 = [
        (0.069_431_844_202_973_7, 0.173_927_422_568_726_9),
        (0.330_009_478_207_571_9, 0.326_072_577_431_273_1),
        (0.669_990_521_792_428_1, 0.326_072_577_431_273_1),
        (0.930_568_155_797_026_3, 0.173_927_422_568_726_9),
    ];
    let (n, r) = (5, 4);
    let fine_n = n * r;
    let fine = Mesh::structured_2d(1.0, 1.0, fine_n, fine_n, Cell::Quad).unwrap();
    let mut rnd = noise(11);
    let f: Vec<f64> = (0..fine.points.len()).map(|_| rnd()).collect();
    for kind in [Cell::Quad, Cell::Triangle] {
        let coarse = Mesh::structured_2d(1.0, 1.0, n, n, kind).unwrap();
        let c: Vec<f64> = (0..coarse.points.len()).map(|_| rnd()).collect();
        let nested = Nested::new(n, r, kind);
        let got = nested.distance_squared(&c, &nested.cross_products(&f), q1_square(fine_n, &f));
        let h = 1.0 / fine_n as f64;
        let mut want = 0.0;
        for j in 0..fine_n {
            for i in 0..fine_n {
                let (x0, y0) = (i as f64 * h, j as f64 * h);
                for &(u, wu) in &g4 {
                    for &(v, wv) in &g4 {
                        // Lower half: x = x0 + h u, y = y0 + h u v; upper: x = x0 + h u v, y = y0 + h u.
                        for (x, y) in [(x0 + h * u, y0 + h * u * v), (x0 + h * u * v, y0 + h * u)] {
                            let d = evaluate(&coarse, n, &c, x, y) - evaluate(&fine, fine_n, &f, x, y);
                            want += h * h * wu * wv * u * d * d;
                        }
                    }
                }
            }
        }
        let scale = nested.distance_squared(&c, &vec![0.0; c.len()], 0.0) + q1_square(fine_n, &f);
        assert!((got - want).abs() <= 1e-13 * scale, "{}: {got:e} against {want:e}", kind.name());
        // A nested Q1 function is its own prolongation: at distance 0 from its fine interpolant.
        if kind == Cell::Quad {
            let p: Vec<f64> = fine.points.iter().map(|q| evaluate(&coarse, n, &c, q[0], q[1])).collect();
            let d = nested.distance_squared(&c, &nested.cross_products(&p), q1_square(fine_n, &p));
            assert!(d.abs() <= 1e-13 * scale, "{d:e}");
        }
    }
}
