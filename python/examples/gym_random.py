"""Random actions in pliant.gym's cable finger: steps per second for 1 and 8
environments in one process (issue 18 item 4).

    python python/examples/gym_random.py [--steps 1000] [--scene PATH] [--iterations N]

--steps: steps of the (vector) environment; with 8 environments each step
advances 8 simulations, and the table gives simulation steps per second.
"""
import argparse
import time

import numpy as np

import pliant
import pliant.gym

pliant.set_log_level("warning")


def run(n, steps, kw):
    envs = pliant.gym.make_vec(n, **kw)
    envs.reset(seed=list(range(n)))
    envs.action_space.seed(0)
    t0 = time.perf_counter()
    episodes = 0
    for _ in range(steps):
        _, _, term, trunc, _ = envs.step(envs.action_space.sample())
        episodes += int(np.sum(term | trunc))
    dt = time.perf_counter() - t0
    envs.close()
    return steps * n / dt, episodes


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--scene", default=None, help="default: the package's cable_finger.xml")
    ap.add_argument("--iterations", type=int, default=None,
                    help="local-global iterations a step (default: the scene's)")
    a = ap.parse_args()
    kw = {"scene": a.scene, "iterations": a.iterations}
    print(f"scene {a.scene or 'cable_finger.xml'}, iterations {a.iterations or 'as the scene'}, "
          f"{a.steps} random steps")
    print("| environments | simulation steps/s | episodes ended |")
    print("|---|---|---|")
    for n in (1, 8):
        rate, episodes = run(n, a.steps, kw)
        print(f"| {n} | {rate:.0f} | {episodes} |")


if __name__ == "__main__":
    main()
