//! VTK XML output for ParaView: one `.vtu` (UnstructuredGrid, ASCII) per frame and a `.pvd`
//! collection with the frame times, plus a reader for the files written here (read-back tests).
//!
//! Each frame has the points (z = 0), the cells (VTK_QUAD = 9 or VTK_TRIANGLE = 5), the point
//! data `u` and `v` (0 on Γ_D) and `warp` = (0, 0, u) (for "Warp By Vector"), and the cell data
//! `weight` (the mass redistribution). Numbers are written with Rust's shortest round-trip
//! formatting, so reading them back gives the same `f64` bit for bit. [`FrameWriter`] streams
//! the frames of a run as they are produced.

use super::mesh::{CellKind, Mesh2d};
use crate::numfmt::Shortest;
use std::io::Write;

/// VTK cell type codes.
pub fn vtk_type(kind: CellKind) -> u8 {
    match kind {
        CellKind::Quad => 9,
        CellKind::Triangle => 5,
    }
}

fn data_array<W: Write + ?Sized>(
    out: &mut W,
    name: &str,
    components: usize,
    values: impl Iterator<Item = f64>,
) -> std::io::Result<()> {
    write!(
        out,
        "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">\n         "
    )?;
    for (k, x) in values.enumerate() {
        if k > 0 && k % 12 == 0 {
            out.write_all(b"\n         ")?;
        }
        write!(out, " {}", Shortest(x))?;
    }
    out.write_all(b"\n        </DataArray>\n")
}

fn int_array<W: Write + ?Sized>(
    out: &mut W,
    name: &str,
    ty: &str,
    values: impl Iterator<Item = usize>,
) -> std::io::Result<()> {
    write!(out, "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">\n         ")?;
    for (j, x) in values.enumerate() {
        if j > 0 && j % 20 == 0 {
            out.write_all(b"\n         ")?;
        }
        write!(out, " {x}")?;
    }
    out.write_all(b"\n        </DataArray>\n")
}

/// Writes the `.vtu` text of one frame: `u`, `v` at every mesh node, `weights` per cell.
pub fn write_vtu<W: Write + ?Sized>(
    out: &mut W,
    mesh: &Mesh2d,
    u: &[f64],
    v: &[f64],
    weights: &[f64],
) -> std::io::Result<()> {
    assert!(u.len() == mesh.n_nodes() && v.len() == mesh.n_nodes() && weights.len() == mesh.n_cells());
    out.write_all(b"<?xml version=\"1.0\"?>\n")?;
    out.write_all(
        b"<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
    )?;
    out.write_all(b"  <UnstructuredGrid>\n")?;
    writeln!(out, "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">", mesh.n_nodes(), mesh.n_cells())?;
    out.write_all(b"      <PointData Scalars=\"u\" Vectors=\"warp\">\n")?;
    data_array(out, "u", 1, u.iter().copied())?;
    data_array(out, "v", 1, v.iter().copied())?;
    data_array(out, "warp", 3, u.iter().flat_map(|&x| [0.0, 0.0, x]))?;
    out.write_all(b"      </PointData>\n      <CellData Scalars=\"weight\">\n")?;
    data_array(out, "weight", 1, weights.iter().copied())?;
    out.write_all(b"      </CellData>\n      <Points>\n")?;
    data_array(out, "Points", 3, mesh.points.iter().flat_map(|p| [p[0], p[1], 0.0]))?;
    out.write_all(b"      </Points>\n      <Cells>\n")?;
    let k = mesh.kind.verts();
    int_array(out, "connectivity", "Int64", mesh.cells.iter().copied())?;
    int_array(out, "offsets", "Int64", (1..=mesh.n_cells()).map(|c| c * k))?;
    int_array(out, "types", "UInt8", (0..mesh.n_cells()).map(|_| vtk_type(mesh.kind) as usize))?;
    out.write_all(b"      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n")
}

/// The `.vtu` text of one frame ([`write_vtu`] into a string).
pub fn vtu_string(mesh: &Mesh2d, u: &[f64], v: &[f64], weights: &[f64]) -> String {
    let mut s = Vec::with_capacity(64 * mesh.n_nodes());
    write_vtu(&mut s, mesh, u, v, weights).expect("writing to memory");
    String::from_utf8(s).expect("ASCII")
}

const PVD_HEAD: &str = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
const PVD_TAIL: &str = "  </Collection>\n</VTKFile>\n";

/// One `<DataSet>` line of a `.pvd` collection.
fn write_pvd_entry<W: Write>(out: &mut W, t: f64, file: &str) -> std::io::Result<()> {
    writeln!(out, "    <DataSet timestep=\"{}\" part=\"0\" file=\"{file}\"/>", Shortest(t))
}

/// The `.pvd` collection of `(time, file)` frames (file names relative to the `.pvd`).
pub fn pvd_string(frames: &[(f64, String)]) -> String {
    let mut s = PVD_HEAD.as_bytes().to_vec();
    for (t, f) in frames {
        write_pvd_entry(&mut s, *t, f).expect("writing to memory");
    }
    s.extend_from_slice(PVD_TAIL.as_bytes());
    String::from_utf8(s).expect("ASCII")
}

// The reader of the files written here is the one of every mesh (`crate::fem::vtu`).
pub use crate::fem::vtu::{DataArray, VtuData, VtuError, read_pvd, read_vtu};

/// The plate's frames for the streaming writer: `u`, `v`, `warp` and `weight` ([`write_vtu`]).
impl crate::fem::frames::VtuFrames for super::PlateSystem {
    const COLLECTION: &'static str = "plate";

    fn write_vtu(&self, out: &mut dyn Write, u: &[f64], v: &[f64], _lambda: &[f64]) -> std::io::Result<()> {
        write_vtu(out, &self.mesh, u, v, &self.weights)
    }
}

/// The streaming frame writer of every geometry ([`crate::fem::frames`]).
pub use crate::fem::frames::FrameWriter;
