"""Plug an environment written in Python into saggriac's Rust loop.

Here the body is the paper's arm with a noisy position sensor: each reading of the end effector
carries Gaussian noise. The environment is seeded once through reset(seed=...), from the run's
root seed, so the run repeats exactly.

    python examples/python_environment.py [--steps 5000] [--noise 0.05]
"""

import argparse

import numpy as np

import saggriac
from saggriac.bodies.environments import PlanarArm
from saggriac.testing import check_environment


class NoisySensorArm(PlanarArm):
    def __init__(self, noise: float, **arm) -> None:
        super().__init__(**arm)
        self.noise = noise
        self.rng = np.random.default_rng(0)

    def reset(self, *, seed=None, options=None):
        if seed is not None:
            self.rng = np.random.default_rng(seed)
        theta, x = super().reset(options=options)
        # Placements (options) read the true position, so test configurations stay exact.
        return theta, x if options else x + self.rng.normal(0.0, self.noise, 2)

    def step(self, dtheta):
        theta, x = super().step(dtheta)
        return theta, x + self.rng.normal(0.0, self.noise, 2)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=5000)
    p.add_argument("--noise", type=float, default=0.05)
    a = p.parse_args()
    check_environment(PlanarArm())  # the conformance checker users run on their own bodies
    cfg = saggriac.Config.from_preset("exp1", n_steps=a.steps, n_evals=5)
    res = saggriac.run(cfg, seed=0, environment=NoisySensorArm(a.noise))
    again = saggriac.run(cfg, seed=0, environment=NoisySensorArm(a.noise))
    assert np.array_equal(res.reach_error, again.reach_error), "same seed, same numbers"
    print(f"noisy-sensor arm (noise {a.noise}), {a.steps} steps: reaching error {res.reach_error[0]:.2f} -> {res.reach_error[-1]:.2f}")
    print(f"same seed, same result: {np.array_equal(res.reach_error, again.reach_error)}; {len(res.goals)} goals")


if __name__ == "__main__":
    main()
