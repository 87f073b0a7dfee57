"""The text of a user's teacher module, as a user would write it (the tests write it to a
temporary folder outside the repository and bench it by import path)."""

SOURCE = '''
import time

import numpy as np


class Uniform:
    """Goals uniform in the box, from the teacher's own generator."""

    spaces = ("box",)
    competence_range = (0.0, 1.0)

    def __init__(self, low, high, seed=0, spread=1.0):
        self.low, self.high = np.asarray(low, float), np.asarray(high, float)
        self.rng = np.random.default_rng(seed)
        self.spread = spread
        self.calls = 0

    def sample(self):
        self.calls += 1
        mid = (self.low + self.high) / 2
        return mid + self.spread * (self.rng.uniform(self.low, self.high) - mid)

    def update(self, goal, competence):
        assert 0.0 <= competence <= 1.0


class Centre:
    """Always the box's centre (no spaces attribute: a box teacher)."""

    def __init__(self, low, high, seed=0):
        self.goal = (np.asarray(low, float) + np.asarray(high, float)) / 2

    def sample(self):
        return self.goal.copy()

    def update(self, goal, competence):
        pass


class Raises(Uniform):
    def update(self, goal, competence):
        if self.calls == 100:
            raise ValueError("my teacher broke")


class OutOfBox(Uniform):
    def sample(self):
        goal = super().sample()
        return self.high + 1.0 if self.calls == 7 else goal


class Hangs(Uniform):
    def sample(self):
        if self.calls == 3:
            time.sleep(30)
        return super().sample()


class Slow(Uniform):
    def sample(self):
        time.sleep(0.0002)
        return super().sample()


class FirstTask:
    """A task-list teacher that always asks task 0, then a task that does not exist."""

    spaces = ("tasks",)

    def __init__(self, n_tasks, seed=0):
        self.n, self.calls = n_tasks, 0

    def sample(self):
        self.calls += 1
        return 0 if self.calls < 5 else self.n

    def update(self, goal, competence):
        pass


class Around(Uniform):
    """Uniform in a box about ``start`` (positions in [0, 1] of the box), ``width`` of it wide;
    it takes expert knowledge: the easy region's centre and width."""

    def __init__(self, low, high, seed=0, start=0.5, width=1.0):
        super().__init__(low, high, seed)
        span = self.high - self.low
        centre = self.low + np.asarray(start, float) * span
        half = np.asarray(width, float) * span / 2
        self.lo, self.hi = np.maximum(self.low, centre - half), np.minimum(self.high, centre + half)

    @staticmethod
    def expert_params(knowledge):
        return {"start": knowledge.position(knowledge.easy.centre), "width": knowledge.share(knowledge.easy.width)}

    def sample(self):
        return self.rng.uniform(self.lo, self.hi)


class BadKnowledge(Uniform):
    @staticmethod
    def expert_params(knowledge):
        raise ValueError("cannot read it")
'''


def write(folder):
    """Write the module as ``myteachers.py`` in ``folder``; its path."""
    path = folder / "myteachers.py"
    path.write_text(SOURCE)
    return path
