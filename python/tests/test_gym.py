"""pliant.gym: the cable finger environment (issue 18 item 4)."""
import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402

import pliant  # noqa: E402
import pliant.gym  # noqa: E402

SMALL = dict(scene=pliant.scene("cable_finger_small.xml"), iterations=10)


def test_env_checker_passes():
    check_env(pliant.gym.CableFingerEnv(**SMALL), skip_render_check=True)


def test_pulling_reaches_a_target_on_the_path():
    env = pliant.gym.CableFingerEnv(**SMALL, max_steps=100)
    obs, info = env.reset(seed=1)
    rest_tip = obs[:3].copy()
    assert info["distance"] > env.tolerance        # the target is away from the rest pose
    np.testing.assert_allclose(obs[8:], env.target, rtol=1e-6)
    # bang-bang: pull while the tip is below the target, else release (it
    # overshoots once, then passes within 1 mm at step 41)
    rewards, tensions = [], []
    for _ in range(100):
        up = env.x[env.tip, 1] < env.target[1]
        obs, r, terminated, truncated, info = env.step([env.max_rate if up else -env.max_rate])
        rewards.append(r)
        tensions.append(obs[7])
        if terminated or truncated:
            break
    assert terminated, f"closest approach {-max(rewards):.4f} m"
    assert -rewards[-1] < 1e-3 and obs[1] > rest_tip[1]
    assert min(tensions) >= 0 and max(tensions) > 0.1   # the cable pulls, never pushes


def test_action_bounds_and_truncation():
    env = pliant.gym.CableFingerEnv(**SMALL, max_steps=5)
    env.reset(seed=0, options={"target": [1.0, 1.0, 1.0]})   # out of reach
    for k in range(5):
        obs, r, terminated, truncated, info = env.step([-1.0])  # clipped, and >= min
        assert info["value"] == env.limits[0]
    assert truncated and not terminated
    assert r == pytest.approx(-np.linalg.norm(obs[:3] - 1.0), rel=1e-5)


def test_vector_env_steps_independent_fingers():
    envs = pliant.gym.make_vec(2, **SMALL)
    obs, _ = envs.reset(seed=[3, 3])
    for _ in range(20):
        obs, r, term, trunc, _ = envs.step(np.array([[0.05], [0.0]], dtype=np.float32))
    assert obs[0, 1] > obs[1, 1] + 1e-3              # the pulled finger's tip is higher
    envs.close()


def test_a_forked_env_follows_the_same_trajectory():
    env = pliant.gym.CableFingerEnv(**SMALL)
    twin = env.fork()
    a, _ = env.reset(seed=5)
    b, _ = twin.reset(seed=5)
    np.testing.assert_array_equal(a, b)
    for k in range(8):
        action = [0.05 if k < 5 else -0.02]
        a = env.step(action)[0]
        b = twin.step(action)[0]
    np.testing.assert_array_equal(a, b)
