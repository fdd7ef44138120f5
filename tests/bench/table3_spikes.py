#!/usr/bin/env python3
"""tests/bench/table3_spikes.py RES - issue 16 item 5's criterion on the runs of
tests/bench/table3.sh: every frame (0.01 s: one step, four for the raptors) should
stay within 1.5x the median of the frames whose contact count is within 10% of its
own.  Reads the timings files RES/<gpu|cpu>_<scene>.json (their per-frame table,
"frames"), leaves out the first frame (allocations, the first CUDA graph) and prints,
per run, the worst frame against its peers' median and the two phases that grew most
in it (against their medians over the same peers) and, where the run recorded them
(pl_timer_watch: every run since 2026-11-27), how much more of that frame than of
its peers' the main thread spent off its CPU, and the page faults and preemptions it
had.  Python 3, standard library only.
"""
import json
import os
import statistics
import sys


HOST = ("Frame off-CPU ms", "Frame page faults", "Frame preemptions")


def per_frame(path, steps_per_frame):
    run = json.load(open(path))
    fr = run["frames"]
    step_times = fr["Frame"]
    contacts = fr.get("contacts max", [0] * len(step_times))
    # the phases (ms), and the host's columns of the Frame (pl_timer_watch) when recorded
    phases = {k: v for k, v in fr.items()
              if isinstance(v, list) and len(v) == len(step_times)
              and ((k in run["phases"] and k != "Frame") or k in HOST)}
    m = len(step_times) // steps_per_frame

    def frames(v):
        return [sum(v[i * steps_per_frame:(i + 1) * steps_per_frame]) for i in range(m)]

    count = [max(contacts[i * steps_per_frame:(i + 1) * steps_per_frame]) for i in range(m)]
    return frames(step_times)[1:], count[1:], {k: frames(v)[1:] for k, v in phases.items()}


def peers(count, c):
    return [j for j, cj in enumerate(count) if abs(cj - c) <= 0.1 * c or (c == 0 and cj == 0)]


def worst(path):
    spf = 4 if "raptor" in os.path.basename(path) else 1
    times, count, phases = per_frame(path, spf)
    best = (0.0, 0, 0.0)
    for i, (t, c) in enumerate(zip(times, count)):
        med = statistics.median(times[j] for j in peers(count, c))
        if med > 0 and t / med > best[0]:
            best = (t / med, i, med)
    ratio, i, med = best
    p = peers(count, count[i])
    def excess(v):
        return v[i] - statistics.median(v[j] for j in p)
    grew = sorted(((excess(v), k) for k, v in phases.items() if k not in HOST), reverse=True)[:2]
    host = {k: excess(phases[k]) for k in HOST if k in phases}
    return (len(times), ratio, i + 2, times[i], med, count[i], grew, first_contact(times, count),
            host)


def first_contact(times, count):
    """The frame of the first contact against the median of the 10 frames after it: it
    has no peers (the criterion above cannot see it), and a one-time setup paid there
    (a library loaded on first use) is a hitch in the middle of the motion."""
    i = next((k for k, c in enumerate(count) if c > 0), None)
    after = times[i + 1:i + 11] if i is not None else []
    if not after:
        return None
    return times[i] / statistics.median(after), i + 2


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    res = sys.argv[1]
    print("| run | frames | worst / peers' median | frame | ms | peers' median ms | contacts "
          "| grew most [ms] | off-CPU, faults, preemptions over the peers' | "
          "first contact / next 10 (frame) |")
    print("|---|--:|--:|--:|--:|--:|--:|---|---|--:|")
    over = hitches = hosts = 0
    for f in sorted(os.listdir(res)):
        if not f.endswith(".json") or not f.startswith(("gpu_", "cpu_")):
            continue
        n, ratio, frame, ms, med, c, grew, fc, host = worst(os.path.join(res, f))
        over += ratio > 1.5
        # the host's spike: the thread off its CPU for at least half of what the frame grew
        hosts += ratio > 1.5 and host.get(HOST[0], 0.0) >= 0.5 * (ms - med)
        print("| %s | %d | %.2f | %d | %.2f | %.2f | %d | %s | %s | %s |" % (
            f[:-5], n, ratio, frame, ms, med, c, ", ".join("%s +%.1f" % (k, g) for g, k in grew),
            "%+.1f ms, %+.0f, %+.0f" % tuple(host[k] for k in HOST) if len(host) == 3 else "",
            "%.2f (%d)" % fc if fc else ""))
        hitches += fc is not None and fc[0] > 1.5
    print("\n%d run(s) with a frame over 1.5x its peers' median, %d of them with the thread "
          "off its CPU for at least half the excess" % (over, hosts))
    print("%d run(s) whose first contact takes over 1.5x the 10 frames after it" % hitches)


if __name__ == "__main__":
    main()
