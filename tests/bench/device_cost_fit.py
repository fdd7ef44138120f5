#!/usr/bin/env python3
"""Fits the constants of device=auto's cost model (core/src/device_cost.c).

Reads a folder of `pliant run SCENE --timings` files, two per scene:
  <scene>_cpu.json         --device cpu (16 threads on the GPU host)
  <scene>_gpu-always.json  --device gpu-always (else <scene>_auto.json, from
                           runs made before the cost model, when auto meant
                           the GPU)
  <scene>_auto.json        optional, beside gpu-always: what auto chose
The step time is the "Frame" phase's median.  The sizes the model reads are
the "cost: ..." statistics of those files; files written before they existed
take them from --sizes DIR (<scene>.json, e.g. from `pliant run SCENE -n 1
--device cpu --timings DIR/<scene>.json` on any machine: sizes do not depend
on it).  Fits, by non-negative least squares on relative errors, the CPU and
the GPU constants of each term, nnz(S)'s estimate (S_TET, S_TRI), PARTIAL and
FT_ITERATIONS (see device_cost.c), prints a table

  scene | CPU ms | GPU ms | predicted CPU | predicted GPU | choice | right?

and, with --write FILE, replaces the FITTED block of FILE (device_cost.c).
With --check FILE it fits nothing: the table of the choices FILE's constants
make on these timings (after a change that sped up one side, are they still
right?), exit 1 if one is wrong.
Python 3 standard library only (the GPU machine has no packages).

  python3 tests/bench/device_cost_fit.py DIR [--sizes DIR] [--write core/src/device_cost.c]
  python3 tests/bench/device_cost_fit.py DIR --check core/src/device_cost.c
  python3 tests/bench/device_cost_fit.py --selftest    (ctest device_cost_fit)
"""
import argparse
import json
import math
import os
import re
import statistics
import sys

TERMS = ["STEP", "ITER", "ARAP", "COROT", "NH", "NHTRI", "NHFLOOR", "SOLVE", "CR", "ROWS", "DETECT",
         "ELEMS"]
PARALLEL = {"ARAP", "COROT", "NH", "NHTRI", "SOLVE", "ROWS", "ELEMS"}
CAL_THREADS = 16
CLOSE = 0.10  # a wrong choice within 10% of the other device is "close"


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def frame_ms(j):
    return j["phases"]["Frame"]["median_ms"] if j and "Frame" in j.get("phases", {}) else None


def sizes_of(*docs):
    for d in docs:
        if d and "cost: vertices" in d.get("stats", {}):
            return {k[6:]: v for k, v in d["stats"].items() if k.startswith("cost: ")}
    return None


def read_scenes(folder, sizes_dir):
    names = sorted({re.sub(r"_(cpu|auto|gpu-always)\.json$", "", f) for f in os.listdir(folder)
                    if re.search(r"_(cpu|auto|gpu-always)\.json$", f)})
    scenes = []
    for n in names:
        cpu = load(os.path.join(folder, n + "_cpu.json"))
        gpu = load(os.path.join(folder, n + "_gpu-always.json"))
        auto = load(os.path.join(folder, n + "_auto.json"))
        if gpu is None:
            gpu, auto = auto, None
        size = sizes_of(cpu, gpu, auto)
        if size is None and sizes_dir:
            size = sizes_of(load(os.path.join(sizes_dir, n + ".json")))
        if not (frame_ms(cpu) and frame_ms(gpu) and size):
            print(f"skipped {n}: " + ("no sizes" if not size else "no CPU and GPU timings"),
                  file=sys.stderr)
            continue
        its = cpu.get("series", {}).get("iterations")
        if "S device memory [MB]" not in gpu.get("stats", {}):
            print(f"warning: {n}: the GPU run has no device statistics (did a GPU answer?)",
                  file=sys.stderr)
        scenes.append({"name": n, "cpu": frame_ms(cpu), "gpu": frame_ms(gpu),
                       "auto": frame_ms(auto), "z": size,
                       "nnz_s": cpu.get("stats", {}).get("nnz(S)"),
                       "iters_measured": statistics.median(its) if its else None})
    return scenes


