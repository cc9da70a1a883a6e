//! The elastic candidates for the paper's 2D table (`massredist::paper::elastic_table`): the
//! λ = 0 Q1 rows are the scalar plate's Q1 rows, and the new exact error on triangles agrees with
//! the plate's independent exact rule (cells clipped at the kinks of the closed form).

use massredist::exact::ImpactingBar;
use massredist::fem::Cell;
use massredist::fem::Mesh;
use massredist::fem::columns::Columns;
use massredist::mass::MassKind;
use massredist::paper::elastic_table::{Material, linf_l2_errors, simplex_l2_error, spec};
use massredist::paper::plate_table;
use massredist::plate::PlateProblem;
use massredist::scene::{Formulation, PlateInitial, PlateSpec, SchemeSpec};

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
