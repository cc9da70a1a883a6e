//! The solid's VTU frames for ParaView, written by the shared binary writer [`crate::fem::vtu`]
//! (which also reads them back): the point data `contact_pressure` (λ_c / ∫_{Γ_C} φ_c on the
//! contact nodes, 0 elsewhere), `displacement` and `velocity` (3-component vectors, z = 0 in 2D;
//! 0 where eliminated), and the cell data `weight` (the mass redistribution). "Warp By Vector"
//! with `displacement` shows the deformed solid.
//!
//! A body against a plane (`crate::solid::body`) writes its `contact_pressure` as the reaction
//! over the node's share of the contact area, `R_i / a_i = −λ_i / a_i ≥ 0`, and a fourth point
//! array `contact_state`: 1 on a contact node in contact, read off the force (`R_i > 0`, as the
//! summary's events: [`crate::driver::ContactStats::touching`]), 0 elsewhere. Every solid then
//! writes the friction arrays (issue 29; 0 without a friction law): `slip_state` (0 free, 1 stick, 2 slip, as the
//! summary's `final_stick_nodes`/`final_slip_nodes` count them) and `friction_traction`
//! (`r_t,i / a_i`, 3 world components).

use super::assembly::SolidSystem;
use crate::contact::friction::FrictionRecord;
use crate::fem::vtu::{Array, Grid, Layout, vtk_type, write_series};

/// Pads interleaved d-component nodal values to 3 components, into `out`.
fn to_3d(values: &[f64], d: usize, out: &mut Vec<f64>) {
    out.clear();
    out.extend(values.chunks(d).flat_map(|c| [c[0], c[1], if d == 3 { c[2] } else { 0.0 }]));
}

/// The frame layout of a solid: its mesh and weights serialised once, point arrays
/// `contact_pressure`, `displacement`, `velocity`.
pub fn layout(solid: &SolidSystem) -> Layout {
    let mesh = &solid.mesh;
    let grid = Grid { points: &mesh.points, cells: &mesh.cells, verts: mesh.kind.verts(), kind: vtk_type(mesh.kind) };
    let mut point_arrays = vec![("contact_pressure", 1), ("displacement", 3), ("velocity", 3)];
    if solid.frame.is_some() {
        point_arrays.push(("contact_state", 1));
    }
    point_arrays.extend([("slip_state", 1), ("friction_traction", 3)]);
    Layout::new(
        &grid,
        &point_arrays,
        "displacement",
        &[Array { name: "weight", components: 1, values: &solid.weights }],
    )
}

/// The point arrays of one state ([`layout`]'s order) into `arrays`: `u`, `v` nodal values
/// interleaved `node·d + component` (as [`crate::problem::GeometryView::nodal_values`] gives
/// them), λ in contact order, the step's friction.
fn point_arrays(
    solid: &SolidSystem,
    u: &[f64],
    v: &[f64],
    lambda: &[f64],
    friction: Option<&FrictionRecord>,
    arrays: &mut Vec<Vec<f64>>,
) {
    let mesh = &solid.mesh;
    let d = mesh.dim;
    assert!(u.len() == mesh.n_nodes() * d && v.len() == u.len() && lambda.len() == solid.contact_nodes.len());
    // A body's `contact_state` sits before the friction arrays.
    let body = usize::from(solid.frame.is_some());
    arrays.resize(5 + body, Vec::new());
    let pressure = &mut arrays[0];
    pressure.clear();
    pressure.resize(mesh.n_nodes(), 0.0);
    let sign = if solid.frame.is_some() { -1.0 } else { 1.0 };
    for ((&node, &l), &a) in solid.contact_nodes.iter().zip(lambda).zip(&solid.contact_areas) {
        pressure[node] = sign * l / a;
    }
    to_3d(u, d, &mut arrays[1]);
    to_3d(v, d, &mut arrays[2]);
    if solid.frame.is_some() {
        let state = &mut arrays[3];
        state.clear();
        state.resize(mesh.n_nodes(), 0.0);
        for (&node, &l) in solid.contact_nodes.iter().zip(lambda) {
            state[node] = if l < 0.0 { 1.0 } else { 0.0 };
        }
    }
    let (slip, traction) = arrays[3 + body..].split_at_mut(1);
    let (slip, traction) = (&mut slip[0], &mut traction[0]);
    slip.clear();
    slip.resize(mesh.n_nodes(), 0.0);
    traction.clear();
    traction.resize(3 * mesh.n_nodes(), 0.0);
    if let Some(f) = friction {
        for (i, &node) in solid.contact_nodes.iter().enumerate() {
            slip[node] = f64::from(f.state[i]);
            traction[3 * node..3 * node + 3].copy_from_slice(&f.traction[i]);
        }
    }
}

/// The `.vtu` of one frame ([`point_arrays`] for the arguments).
pub fn vtu_bytes(
    solid: &SolidSystem,
    u: &[f64],
    v: &[f64],
    lambda: &[f64],
    friction: Option<&FrictionRecord>,
) -> Vec<u8> {
    let mut arrays = Vec::new();
    point_arrays(solid, u, v, lambda, friction, &mut arrays);
    let refs: Vec<&[f64]> = arrays.iter().map(Vec::as_slice).collect();
    layout(solid).frame(&refs)
}

/// Writes `frames` as `vtu/frame_NNNNN.vtu` and the collection `solid.pvd` into `dir`.
pub fn write_frames(
    dir: &std::path::Path,
    solid: &SolidSystem,
    frames: &[crate::observe::Frame],
) -> std::io::Result<()> {
    let times: Vec<f64> = frames.iter().map(|f| f.t).collect();
    let layout = layout(solid);
    let mut arrays = Vec::new();
    write_series(dir, "solid", &times, |k| {
        let f = &frames[k];
        point_arrays(solid, &f.u, &f.v, &f.lambda, f.friction.as_ref(), &mut arrays);
        let refs: Vec<&[f64]> = arrays.iter().map(Vec::as_slice).collect();
        layout.frame(&refs)
    })
}

/// The solid's frames for the streaming writer ([`crate::fem::frames::FrameWriter`]).
impl crate::fem::frames::VtuFrames for SolidSystem {
    fn collection(&self) -> &'static str {
        "solid"
    }

    fn frame_layout(&self) -> Layout {
        layout(self)
    }

    fn point_arrays(
        &self,
        u: &[f64],
        v: &[f64],
        lambda: &[f64],
        friction: Option<&FrictionRecord>,
        arrays: &mut Vec<Vec<f64>>,
    ) {
        point_arrays(self, u, v, lambda, friction, arrays)
    }
}
