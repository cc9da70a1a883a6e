//! A solid scene's trajectory from the library API (`SolidSpec::problem` + the driver), for
//! checking the FEniCSx engine before `massredist run` takes `[solid]` scenes:
//!
//! ```text
//! cargo run --example solid_series -- SCENE.toml > series.csv
//! ```
//!
//! Columns: t, u_mean (plain mean of u_x over Γ_C), lambda (Σ λ_c / |Γ_C|), energy, min_uc.

use massredist::driver::{Observer, Sample, integrate};
use massredist::mass::MassKind;
use massredist::schemes::{Formulation, SchemeSpec};
use massredist::solid::spec::parse_solid;

struct Rows;

impl Observer for Rows {
    fn needs(&self) -> massredist::driver::Needs {
        massredist::driver::Needs { energy: true, ..Default::default() }
    }
    fn observe(&mut self, s: &Sample) {
        let st = s.state;
        let min_uc = s.geometry.contact().iter().map(|&i| st.u[i]).fold(f64::INFINITY, f64::min);
        println!("{},{},{},{},{}", st.t, s.u_mean, s.pressure, s.energy, min_uc);
    }
}

fn main() {
    let path = std::env::args().nth(1).expect("SCENE.toml");
    let table: toml::Table = std::fs::read_to_string(&path).unwrap().parse().unwrap();
    let spec = parse_solid(table["solid"].as_table().unwrap()).unwrap();
    let mass = match table["mass"]["kind"].as_str().unwrap() {
        "standard" => MassKind::Standard,
        "mod1" => MassKind::Mod1,
        "mod2" => MassKind::Mod2,
        _ => MassKind::Mod3,
    };
    let scheme = match table["scheme"]["kind"].as_str().unwrap() {
        "backward-euler" => SchemeSpec::BackwardEuler,
        "hybrid" => SchemeSpec::Hybrid,
        _ => SchemeSpec::CrankNicolson { formulation: Formulation::Full },
    };
    let num = |k: &str| table["time"][k].as_float().unwrap();
    let (dt, end) = (num("dt"), num("end"));
    let problem = spec.problem(&mass, end).unwrap();
    let mut s = problem.scheme(&scheme, dt).unwrap();
    println!("t,u_mean,lambda,energy,min_uc");
    integrate(&problem, s.as_mut(), (end / dt).round() as usize, &mut [&mut Rows]).unwrap();
}
