"""What a call through Python costs over the Rust call: the triangle
distance one pair per call, and batched (per pair), on the same 10,000
pairs (random triangles 1e-3 to 1e-1 apart), Python's calls timed here and
the Rust library's in the same run by `cargo run --example rust_answers --
--time` (one thread each: the batch below runs with RAYON_NUM_THREADS=1
unless told otherwise).

Usage: ``python python/benchmarks/overhead.py`` (from the repository, with
cargo on PATH)
"""

import json
import os
import pathlib
import subprocess
import tempfile
import time

import numpy as np

import nearmiss


def pairs(count: int, seed: int = 1):
    """Random triangles in the unit cube, the second moved off the first
    along a random direction so that they are 1e-3 to 1e-1 apart."""
    rng = np.random.default_rng(seed)
    a = rng.random((count, 3, 3))
    b = rng.random((count, 3, 3))
    # Separate each pair: shift b beyond a's extent, then bring it back to a
    # gap drawn log-uniformly in [1e-3, 1e-1].
    d = nearmiss.triangle_distances(a, b + 10.0)
    gap = 10.0 ** rng.uniform(-3, -1, count)
    b = b + 10.0 - (d - gap)[:, None, None] * np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
    return a, b


def best_of(runs: int, work) -> float:
    best = float("inf")
    for _ in range(runs):
        clock = time.perf_counter()
        work()
        best = min(best, time.perf_counter() - clock)
    return best


def rust_times(a, b):
    """The Rust library's ns per pair on (a, b): one a call, and batched."""
    root = pathlib.Path(__file__).resolve().parents[2]
    with tempfile.TemporaryDirectory() as folder:
        path = pathlib.Path(folder) / "pairs.f64"
        np.concatenate([a.ravel(), b.ravel()]).astype("<f8").tofile(path)
        run = subprocess.run(
            ["cargo", "run", "--quiet", "--release", "-p", "nearmiss-cli", "--example", "rust_answers", "--", "--time", str(path)],
            capture_output=True, text=True, cwd=root, check=True,
        )
    times = json.loads(run.stdout)
    return times["single_ns"], times["batched_ns"]


def main():
    a, b = pairs(10_000)
    rust_single, rust_batched = rust_times(a, b)
    single = best_of(5, lambda: [nearmiss.triangle_distance(x, y) for x, y in zip(a, b)]) / len(a)
    batched = best_of(20, lambda: nearmiss.triangle_distances(a, b)) / len(a)
    closest = best_of(10, lambda: nearmiss.triangle_closest_points(a, b)) / len(a)
    large_a, large_b = pairs(1_000_000, seed=2)
    large = best_of(5, lambda: nearmiss.triangle_distances(large_a, large_b)) / len(large_a)
    threads = os.environ.get("RAYON_NUM_THREADS")
    where = f"RAYON_NUM_THREADS={threads}" if threads else "batches on all cores"
    print(f"| call ({where}; Rust on one thread) | Python, per pair | Rust, per pair | Python's overhead |")
    print("|---|---|---|---|")
    print(f"| triangle_distance, one pair a call | {single * 1e9:.0f} ns | {rust_single:.0f} ns | {single * 1e9 - rust_single:.0f} ns a call |")
    print(f"| triangle_distances, 10,000 pairs | {batched * 1e9:.1f} ns | {rust_batched:.1f} ns | {batched * 1e9 - rust_batched:.1f} ns a pair |")
    print(f"| triangle_distances, 1,000,000 pairs | {large * 1e9:.1f} ns | — | — |")
    print(f"| triangle_closest_points, 10,000 pairs | {closest * 1e9:.1f} ns | {rust_single:.0f} ns (one a call) | {closest * 1e9 - rust_single:.1f} ns a pair |")


if __name__ == "__main__":
    main()
