//! Streaming VTU frames of any geometry: [`FrameWriter`] writes `vtu/frame_NNNNN.vtu` every
//! `every` steps as the run produces them and adds its line to `<collection>.pvd`, which
//! [`FrameWriter::finish`] closes. Memory holds one frame's nodal values, whatever the number of
//! steps (a [`crate::observe::FrameRecorder`] keeps the frames in memory instead). What a frame
//! holds is the geometry's ([`VtuFrames`]: plates in `crate::plate::vtu`, solids in
//! `crate::solid::vtu`).
//!
//! An observer cannot fail: the first write error is kept, the run is halted
//! ([`Observer::halted`]), and `finish` returns it.

use crate::contact::friction::FrictionRecord;
use crate::driver::{Observer, Sample};
use crate::fem::vtu::Layout;
use crate::problem::GeometryView;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A geometry whose states are written as VTU frames.
pub trait VtuFrames: GeometryView {
    /// The name of the `.pvd` collection (`plate`, `solid`).
    fn collection(&self) -> &'static str;
    /// The layout of this geometry's frames: the mesh and the constant cell data, serialised
    /// once per run ([`Layout`]).
    fn frame_layout(&self) -> Layout;
    /// The point arrays of one state, in the layout's order, into `arrays` (buffers reused from
    /// frame to frame): `u`, `v` as [`GeometryView::nodal_values`] gives them, `lambda` the
    /// contact reactions in contact order, `friction` the step's friction (None without).
    fn point_arrays(
        &self,
        u: &[f64],
        v: &[f64],
        lambda: &[f64],
        friction: Option<&FrictionRecord>,
        arrays: &mut Vec<Vec<f64>>,
    );
}

const PVD_HEAD: &str = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
const PVD_TAIL: &str = "  </Collection>\n</VTKFile>\n";

/// Streams the frames of one run into a folder (module docs).
pub struct FrameWriter<'a> {
    dir: PathBuf,
    geometry: &'a dyn VtuFrames,
    /// The geometry's bytes, serialised once.
    layout: Layout,
    /// One frame's point arrays.
    arrays: Vec<Vec<f64>>,
    every: usize,
    frames: usize,
    pvd: std::io::BufWriter<std::fs::File>,
    u: Vec<f64>,
    v: Vec<f64>,
    name: String,
    error: Option<std::io::Error>,
}

impl<'a> FrameWriter<'a> {
    /// Creates `dir/vtu/` and `dir/<collection>.pvd` (its head written) for frames of `geometry`.
    pub fn create(dir: &Path, geometry: &'a dyn VtuFrames, every: usize) -> std::io::Result<Self> {
        std::fs::create_dir(dir.join("vtu"))?;
        let pvd = std::fs::File::create(dir.join(format!("{}.pvd", geometry.collection())))?;
        let mut pvd = std::io::BufWriter::new(pvd);
        pvd.write_all(PVD_HEAD.as_bytes())?;
        let n = geometry.n_nodes() * geometry.components();
        Ok(Self {
            dir: dir.to_path_buf(),
            geometry,
            layout: geometry.frame_layout(),
            arrays: Vec::new(),
            every: every.max(1),
            frames: 0,
            pvd,
            u: vec![0.0; n],
            v: vec![0.0; n],
            name: String::with_capacity(32),
            error: None,
        })
    }

    /// Closes the `.pvd`; the first write error if there was one.
    pub fn finish(mut self) -> std::io::Result<()> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.pvd.write_all(PVD_TAIL.as_bytes())?;
        self.pvd.flush()
    }

    /// Writes a frame recorded in memory ([`crate::observe::FrameRecorder`]: its values are
    /// at the mesh nodes already), as the observer writes a state (the Python package's
    /// `run(..., vtu_dir=)`).
    pub fn write_recorded(&mut self, frame: &crate::observe::Frame) -> std::io::Result<()> {
        self.u.copy_from_slice(&frame.u);
        self.v.copy_from_slice(&frame.v);
        self.write_frame(frame.t, &frame.lambda, frame.friction.as_ref())
    }

    fn write_frame(&mut self, t: f64, lambda: &[f64], friction: Option<&FrictionRecord>) -> std::io::Result<()> {
        use std::fmt::Write as _;
        self.name.clear();
        let _ = write!(self.name, "vtu/frame_{:05}.vtu", self.frames);
        let mut f = std::io::BufWriter::new(std::fs::File::create(self.dir.join(&self.name))?);
        self.geometry.point_arrays(&self.u, &self.v, lambda, friction, &mut self.arrays);
        let arrays: Vec<&[f64]> = self.arrays.iter().map(|a| &a[..]).collect();
        self.layout.write(&mut f, &arrays)?;
        f.flush()?;
        writeln!(
            self.pvd,
            "    <DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>",
            crate::numfmt::Shortest(t),
            self.name
        )?;
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
        if let Err(e) = self.write_frame(s.state.t, s.state.lambda, s.friction) {
            self.error = Some(e);
        }
    }

    fn halted(&self) -> bool {
        self.error.is_some()
    }
}
