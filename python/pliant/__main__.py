"""python3 -m pliant run script.py [-n N] [--set path=value ...]

Runs a SofaPython3-style script (createScene(rootNode)) as `runSofa
script.py` would, headless: what `pliant run script.py` hands over.  The
script's folder is on sys.path, __file__ is set, and pliant.sofa is
importable as Sofa (Sofa.Core, Sofa.Simulation, Sofa.constants).
Exit codes as the pliant CLI: 0 ok, 1 internal error, 2 bad input.
"""
import argparse
import os
import sys
import time
import traceback


def _install_sofa():
    from .sofa import install_as_sofa
    install_as_sofa()


def run(argv):
    ap = argparse.ArgumentParser(prog="pliant run", description="Runs a createScene script "
                                 "(SofaPython3 style) headless.")
    ap.add_argument("script")
    ap.add_argument("-n", "--steps", type=int, default=100, help="time steps (default 100)")
    ap.add_argument("-s", "--set", action="append", default=[], metavar="PATH=VALUE",
                    help="change a field after the scene is built (repeatable)")
    ap.add_argument("-q", "--quiet", action="store_true", help="warnings and errors only")
    a = ap.parse_args(argv)
    import pliant
    from .sofa import Simulation, load_script
    if a.quiet:
        pliant.set_log_level("warning")
    script = os.path.abspath(a.script)
    if not os.path.isfile(script):
        print(f"pliant run: {a.script}: no such file", file=sys.stderr)
        return 2
    sys.argv = [script]
    try:
        root = load_script(script)
    except Exception:
        traceback.print_exc()
        print(f"pliant run: {a.script}: the script failed; the scene was not run",
              file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    try:
        Simulation.init(root)
        sim = root.simulation
        for s in a.set:
            path, sep, value = s.partition("=")
            if not sep:
                print(f"pliant run: --set {s}: expected PATH=VALUE", file=sys.stderr)
                return 2
            sim.set(path, value)
    except pliant.InputError as e:
        print(e, file=sys.stderr)
        print(f"pliant run: {a.script}: the scene was not run", file=sys.stderr)
        return 2
    load = time.perf_counter() - t0
    t0 = time.perf_counter()
    try:
        sim.step(a.steps)
    except pliant.Error as e:
        print(e, file=sys.stderr)
        return e.code if e.code in (1, 2) else 1
    except Exception:
        traceback.print_exc()
        print(f"pliant run: {a.script}: a controller failed at t = {sim.time:.4g} s",
              file=sys.stderr)
        return 2
    dt = time.perf_counter() - t0
    print(f"{a.script}: {a.steps} steps, t = {sim.time:.4g} s, load {load:.3f} s, "
          f"{1e3 * dt / max(a.steps, 1):.3f} ms/step")
    return 0


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if argv else 2
    if argv[0] != "run":
        print(f"python3 -m pliant: unknown command '{argv[0]}' (expected: run)", file=sys.stderr)
        return 2
    return run(argv[1:])


if __name__ == "__main__":
    sys.exit(main())
