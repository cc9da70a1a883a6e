//! Scale of the body-mesh path (issue 19, item 8): reading a gmsh file of ~10⁶ cells and
//! assembling the solid's matrices against building the box mesh of the same cells and
//! assembling. Timed from outside, in release, e.g.
//!
//! ```text
//! cargo test --release --test gmsh_scale --no-run     # prints the binary
//! SCALE_MODE=write SCALE_N=707 BIN --ignored --exact scale   # writes /tmp/massredist-scale-707.msh
//! farm-bench -- env SCALE_MODE=file SCALE_N=707 BIN --ignored --exact scale \
//!   --vs 'env SCALE_MODE=box SCALE_N=707 BIN --ignored --exact scale'
//! ```
//!
//! The mesh: the unit square's N × N squares as 2 N² triangles (N = 707: 999 698 cells), the
//! file MSH 2.2 binary (written here, in the format gmsh writes). Plain `cargo test` skips it.

use massredist::fem::{Cell, Mesh};
use massredist::scene::mesh_file::read_body;
use massredist::solid::assembly::{Lame, assemble};
use std::io::Write;

fn path(n: usize) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("massredist-scale-{n}.msh"))
}

/// MSH 2.2 binary: nodes tagged 1.., triangles (type 2) with physical tag 1, entity 1.
fn write_msh(mesh: &Mesh, out: &std::path::Path) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(out)?);
    f.write_all(b"$MeshFormat\n2.2 1 8\n")?;
    f.write_all(&1i32.to_le_bytes())?;
    write!(f, "\n$EndMeshFormat\n$Nodes\n{}\n", mesh.n_nodes())?;
    for (i, p) in mesh.points.iter().enumerate() {
        f.write_all(&(i as i32 + 1).to_le_bytes())?;
        for x in p {
            f.write_all(&x.to_le_bytes())?;
        }
    }
    write!(f, "\n$EndNodes\n$Elements\n{}\n", mesh.n_cells())?;
    for x in [2i32, mesh.n_cells() as i32, 2] {
        f.write_all(&x.to_le_bytes())?;
    }
    for c in 0..mesh.n_cells() {
        for x in [c as i32 + 1, 1, 1] {
            f.write_all(&x.to_le_bytes())?;
        }
        for &v in mesh.cell(c) {
            f.write_all(&(v as i32 + 1).to_le_bytes())?;
        }
    }
    f.write_all(b"\n$EndElements\n")
}

#[test]
#[ignore = "a timing run (module docs)"]
fn scale() {
    let n: usize = std::env::var("SCALE_N").ok().and_then(|v| v.parse().ok()).unwrap_or(100);
    let mode = std::env::var("SCALE_MODE").unwrap_or_else(|_| "box".into());
    let lame = Lame { lambda: 20.0, mu: 20.0, density: 1.0 };
    let mesh = match mode.as_str() {
        "write" => {
            let m = Mesh::structured_2d(1.0, 1.0, n, n, Cell::Triangle).unwrap();
            write_msh(&m, &path(n)).unwrap();
            return;
        }
        "box" => Mesh::structured_2d(1.0, 1.0, n, n, Cell::Triangle).unwrap(),
        "file" => read_body("solid.mesh", &path(n), 2).unwrap(),
        other => panic!("SCALE_MODE = {other}: write | box | file"),
    };
    let (m, s) = assemble(&mesh, &vec![1.0; mesh.n_cells()], &lame).unwrap();
    // The two meshes are the same: the same matrix sizes and non-zeros.
    println!("{mode}: {} cells, {} + {} non-zeros", mesh.n_cells(), m.compute_nnz(), s.compute_nnz());
}
