"""Python's leafdig.build_leaf against the same work in C++ (issue 30: a Python build of 100
leaves costs at most 5 % more than C++'s). Builds LEAVES leaves (the three samples in turn,
export mesh, metrics read as a dict) from Python, runs BM_BuildLeafAsModelBuild of
leafdig_bench for the C++ side, and prints both per leaf and their ratio. Then the same
leaves built by two Python threads at once against one (the GIL is released inside a build,
so two threads on two cores build nearly twice as many leaves a second). Numbers, not a
test: docs/benchmarks.md records them with the machine.

    PYTHONPATH=build/ci/python /usr/bin/python3 tests/bench/python_bench.py build/ci/tests/leafdig_bench [LEAVES]
"""
import json
import os
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

import leafdig

bench = sys.argv[1]
leaves = int(sys.argv[2]) if len(sys.argv) > 2 else 100
source = Path(__file__).resolve().parents[2]
names = ["lower-leaf-n10", "upper-small-leaf-n17", "upper-curved-leaf-n14"]  # model_bench.cpp's order
samples = [leafdig.read_markers(source / "data/samples" / (n + ".markers.json")) for n in names]


def python_ms_per_leaf():
    start = time.perf_counter()
    for k in range(leaves):
        leaf = leafdig.build_leaf(samples[k % 3])
        assert leaf.metrics["blade_area_mm2"] > 0
    return (time.perf_counter() - start) * 1000.0 / leaves


def cpp_ms_per_leaf():
    # Google Benchmark runs about as many leaves as Python builds (each takes ~0.15 s here).
    out = subprocess.run([bench, "--benchmark_filter=BM_BuildLeafAsModelBuild$", "--benchmark_format=json",
                          "--benchmark_min_time=%g" % (leaves * 0.15)], capture_output=True, text=True,
                         check=True).stdout
    run = json.loads(out)["benchmarks"][0]
    assert run["time_unit"] == "ms", run
    return run["real_time"]  # per iteration: one leaf


def threads_leaves_per_s(threads):
    # Each thread builds its share of the same leaves; the wall time of all of them.
    def work(first):
        for k in range(first, leaves, threads):
            assert leafdig.build_leaf(samples[k % 3]).metrics["blade_area_mm2"] > 0
    pool = [threading.Thread(target=work, args=(t,)) for t in range(threads)]
    start = time.perf_counter()
    for t in pool:
        t.start()
    for t in pool:
        t.join()
    return leaves / (time.perf_counter() - start)


rounds = int(os.environ.get("LEAFDIG_BENCH_ROUNDS", "3"))
py, cpp = [], []
for _ in range(rounds):  # interleaved, so a busy moment of the machine falls on both
    cpp.append(cpp_ms_per_leaf())
    py.append(python_ms_per_leaf())
one, two = [], []
for _ in range(rounds):
    one.append(threads_leaves_per_s(1))
    two.append(threads_leaves_per_s(2))
p, c = statistics.median(py), statistics.median(cpp)
o, t = statistics.median(one), statistics.median(two)
print(json.dumps({"leaves": leaves, "rounds": rounds, "python_ms_per_leaf": round(p, 2),
                  "cpp_ms_per_leaf": round(c, 2), "ratio": round(p / c, 4),
                  "python_rounds_ms": [round(x, 2) for x in py], "cpp_rounds_ms": [round(x, 2) for x in cpp],
                  "one_thread_leaves_per_s": round(o, 1), "two_threads_leaves_per_s": round(t, 1),
                  "two_threads_speed_up": round(t / o, 3), "cores": os.cpu_count()}))