def features(z, iterations, nnz_s, threads=CAL_THREADS, cpu=True):
    """The model's x_j, as device_cost.c's terms() (CPU: parallel terms scaled)."""
    k = max(iterations, 1)
    law = {l: z[l + " tetrahedra"] + z[l + " triangles"] for l in ("ARAP", "corotational")}
    nh_tets, nh_tris = z["Neo-Hookean tetrahedra"], z["Neo-Hookean triangles"]
    cr = (z["CR iterations"] or 1) if z["constraints"] > 0 else 0
    sv = z["surface vertices"]
    x = {"STEP": 1, "ITER": k, "ARAP": k * law["ARAP"] / 1e3,
         "COROT": k * law["corotational"] / 1e3, "NH": k * nh_tets / 1e3,
         "NHTRI": k * nh_tris / 1e3, "NHFLOOR": k if nh_tets > 0 else 0,
         "SOLVE": k * nnz_s / 1e6, "CR": k * cr, "ROWS": k * cr * sv / 1e3, "DETECT": sv / 1e3,
         "ELEMS": (sum(law.values()) + nh_tets + nh_tris) / 1e3}
    scale = CAL_THREADS / threads if cpu else 1.0
    return [x[t] * (scale if (cpu and t in PARALLEL) else 1.0) for t in TERMS]


def nnls(rows, y, sweeps=20000):
    """min sum (y_i - a_i.c)^2 over c >= 0: coordinate descent on the normal
    equations, columns scaled to unit norm."""
    m = len(rows[0])
    norms = [math.sqrt(sum(r[j] ** 2 for r in rows)) or 1.0 for j in range(m)]
    a = [[r[j] / norms[j] for j in range(m)] for r in rows]
    g = [[sum(r[i] * r[j] for r in a) for j in range(m)] for i in range(m)]
    b = [sum(r[i] * yy for r, yy in zip(a, y)) for i in range(m)]
    c = [0.0] * m
    for _ in range(sweeps):
        delta = 0.0
        for i in range(m):
            if g[i][i] <= 0:
                continue
            r = b[i] - sum(g[i][j] * c[j] for j in range(m))
            new = max(0.0, c[i] + r / g[i][i])
            delta = max(delta, abs(new - c[i]))
            c[i] = new
        if delta < 1e-13:
            break
    return [c[j] / norms[j] for j in range(m)]


def fit_relative(xs, ys):
    return nnls([[v / y for v in x] for x, y in zip(xs, ys)], [1.0] * len(ys))


def fit_s(scenes):
    """nnz(S) ~ S_TET s_tet + S_TRI s_tri, relative least squares."""
    pts = [(s["z"]["S basis tetrahedra"], s["z"]["S basis triangles"], s["nnz_s"]) for s in scenes
           if s["nnz_s"]]
    c = fit_relative([[a, b] for a, b, _ in pts], [n for _, _, n in pts])
    return c[0], c[1]


def fit(scenes, partial_before=1.0):
    s_tet, s_tri = fit_s(scenes)
    ft = [s["iters_measured"] for s in scenes if s["z"]["force tolerance"] and s["iters_measured"]]
    ft_iterations = int(round(statistics.median(ft))) if ft else 100
    for s in scenes:
        z = s["z"]
        s["nnz_est"] = s_tet * z["S basis tetrahedra"] + s_tri * z["S basis triangles"]
        s["k_fit"] = s["iters_measured"] or z["iterations"]
    cpu = fit_relative([features(s["z"], s["k_fit"], s["nnz_est"]) for s in scenes],
                       [s["cpu"] for s in scenes])
    full = [s for s in scenes if s["z"]["device path"] and s["z"]["sparse inverse"]]
    gpu = fit_relative([features(s["z"], s["k_fit"], s["nnz_est"], cpu=False) for s in full],
                       [s["gpu"] for s in full])
    part = [s["gpu"] / s["cpu"] for s in scenes
            if not s["z"]["device path"] and s["z"]["sparse inverse"]]
    # no scene without a device path (every scene of scenes/ has one now): keep
    # the ratio fitted before rather than invent one
    partial = statistics.median(part) if part else partial_before
    return {"CPU_MS": cpu, "GPU_MS": gpu, "S_TET": s_tet, "S_TRI": s_tri, "PARTIAL": partial,
            "FT_ITERATIONS": ft_iterations}


def predict(k, z, threads=CAL_THREADS):
    """device_cost.c's pl_device_cost_predict, with the C side's iteration count."""
    its = z["iterations"]
    nnz = k["S_TET"] * z["S basis tetrahedra"] + k["S_TRI"] * z["S basis triangles"]
    cpu = sum(c * x for c, x in zip(k["CPU_MS"], features(z, its, nnz, threads)))
    gpu = sum(c * x for c, x in zip(k["GPU_MS"], features(z, its, nnz, cpu=False)))
    if not z["sparse inverse"]:
        gpu = cpu
    elif not z["device path"]:
        gpu = k["PARTIAL"] * cpu
    return cpu, gpu


