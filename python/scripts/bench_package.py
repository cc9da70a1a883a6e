"""The cost of running a scene from Python against the CLI (issue 21: "running the paper's
Figure 11 scene from Python costs at most 1.1x the CLI run").

Usage (from the repository root, with the package installed and the release binary built):
    target/python/venv/bin/python python/scripts/bench_package.py [scene] [runs]

Prints the median wall time of (a) one ``massredist.run(massredist.load(scene))`` call in this
interpreter (the scene read, set up, run; results as numpy arrays), (b) one ``massredist run``
process of the CLI (start-up, the same work, its output folder written), and their ratio; then
the one-off cost of starting an interpreter that imports the package (``python -c "import
massredist"``), which a session pays once whatever it runs.
"""

import statistics
import subprocess
import sys
import tempfile
import time

import massredist as mr


def median_seconds(f, runs: int) -> float:
    f()  # warm-up (page cache, first-call set-up)
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    scene = sys.argv[1] if len(sys.argv) > 1 else "scenes/fig11-mod3.toml"
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    cli = "target/release/massredist"
    with tempfile.TemporaryDirectory() as tmp:
        out = f"{tmp}/out"

        def in_python() -> None:
            assert mr.run(mr.load(scene)).ok

        def by_cli() -> None:
            cmd = [cli, "run", scene, "--out", out, "--force"]
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

        def interpreter() -> None:
            subprocess.run([sys.executable, "-c", "import massredist"], check=True)

        a = median_seconds(in_python, runs)
        b = median_seconds(by_cli, runs)
        c = median_seconds(interpreter, max(runs // 20, 5))
    print(f"scene {scene}, medians of {runs} runs")
    print(f"massredist.run in this interpreter : {a * 1e3:9.3f} ms")
    print(f"massredist run (CLI process)       : {b * 1e3:9.3f} ms")
    print(f"ratio Python / CLI                 : {a / b:9.3f}")
    print(f"one-off: python -c 'import massredist': {c * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
