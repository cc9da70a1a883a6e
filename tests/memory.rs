//! Issue 22 D3: what cannot fit in memory is refused before it is allocated, naming the keys,
//! the estimate and the limit (exit 2), instead of aborting in an allocation.
//!
//! One test in this binary: it sets the process-wide factor limit
//! (`massredist::linalg::set_memory_limit`), which no other test may see.

use std::process::Command;

#[test]
fn what_cannot_fit_is_refused_before_it_is_allocated() {
    // 1. The assembly estimate, at validation: a 10000 × 31 × 31 hex solid (9.6e6 cells,
    //    inside the 1e7-cell cap) needs at least 354 GB for its element triplets. Before the fix
    //    `check` began assembling it and aborted in an allocation (the starting commit's binary:
    //    exit 134, SIGABRT), which this assertion on exit 2 catches.
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("long.toml");
    std::fs::write(&scene, "[solid]\ndim = 3\nnx = 10000\nny = 31\nnz = 31\n[time]\ndt = 0.01\nend = 0.01\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_massredist")).arg("check").arg(&scene).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("solid.nx") && err.contains("GB") && err.contains("memory limit"), "{err}");
    assert!(!dir.path().join("out").exists());

    // 2. The factor, exactly, after its symbolic analysis and before its values are allocated:
    //    with a 64 kB limit a 40 × 40 plate's factor (tens of thousands of values) is refused,
    //    naming the matrix, its size and the limit; with no limit it is set up. Mutation: the
    //    check in `SparseLlt::with_trailing` removed -> the setup succeeds -> fails.
    let plate =
        massredist::scene::PlateScene::from_toml("[plate]\nnx = 40\nny = 40\n[time]\ndt = 0.01\nend = 0.01\n").unwrap();
    massredist::linalg::set_memory_limit(1 << 16);
    let refused = massredist::run::setup(&plate).err().expect("refused").to_string();
    massredist::linalg::set_memory_limit(u64::MAX);
    assert!(refused.contains("Cholesky factor") && refused.contains("memory limit of 0.00 GB"), "{refused}");
    assert!(massredist::run::setup(&plate).is_ok());

    // 3. What the run holds already counts (issue 32, E4: the first factor of a 1200² plate
    //    fitted the limit on its own, the second aborted the run at 4 GB). With 1 GB allowed
    //    and all but 1 MB of it held, the ordering of the first matrix is refused, naming what
    //    is left. Mutation: the measure ignored (`memory_left` = `memory_limit`) -> the setup
    //    succeeds -> fails.
    massredist::linalg::set_memory_limit(1 << 30);
    massredist::linalg::set_memory_in_use(|| (1 << 30) - (1 << 20));
    let refused = massredist::run::setup(&plate).err().expect("refused").to_string();
    massredist::linalg::set_memory_in_use(|| 0);
    massredist::linalg::set_memory_limit(u64::MAX);
    assert!(refused.contains("0.00 GB left of the memory limit of 1.07 GB"), "{refused}");
    assert!(refused.contains("the run holds 1.07 GB already"), "{refused}");

    // 4. The divergence watch's own factor (`E_F = ½ F_rᵀ S_rr⁻¹ F_r`, factored when the run
    //    starts) refused by the limit is the run's set-up error, not a silent fall-back to the
    //    free-flight scale. The measure lets the set-up's checks pass (counted on a first
    //    set-up) and refuses every later one. Before the fix the run went on (Ok).
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    static ALLOWED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(usize::MAX);
    use std::sync::atomic::Ordering::SeqCst;
    let loaded = massredist::scene::SolidScene::from_toml(
        "[solid]\ndim = 2\nnx = 8\nny = 4\nforce = [0.0, -1.0]\n[time]\ndt = 0.01\nend = 0.02\n",
    )
    .unwrap();
    massredist::linalg::set_memory_limit(1 << 40);
    massredist::linalg::set_memory_in_use(|| {
        let n = CALLS.fetch_add(1, SeqCst);
        if n < ALLOWED.load(SeqCst) { 0 } else { 1 << 40 }
    });
    massredist::run::setup(&loaded).expect("set up with every check passing");
    ALLOWED.store(CALLS.swap(0, SeqCst), SeqCst);
    let refused = massredist::run::run_scene(&loaded, &mut []).err().expect("refused");
    massredist::linalg::set_memory_in_use(|| 0);
    massredist::linalg::set_memory_limit(u64::MAX);
    assert!(refused.invalid_input(), "{refused}");
    assert!(refused.to_string().contains("stiffness matrix"), "{refused}");

    // 5. Under `ulimit -v` (the command line reads it, and the address space the process holds,
    //    from /proc): a 300² plate with 160 MB. Its set-up peaks near 260 MB of address space
    //    (measured: `VmPeak` 256 MB at its first factor); the estimate at validation (3× its
    //    69 MB of assembly buffers, the measured ratio: 0.21 GB) exceeds even the whole limit
    //    (15/16 of 160 MB), whatever the process holds, so it is refused naming plate.nx before
    //    any assembly. (At 250 MB the outcome depended on the binary's own address space: the
    //    debug build passed validation and was refused at set-up.) Before the fix `check`
    //    passed validation and aborted (exit 134, the binary at 014a145, at 160, 200 and 250 MB).
    let scene = dir.path().join("plate300.toml");
    std::fs::write(&scene, "[plate]\nnx = 300\nny = 300\n[time]\ndt = 0.0001\nend = 0.0003\n").unwrap();
    let out = Command::new("bash")
        .arg("-c")
        .arg("ulimit -v 163840 && exec \"$0\" check \"$1\"")
        .arg(env!("CARGO_BIN_EXE_massredist"))
        .arg(&scene)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("plate.nx, plate.ny: setting this mesh up takes about 0.21 GB"), "{err}");
}