def verdict(s, gpu_chosen):
    best, other = (s["gpu"], s["cpu"]) if gpu_chosen else (s["cpu"], s["gpu"])
    if best <= other:
        return "yes"
    return "close" if best <= other * (1 + CLOSE) else "NO"


def c_block(k):
    def arr(name, v):
        items = [f"{c:.4g}" for c in v]
        lines = [", ".join(items[i:i + 6]) for i in range(0, len(items), 6)]
        return (f"static const double {name}[NTERMS] = {{\n    " + ",\n    ".join(lines) +
                "};\n")
    return (f"/* {' '.join(TERMS)} */\n" + arr("CPU_MS", k["CPU_MS"]) + arr("GPU_MS", k["GPU_MS"]) +
            f"static const double S_TET = {k['S_TET']:.4g}, S_TRI = {k['S_TRI']:.4g}, "
            f"PARTIAL = {k['PARTIAL']:.3g};\n"
            f"static const int CAL_THREADS = {CAL_THREADS}, FT_ITERATIONS = {k['FT_ITERATIONS']};\n")


def selftest():
    """Timings made by known constants through the whole path (files, fit,
    table, --write): the fit must predict them within 2% and choose right."""
    import random
    import tempfile
    rng = random.Random(16)
    truth = {"CPU_MS": [0.05, 0.16, 0.07, 0.07, 0.13, 0.1, 0.11, 0.02, 0.004, 0.001, 2.0, 0.01],
             "GPU_MS": [0.3, 0.04, 0.001, 0.003, 0.02, 0.004, 0.5, 0.05, 0.01, 0.03, 2.0, 0.0],
             "S_TET": 6.0, "S_TRI": 4.0, "PARTIAL": 0.8, "FT_ITERATIONS": 80}
    laws = ["ARAP", "corotational", "Neo-Hookean"]
    with tempfile.TemporaryDirectory() as d:
        for i in range(40):
            n = int(10 ** rng.uniform(2, 4.5))
            tets = rng.random() < 0.6
            z = {f"{l} {k}": 0 for l in laws for k in ("tetrahedra", "triangles")}
            z[f"{rng.choice(laws)} {'tetrahedra' if tets else 'triangles'}"] = n * (5 if tets else 2)
            contact = rng.random() < 0.5
            z.update({"vertices": n, "S basis tetrahedra": n ** (4 / 3) if tets else 0,
                      "S basis triangles": 0 if tets else n * math.log2(n),
                      "iterations": rng.choice([5, 10]), "force tolerance": 0,
                      "constraints": 1 if contact else 0, "CR iterations": 10 if contact else 0,
                      "surface vertices": n if contact else 0, "device path": 1,
                      "sparse inverse": 1})
            nnz = truth["S_TET"] * z["S basis tetrahedra"] + truth["S_TRI"] * z["S basis triangles"]
            cpu, gpu = predict(truth, z)
            for dev, ms in (("cpu", cpu), ("gpu-always", gpu)):
                doc = {"phases": {"Frame": {"median_ms": ms}},
                       "stats": dict({"cost: " + k: v for k, v in z.items()}, **{
                           "nnz(S)": nnz, "S device memory [MB]": 1})}
                with open(os.path.join(d, f"s{i}_{dev}.json"), "w") as f:
                    json.dump(doc, f)
        scenes = read_scenes(d, None)
        k = fit(scenes)
        for s in scenes:
            cpu, gpu = predict(k, s["z"])
            if abs(cpu / s["cpu"] - 1) > 0.02 or abs(gpu / s["gpu"] - 1) > 0.02:
                sys.exit(f"selftest: {s['name']}: predicted {cpu:.4g} / {gpu:.4g} ms, "
                         f"made {s['cpu']:.4g} / {s['gpu']:.4g} ms")
            if verdict(s, gpu < cpu) != "yes":
                sys.exit(f"selftest: {s['name']}: wrong choice")
        path = os.path.join(d, "device_cost.c")
        with open(path, "w") as f:
            f.write("a\n/* BEGIN FITTED (x) */\nold\n/* END FITTED */\nb\n")
        write_block(path, c_block(k))
        with open(path) as f:
            text = f.read()
        if "old" in text or "CPU_MS[NTERMS]" not in text or not text.endswith("*/\nb\n"):
            sys.exit("selftest: the FITTED block was not replaced")
    print(f"selftest: {len(scenes)} made-up scenes predicted within 2%, every choice right")
    return 0


