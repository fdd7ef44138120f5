"""pliant.gym: the cable finger reaching a target with its tip, on gymnasium's
Env API (issue 18 item 4; docs/python.md).

    import gymnasium as gym, pliant.gym
    env = pliant.gym.CableFingerEnv()          # scenes/cable_finger.xml
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    envs = pliant.gym.make_vec(8)              # 8 fingers over one loaded model

Observation (float32, 11 numbers): the tip's position [m] (3) and velocity
[m/s] (3), the cable's length [m] and tension [N], the target [m] (3).
Action: the cable's displacement rate [m/s], in [-max_rate, max_rate]; the
commanded displacement integrates it and stays within the cable's limits (the
range the scene's KeyboardController gives, 0 to 20 mm for cable_finger.xml).
Reward: minus the tip's distance to the target [m].  Episode: terminated when
the tip is within 1 mm of the target, truncated after 200 steps.  Targets are
drawn on the tip's path under a slow pull, so each one can be reached.
"""
import xml.etree.ElementTree as ET

import gymnasium
import numpy as np
from gymnasium import spaces

from . import simulation

# Components that would drive the cable themselves or write files.
_DROPPED = {"Keyframes", "KeyboardController", "VTKExporter"}


def _load(scene, iterations):
    """The scene's XML without its cable drivers and exporters, and the
    cable's displacement range from its KeyboardController (min, max)."""
    root = ET.parse(scene).getroot()
    limits = (0.0, 0.02)
    for parent in list(root.iter()):
        for child in list(parent):
            if child.tag == "KeyboardController" and "max" in child.attrib:
                limits = (float(child.get("min", 0)), float(child.get("max")))
            if child.tag in _DROPPED:
                parent.remove(child)
            elif child.tag == "LocalGlobalSolver" and iterations:
                child.set("iterations", str(iterations))
                child.attrib.pop("forceTolerance", None)
    return ET.tostring(root, encoding="unicode"), limits


class CableFingerEnv(gymnasium.Env):
    """The cable-driven finger (SoftRobots' CableDisplacement) reaching a target.

    scene: a cable finger scene (default: the package's cable_finger.xml);
    iterations: local-global iterations a step instead of the scene's own
    setting (fewer: faster and less converged); max_rate: the action's bound
    [m/s]; max_steps: the episode's length; tolerance: the reach distance [m]."""

    metadata = {"render_modes": []}
    _paths = {}   # (scene, iterations) -> tip positions along a slow pull (cached)

    def __init__(self, scene=None, iterations=None, max_rate=0.05, max_steps=200,
                 tolerance=1e-3, cable="finger/cable", dofs="finger/dofs"):
        self.scene = scene or simulation.scene("cable_finger.xml")
        self.iterations = iterations
        xml, self.limits = _load(self.scene, iterations)
        self.cable, self.dofs = cable, dofs
        self.max_rate, self.max_steps, self.tolerance = max_rate, max_steps, tolerance
        self._attach(simulation.Simulation(xml=xml, name=self.scene))
        self.action_space = spaces.Box(-max_rate, max_rate, shape=(1,), dtype=np.float32)
        # generous physical bounds: positions within 1 m, speeds 100 m/s, tension 1 MN
        high = np.array([1, 1, 1, 100, 100, 100, 10, 1e6, 1, 1, 1], dtype=np.float32)
        low = -high
        low[6] = 0.0
        self.observation_space = spaces.Box(low, high, dtype=np.float32)
        self.target = self.x[self.tip].copy()
        self.value = 0.0
        self.steps = 0

    def _attach(self, sim):
        self.sim = sim
        self.dt = sim.dt
        self.x = sim.positions(self.dofs)
        self.v = sim.velocities(self.dofs)
        self.tip = int(np.argmin(self.x[:, 0]))   # the finger points along -x

    def fork(self):
        """Another env of the same scene and settings over this one's model (one
        factorisation): its own state, actuation and target (Simulation.fork)."""
        self.sim.reset()
        other = CableFingerEnv.__new__(CableFingerEnv)
        other.__dict__.update({k: v for k, v in self.__dict__.items()
                               if k not in ("sim", "x", "v", "_np_random", "_np_random_seed")})
        other._attach(self.sim.fork())
        other.target = self.target.copy()
        return other

    # the tip's positions under a slow pull from min to max: where targets lie
    def _path(self):
        key = (self.scene, self.iterations)
        if key not in self._paths:
            lo, hi = self.limits
            n = 40
            path = []
            for k in range(n + 1):
                self.sim[f"{self.cable}.value"] = lo + (hi - lo) * k / n
                self.sim.step(3)
                path.append(self.x[self.tip].copy())
            self.sim.reset()
            CableFingerEnv._paths[key] = np.array(path)
        return self._paths[key]

    def _obs(self):
        length = self.sim[f"{self.cable}.cableLength"]
        force = self.sim[f"{self.cable}.force"]
        return np.concatenate([self.x[self.tip], self.v[self.tip], [length, force],
                               self.target]).astype(np.float32)

    def _distance(self):
        return float(np.linalg.norm(self.x[self.tip] - self.target))

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        path = self._path()
        self.sim.reset()
        self.value = self.limits[0]
        self.sim[f"{self.cable}.value"] = self.value
        if options and "target" in options:
            self.target = np.asarray(options["target"], dtype=float)
        else:
            s = self.np_random.uniform(0, len(path) - 1)
            k = min(int(s), len(path) - 2)
            self.target = path[k] + (s - k) * (path[k + 1] - path[k])
        self.steps = 0
        return self._obs(), {"distance": self._distance()}

    def step(self, action):
        rate = float(np.clip(np.asarray(action, dtype=float).reshape(-1)[0],
                             -self.max_rate, self.max_rate))
        self.value = float(np.clip(self.value + rate * self.dt, *self.limits))
        self.sim[f"{self.cable}.value"] = self.value
        self.sim.step(1)
        self.steps += 1
        d = self._distance()
        terminated = d < self.tolerance
        truncated = not terminated and self.steps >= self.max_steps
        return self._obs(), -d, terminated, truncated, {"distance": d, "value": self.value}


def make_vec(n, **kw):
    """n cable fingers of one scene in this process (gymnasium's SyncVectorEnv,
    stepped one after the other): one loaded model, forked n - 1 times (each
    env its own state, actuation and target; the system is factorised once)."""
    first = CableFingerEnv(**kw)
    first._path()
    envs = [first] + [first.fork() for _ in range(n - 1)]
    return gymnasium.vector.SyncVectorEnv([(lambda e=e: e) for e in envs])
