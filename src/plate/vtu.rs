//! VTK XML output for ParaView: one `.vtu` (UnstructuredGrid, ASCII) per frame and a `.pvd`
//! collection with the frame times, plus a reader for the files written here (read-back tests).
//!
//! Each frame has the points (z = 0), the cells (VTK_QUAD = 9 or VTK_TRIANGLE = 5), the point
//! data `u` and `v` (0 on Γ_D) and `warp` = (0, 0, u) (for "Warp By Vector"), and the cell data
//! `weight` (the mass redistribution). Numbers are written with Rust's shortest round-trip
//! formatting, so reading them back gives the same `f64` bit for bit. [`FrameWriter`] streams
//! the frames of a run as they are produced.

use super::mesh::{CellKind, Mesh2d};
use crate::driver::{Observer, Sample};
use crate::numfmt::Shortest;
use std::io::Write;
use std::path::Path;

/// VTK cell type codes.
pub fn vtk_type(kind: CellKind) -> u8 {
    match kind {
        CellKind::Quad => 9,
        CellKind::Triangle => 5,
    }
}

fn data_array<W: Write>(
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

fn int_array<W: Write>(out: &mut W, name: &str, ty: &str, values: impl Iterator<Item = usize>) -> std::io::Result<()> {
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
pub fn write_vtu<W: Write>(out: &mut W, mesh: &Mesh2d, u: &[f64], v: &[f64], weights: &[f64]) -> std::io::Result<()> {
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

/// Streams VTU frames into a folder as the run produces them: every `every` steps it writes
/// `vtu/frame_NNNNN.vtu` and adds its line to `plate.pvd`, which [`FrameWriter::finish`] closes.
/// Memory holds one frame's nodal values, whatever the number of steps (a
/// [`crate::observe::FrameRecorder`] keeps the frames in memory instead). An observer cannot fail:
/// the first write error is kept, the run is halted ([`Observer::halted`]), and `finish` returns
/// it.
pub struct FrameWriter<'a> {
    dir: std::path::PathBuf,
    mesh: &'a Mesh2d,
    weights: &'a [f64],
    every: usize,
    frames: usize,
    pvd: std::io::BufWriter<std::fs::File>,
    u: Vec<f64>,
    v: Vec<f64>,
    name: String,
    error: Option<std::io::Error>,
}

impl<'a> FrameWriter<'a> {
    /// Creates `dir/vtu/` and `dir/plate.pvd` (its head written) for frames of `plate`.
    pub fn create(dir: &Path, plate: &'a super::PlateSystem, every: usize) -> std::io::Result<Self> {
        std::fs::create_dir(dir.join("vtu"))?;
        let mut pvd = std::io::BufWriter::new(std::fs::File::create(dir.join("plate.pvd"))?);
        pvd.write_all(PVD_HEAD.as_bytes())?;
        let n = plate.mesh.n_nodes();
        Ok(Self {
            dir: dir.to_path_buf(),
            mesh: &plate.mesh,
            weights: &plate.weights,
            every: every.max(1),
            frames: 0,
            pvd,
            u: vec![0.0; n],
            v: vec![0.0; n],
            name: String::with_capacity(32),
            error: None,
        })
    }

    /// Closes `plate.pvd`; the first write error if there was one.
    pub fn finish(mut self) -> std::io::Result<()> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.pvd.write_all(PVD_TAIL.as_bytes())?;
        self.pvd.flush()
    }

    fn write_frame(&mut self, t: f64) -> std::io::Result<()> {
        use std::fmt::Write as _;
        self.name.clear();
        let _ = write!(self.name, "vtu/frame_{:05}.vtu", self.frames);
        let mut f = std::io::BufWriter::new(std::fs::File::create(self.dir.join(&self.name))?);
        write_vtu(&mut f, self.mesh, &self.u, &self.v, self.weights)?;
        f.flush()?;
        write_pvd_entry(&mut self.pvd, t, &self.name)?;
        self.frames += 1;
        Ok(())
    }
}

impl Observer for FrameWriter<'_> {
    fn every(&self) -> usize {
        self.every
    }

    fn observe(&mut self, s: &Sample) {
        if self.error.is_some() {
            return;
        }
        s.geometry.nodal_values(s.state.u, &mut self.u);
        s.geometry.nodal_values(s.state.v, &mut self.v);
        if let Err(e) = self.write_frame(s.state.t) {
            self.error = Some(e);
        }
    }

    fn halted(&self) -> bool {
        self.error.is_some()
    }
}
