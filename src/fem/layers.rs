//! Mass redistribution in 2D and 3D: one weight per cell, generalising the paper's §3
//! definitions, for the one [`Mesh`] of plates and solids.
//!
//! In 1D the contact node x = 0 belongs to element 0 only, so `w_0 = 0` makes it massless.
//! In 2D and 3D a contact node belongs to every cell that has it as a vertex, so:
//!
//! - layer 0 = the cells holding a contact node (a vertex on Γ_C = {x = 0} for boxes, any node of
//!   the contact set of a body: [`layers_of`]) (weight 0: all contact nodes massless);
//! - layer 1 = the other cells sharing a node with a layer-0 cell.
//!
//! A node whose every cell has weight 0 is massless. That is allowed when the node is clamped
//! or belongs to a layer-0 cell (contact nodes, and e.g. the edge nodes of second-order cells
//! inside the contact layer, which are then quasi-static without a contact law); any other
//! massless node makes the mass matrix singular where inertia is needed, and is refused.
//!
//! With `A_0`, `A_1` the areas (volumes) of layers 0 and 1 and `|Ω|` the total one:
//! - (Mod 1) nowhere: every other cell has weight 1, total mass `|Ω| − A_0`;
//! - (Mod 2) uniformly: every other cell has weight `|Ω|/(|Ω| − A_0)`, total mass `|Ω|`;
//! - (Mod 3) to the next layer: layer 1 has weight `1 + A_0/A_1`, the rest 1, total mass `|Ω|`;
//! - `standard`: all weights 1; `custom`: one given weight per cell.
//!
//! On a structured nx × ny (× nz) mesh (quads, one-diagonal triangles, hexahedra or the tets of
//! a conforming split of each hexahedron) layer 0 is the first column of squares (cubes) and
//! layer 1 the second, so Mod 2 gives `nx/(nx − 1)` and Mod 3 gives 2: the 1D
//! weights of [`crate::mass::MassKind`] column by column. The weights then depend on x only,
//! which the reduction of Q1 to the 1D problem needs.

use super::mesh::Mesh;
use crate::mass::MassKind;
use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum LayerMassError {
    #[error("mass.weights has {given} entries but the mesh has {cells} cells (one weight per cell, in mesh order)")]
    WrongCount { given: usize, cells: usize },
    #[error("mass.weights[{cell}] = {value}: weights must be finite and >= 0")]
    InvalidWeight { cell: usize, value: f64 },
    #[error(
        "node {node} at ({}) belongs to no cell of the contact layer (layer 0) and all its cells have weight 0: the mass matrix is singular there (only clamped nodes and nodes of layer-0 cells may be massless)",
        point(at)
    )]
    MasslessNode { node: usize, at: Vec<f64> },
    #[error(
        "mass.kind = \"{kind}\" needs cells beyond the contact layer (layer 0: the cells holding a contact node, x = 0 for a box; the mesh has {layer0} of {cells} cells in it)"
    )]
    NoSecondLayer { kind: &'static str, layer0: usize, cells: usize },
}

/// "x, y" or "x, y, z".
fn point(at: &[f64]) -> String {
    at.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(", ")
}

/// The box's node sets: `(contact, clamped)` masks, x = 0 and x = L.
fn box_sets(mesh: &Mesh) -> (Vec<bool>, Vec<bool>) {
    let n = mesh.n_nodes();
    ((0..n).map(|v| mesh.on_contact(v)).collect(), (0..n).map(|v| mesh.on_dirichlet(v)).collect())
}

/// Layer index of every cell of a box: 0 touches Γ_C = {x = 0}, 1 shares a node with layer 0,
/// 2 for the rest ([`layers_of`] with the nodes on x = 0).
pub fn layers(mesh: &Mesh) -> Vec<u8> {
    layers_of(mesh, &box_sets(mesh).0)
}

/// Layer index of every cell for the contact nodes `contact` (a mask over the nodes): 0 holds a
/// contact node, 1 shares a node with layer 0, 2 for the rest.
pub fn layers_of(mesh: &Mesh, contact: &[bool]) -> Vec<u8> {
    let n = mesh.n_cells();
    let mut layer = vec![2u8; n];
    let mut near = vec![false; mesh.n_nodes()];
    for (c, l) in layer.iter_mut().enumerate() {
        if mesh.cell(c).iter().any(|&v| contact[v]) {
            *l = 0;
            for &v in mesh.cell(c) {
                near[v] = true;
            }
        }
    }
    for (c, l) in layer.iter_mut().enumerate() {
        if *l != 0 && mesh.cell(c).iter().any(|&v| near[v]) {
            *l = 1;
        }
    }
    layer
}