def read_block(path):
    """The constants of a device_cost.c's FITTED block (as --write writes them)."""
    text = open(path).read()
    m = re.search(r"/\* BEGIN FITTED.*?/\* END FITTED \*/", text, flags=re.S)
    if not m:
        sys.exit(f"device_cost_fit: no FITTED block in {path}")
    block = m.group(0)

    def arr(name):
        a = re.search(name + r"\[NTERMS\] = \{([^}]*)\}", block)
        return [float(v) for v in a.group(1).split(",")]

    def num(name):
        return float(re.search(name + r" = ([0-9.eE+-]+)", block).group(1))

    return {"CPU_MS": arr("CPU_MS"), "GPU_MS": arr("GPU_MS"), "S_TET": num("S_TET"),
            "S_TRI": num("S_TRI"), "PARTIAL": num("PARTIAL"),
            "FT_ITERATIONS": int(num("FT_ITERATIONS"))}


def check(scenes, k):
    """The choices of constants k (no fit) against the measured times."""
    print("| scene | CPU ms | GPU ms | predicted CPU | predicted GPU | choice | right? |")
    print("|---|--:|--:|--:|--:|---|---|")
    wrong = 0
    for s in scenes:
        cpu, gpu = predict(k, s["z"])
        v = verdict(s, gpu < cpu)
        wrong += v == "NO"
        print(f"| {s['name']} | {s['cpu']:.3g} | {s['gpu']:.3g} | {cpu:.3g} | {gpu:.3g} | "
              f"{'GPU' if gpu < cpu else 'CPU'} | {v} |")
    print(f"\n{len(scenes)} scenes; wrong choices (more than {CLOSE:.0%} slower) of the "
          f"constants as they are: {wrong}")
    return 1 if wrong else 0


def write_block(path, block):
    with open(path) as f:
        text = f.read()
    new, n = re.subn(r"(/\* BEGIN FITTED[^\n]*\n).*?(/\* END FITTED \*/)",
                     lambda m: m.group(1) + block + m.group(2), text, flags=re.S)
    if n != 1:
        sys.exit(f"device_cost_fit: no FITTED block in {path}")
    with open(path, "w") as f:
        f.write(new)


def main():
    if sys.argv[1:] == ["--selftest"]:
        return selftest()
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folder")
    ap.add_argument("--sizes", help="folder of <scene>.json with the cost: statistics")
    ap.add_argument("--write", help="device_cost.c whose FITTED block to replace")
    ap.add_argument("--threads", type=int, default=CAL_THREADS,
                    help="threads of the CPU runs (default 16)")
    ap.add_argument("--check", help="device_cost.c whose FITTED constants to judge, unfitted")
    a = ap.parse_args()
    globals()["CAL_THREADS"] = a.threads
    scenes = read_scenes(a.folder, a.sizes)
    if a.check:
        return check(scenes, read_block(a.check))
    if len(scenes) < len(TERMS):
        sys.exit(f"device_cost_fit: {len(scenes)} scenes with timings and sizes: too few")
    partial_before = 1.0
    if a.write:  # the PARTIAL of the file's current block
        m = re.search(r"PARTIAL = ([0-9.eE+-]+);", open(a.write).read())
        partial_before = float(m.group(1)) if m else 1.0
    k = fit(scenes, partial_before)
    print("| scene | CPU ms | GPU ms | predicted CPU | predicted GPU | choice | right? | LOO |")
    print("|---|--:|--:|--:|--:|---|---|---|")
    wrong = loo_wrong = 0
    for i, s in enumerate(scenes):
        cpu, gpu = predict(k, s["z"])
        choice = gpu < cpu
        v = verdict(s, choice)
        # leave-one-out: the choice with constants fitted on the other scenes
        kl = fit(scenes[:i] + scenes[i + 1:], partial_before)
        lc, lg = predict(kl, s["z"])
        lv = verdict(s, lg < lc)
        wrong += v == "NO"
        loo_wrong += lv == "NO"
        print(f"| {s['name']} | {s['cpu']:.3g} | {s['gpu']:.3g} | {cpu:.3g} | {gpu:.3g} | "
              f"{'GPU' if choice else 'CPU'} | {v} | {lv} |")
    print(f"\n{len(scenes)} scenes; wrong choices (more than {CLOSE:.0%} slower): {wrong}; "
          f"leave-one-out: {loo_wrong}")
    block = c_block(k)
    print("\n" + block, end="")
    if a.write:
        write_block(a.write, block)
        print(f"wrote the constants into {a.write}")
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
