//! The `[solid]` table's mesh keys: the box generator's (`length`, `height`, `depth`, `nx`,
//! `ny`, `nz`, `cells`), its size checked before any mesh is built, or `mesh`, the mesh read
//! from a file or given as arrays ([`crate::mesh_file`]).

use super::*;

/// A cell count in [min, 10000] (default 20).
fn count(key: &'static str, v: Option<i64>, min: i64, range: &'static str) -> Result<usize, SceneError> {
    match v.unwrap_or(20) {
        k if (min..=10_000).contains(&k) => Ok(k as usize),
        k => Err(SceneError::Range { key, value: k.to_string(), range }),
    }
}

/// The mesh of `solid.mesh` for a body: read at the edge, of the table's `dim`; any shape.
pub(super) fn body_file_mesh(t: &RawSolid, dim: usize, input: &MeshInput) -> Result<Mesh, SceneError> {
    let context = "solid.mesh (the mesh file gives the geometry)";
    for (key, v) in [("solid.length", &t.length), ("solid.height", &t.height), ("solid.depth", &t.depth)] {
        forbid(key, v, context)?;
    }
    for (key, v) in [("solid.nx", &t.nx), ("solid.ny", &t.ny), ("solid.nz", &t.nz)] {
        forbid(key, v, context)?;
    }
    forbid("solid.cells", &t.cells, context)?;
    Ok(crate::mesh_file::read_body_input("solid.mesh", input, dim)?)
}

/// The structured box of a `[solid]` table without `mesh`: extent, cells per axis, cell kind,
/// its size checked before any mesh is built.
pub(super) fn structured(t: &RawSolid, dim: usize) -> Result<([f64; 3], [usize; 3], Cell), SceneError> {
    let length = |key, v: Option<Number>| length_in(key, v.map_or(1.0, Number::get));
    let extent =
        [length("solid.length", t.length)?, length("solid.height", t.height)?, length("solid.depth", t.depth)?];
    let n = [
        count("solid.nx", t.nx, 2, "integers in [2, 10000]")?,
        count("solid.ny", t.ny, 1, "integers in [1, 10000]")?,
        count("solid.nz", t.nz, 1, "integers in [1, 10000]")?,
    ];
    let cells = match (dim, t.cells.as_deref().unwrap_or(if dim == 2 { "quad" } else { "hex" })) {
        (2, "quad") => Cell::Quad,
        (2, "triangle") => Cell::Triangle,
        (3, "hex") => Cell::Hex,
        (3, "tet") => Cell::Tet,
        (d, other) => {
            let range = if d == 2 { "quad | triangle (dim = 2)" } else { "hex | tet (dim = 3)" };
            return Err(SceneError::Range { key: "solid.cells", value: format!("\"{other}\""), range });
        }
    };
    check_size(dim, extent, n)?;
    Ok((extent, n, cells))
}

/// The mesh of `solid.mesh`: read by meshio, of the table's `dim`, filling the box
/// (0, L) × (0, H) [× (0, D)] (the contact face x = 0 and the lateral faces are the box's).
pub(super) fn file_mesh(
    t: &RawSolid,
    dim: usize,
    input: &MeshInput,
    path: &std::path::Path,
) -> Result<Mesh, SceneError> {
    let context = "solid.mesh (the mesh file gives the geometry)";
    forbid("solid.length", &t.length, context)?;
    forbid("solid.height", &t.height, context)?;
    forbid("solid.depth", &t.depth, context)?;
    forbid("solid.nx", &t.nx, context)?;
    forbid("solid.ny", &t.ny, context)?;
    forbid("solid.nz", &t.nz, context)?;
    forbid("solid.cells", &t.cells, context)?;
    let mesh = crate::mesh_file::read_input("solid.mesh", input)?;
    let bad = |what: String| SceneError::Range {
        key: "solid.mesh",
        value: format!("\"{}\" ({what})", path.display()),
        range: "a triangle or quad mesh (solid.dim = 2), a tetrahedron or hexahedron mesh (solid.dim = 3), filling the box (0, L) × (0, H) [× (0, D)]",
    };
    if mesh.dim != dim {
        return Err(bad(format!("a {}D mesh", mesh.dim)));
    }
    for axis in 1..dim {
        let lo = mesh.points.iter().map(|p| p[axis]).fold(f64::INFINITY, f64::min);
        if lo.abs() > 1e-12 * mesh.extent[axis] {
            return Err(bad(format!("smallest {} = {}", ["x", "y", "z"][axis], short(lo))));
        }
    }
    mesh.check_fills_box().map_err(|e| bad(e.to_string()))?;
    check_contact_memory((0..mesh.n_nodes()).filter(|&v| mesh.on_contact(v)).count(), "its face x = 0 in solid.mesh")?;
    Ok(mesh)
}

/// Sizes refused before a mesh is built: more than [`MAX_ELEMENTS`] cells, or cells so far from
/// cubes that the stiffness cannot be factored in double precision (as for plates). The contact
/// face's dense Schur complement is the compatibility rule's ([`crate::spec::compat`]).
fn check_size(dim: usize, extent: [f64; 3], n: [usize; 3]) -> Result<(), SceneError> {
    let axes = if dim == 2 { 2 } else { 3 };
    let cells: f64 = n[..axes].iter().map(|&k| k as f64).product();
    if cells > MAX_ELEMENTS as f64 {
        let keys = if dim == 2 { "solid.nx × solid.ny" } else { "solid.nx × solid.ny × solid.nz" };
        return Err(SceneError::Range {
            key: keys_of(dim),
            value: format!("{cells:e} cells ({keys})"),
            range: "at most 1e7 cells",
        });
    }
    // The contact face's Schur complement: checked by the compatibility rule, which knows the
    // scheme (`SceneGeometry::dense_contact`).
    let h: Vec<f64> = (0..axes).map(|a| extent[a] / n[a] as f64).collect();
    let (lo, hi) = h.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    if hi / lo > 1e6 {
        return Err(SceneError::Range {
            key: "solid.height",
            value: short(extent[1]),
            range: "cell edges (length/nx, height/ny[, depth/nz]) within a ratio of 1e6 of each other",
        });
    }
    Ok(())
}

pub(super) fn keys_of(dim: usize) -> &'static str {
    if dim == 2 { "solid.nx, solid.ny" } else { "solid.nx, solid.ny, solid.nz" }
}