/// The cell weights of a mass redistribution on a box, validated (see [`validate_weights`]).
pub fn cell_weights(mesh: &Mesh, kind: &MassKind) -> Result<Vec<f64>, LayerMassError> {
    let (contact, clamped) = box_sets(mesh);
    cell_weights_of(mesh, kind, &contact, &clamped)
}

/// The cell weights of a mass redistribution for the contact and clamped node masks, validated
/// ([`validate_weights_of`]).
pub fn cell_weights_of(
    mesh: &Mesh,
    kind: &MassKind,
    contact: &[bool],
    clamped: &[bool],
) -> Result<Vec<f64>, LayerMassError> {
    let n = mesh.n_cells();
    let layer = layers_of(mesh, contact);
    let area = |l: u8| -> f64 { (0..n).filter(|&c| layer[c] == l).map(|c| mesh.measure(c)).sum() };
    let (a0, a1, total) = (area(0), area(1), (0..n).map(|c| mesh.measure(c)).sum::<f64>());
    let needs_layer1 = |kind: &'static str| {
        if a1 > 0.0 {
            Ok(())
        } else {
            Err(LayerMassError::NoSecondLayer { kind, layer0: layer.iter().filter(|&&l| l == 0).count(), cells: n })
        }
    };
    let by_layer = |w0: f64, w1: f64, w2: f64| layer.iter().map(|&l| [w0, w1, w2][l as usize]).collect::<Vec<f64>>();
    let w = match kind {
        MassKind::Standard => vec![1.0; n],
        MassKind::Mod1 => {
            needs_layer1("mod1")?;
            by_layer(0.0, 1.0, 1.0)
        }
        MassKind::Mod2 => {
            needs_layer1("mod2")?;
            let w = total / (total - a0);
            by_layer(0.0, w, w)
        }
        MassKind::Mod3 => {
            needs_layer1("mod3")?;
            by_layer(0.0, 1.0 + a0 / a1, 1.0)
        }
        MassKind::Custom(w) => w.clone(),
    };
    validate_weights_of(mesh, &w, &layer, clamped)?;
    Ok(w)
}

/// [`validate_weights_of`] on a box (contact x = 0, clamped x = L).
pub fn validate_weights(mesh: &Mesh, w: &[f64]) -> Result<(), LayerMassError> {
    let (contact, clamped) = box_sets(mesh);
    validate_weights_of(mesh, w, &layers_of(mesh, &contact), &clamped)
}

/// Checks count, finiteness and sign, and that every node that is neither clamped nor in a
/// layer-0 cell (`layer` from [`layers_of`]) has a cell of positive weight (its mass-matrix
/// diagonal `Σ_c w_c ∫_c φ_i²` is then positive).
pub fn validate_weights_of(mesh: &Mesh, w: &[f64], layer: &[u8], clamped: &[bool]) -> Result<(), LayerMassError> {
    if w.len() != mesh.n_cells() {
        return Err(LayerMassError::WrongCount { given: w.len(), cells: mesh.n_cells() });
    }
    if let Some((cell, &value)) = w.iter().enumerate().find(|(_, v)| !(v.is_finite() && **v >= 0.0)) {
        return Err(LayerMassError::InvalidWeight { cell, value });
    }
    // Nodes with mass, or allowed to have none (clamped, or in a layer-0 cell).
    let mut fine = clamped.to_vec();
    for (c, &wc) in w.iter().enumerate() {
        if wc > 0.0 || layer[c] == 0 {
            for &v in mesh.cell(c) {
                fine[v] = true;
            }
        }
    }
    if let Some(node) = (0..mesh.n_nodes()).find(|&v| !fine[v]) {
        return Err(LayerMassError::MasslessNode { node, at: mesh.points[node][..mesh.dim].to_vec() });
    }
    Ok(())
}

/// Total mass `Σ_c w_c |c| = ∫_Ω w_h`.
pub fn total_mass(mesh: &Mesh, w: &[f64]) -> f64 {
    w.iter().enumerate().map(|(c, wc)| wc * mesh.measure(c)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::Cell;

    #[test]
    fn structured_weights_follow_the_1d_ones_column_by_column() {
        for kind in [Cell::Quad, Cell::Triangle] {
            let mesh = Mesh::structured_2d(1.0, 1.0, 5, 3, kind).unwrap();
            let per_square = if kind == Cell::Quad { 1 } else { 2 };
            for mass in [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3] {
                let w2 = cell_weights(&mesh, &mass).unwrap();
                let w1 = mass.weights(5).unwrap();
                for (c, w) in w2.iter().enumerate() {
                    let column = (c / per_square) % 5;
                    // Same formula, same operations up to the area ratio: a few ulps.
                    assert!(
                        (w - w1[column]).abs() <= 8.0 * f64::EPSILON,
                        "{mass:?} {kind:?} cell {c}: {w} vs {}",
                        w1[column]
                    );
                }
            }
        }
    }
}
