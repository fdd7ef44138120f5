"""SoftRobots' own scripts ($PLIANT_REFERENCE_DIR/reference/softrobots, not part of the
project; .ci/run sets PLIANT_REFERENCE_DIR) run unmodified by `python3 -m pliant run`, when that folder exists;
skipped (and reported as skipped) otherwise.

Those in RUNS run (exit 0).  Those in KNOWN are refused today by libpliant's
SOFA loader, with the script's line (the same refusal as the scene written as
.scn): those are xfails only after checking that the refusal is the loader's
(no Python error in pliant.sofa, the script's line named); the day the loader
accepts one, the test fails until KNOWN is updated."""
import os
import subprocess
import sys

import pytest

_ROOT = os.environ.get("PLIANT_REFERENCE_DIR", "")
REF = os.environ.get("PLIANT_SOFTROBOTS_REFERENCE") or (
    os.path.join(_ROOT, "reference", "softrobots") if _ROOT else "")

# script -> what the loader refuses today (issue 17's work)
KNOWN = {}
# scripts that run today (5 steps)
RUNS = ["CableConstraint/Finger.py", "SurfacePressureConstraint/SurfacePressureConstraint.py",
        "CableConstraint/CableSmoothActuation.py"]


@pytest.mark.skipif(not os.path.isdir(REF), reason=f"no SoftRobots reference folder at {REF}")
@pytest.mark.parametrize("script", sorted(KNOWN) + RUNS)
def test_reference_script_runs_unmodified(script):
    path = os.path.join(REF, script)
    r = subprocess.run([sys.executable, "-m", "pliant", "run", path, "-n", "5", "-q"],
                       capture_output=True, text=True, timeout=600)
    # never a crash nor a Python error inside pliant.sofa: either it runs, or
    # the loader refuses it naming the script's file and line
    assert r.returncode in (0, 2), r.stderr
    if r.returncode == 2:
        assert "Traceback" not in r.stderr, r.stderr
        assert f"{os.path.basename(script)}:" in r.stderr
    if script in KNOWN:
        assert r.returncode == 2, f"{script} runs now: remove it from KNOWN"
        pytest.xfail(f"refused by the loader, as expected today: {KNOWN[script]}")
    assert r.returncode == 0, r.stderr
