"""A serial arm of a MuJoCo model as a saggriac body (the optional extra
``pip install "saggriac[mujoco]"``).

The joints, their limits and the end effector come from the model, and MuJoCo computes the
kinematics (``mj_kinematics``: positions only, no dynamics, as saggriac's own arms). The core
wants the same symmetric limit on every joint, so each joint's angle q in its range [lo, hi] is
seen by saggriac as theta = (q - mid) / half in [-1, 1], with mid = (lo + hi) / 2 and
half = (hi - lo) / 2. Rest (theta = 0) is the middle of every range. ``max_joint_step`` is in
these units: 0.02 moves a joint by at most 2 % of its half-range per micro-action.

:func:`pusher_arm` gives the 7-joint arm of Gymnasium's MuJoCo Pusher model (``pusher_v5.xml``,
shipped by the ``gymnasium`` package); its end effector is the ``tips_arm`` body.
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np

from .environments import Box, joint_step, joint_vector, within_limits
from ..errors import ParameterError
from ..files import check_flag

try:
    import mujoco
except ImportError:  # pragma: no cover - depends on the installation
    raise ImportError('saggriac.bodies.mujoco_arm needs MuJoCo: pip install "saggriac[mujoco]"') from None

PUSHER_JOINTS = ("r_shoulder_pan_joint", "r_shoulder_lift_joint", "r_upper_arm_roll_joint", "r_elbow_flex_joint", "r_forearm_roll_joint", "r_wrist_flex_joint", "r_wrist_roll_joint")


def pusher_model_path() -> str:
    """The path of Gymnasium's ``pusher_v5.xml``."""
    try:
        import gymnasium
    except ImportError:
        raise ImportError('The Pusher model comes with Gymnasium: pip install "saggriac[mujoco]"') from None
    path = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", "pusher_v5.xml")
    if not os.path.exists(path):
        raise FileNotFoundError(f"This Gymnasium has no {path}; saggriac's MuJoCo extra needs Gymnasium >= 1.0.")
    return path


class MujocoArm:
    """The hinge joints ``joints`` of the MuJoCo model ``model`` (an ``MjModel`` or the path of
    an XML file) as a saggriac body whose end effector is the body or site ``end_effector``.
    The model's other joints stay at their ``qpos0``.

    Each joint moves within its range in the model. ``ranges`` gives a range (low, high) in
    radians to joints that have none (unlimited hinges: a Reacher's shoulder, most models' root
    hinges), or overrides a model's. An end effector that some chosen joint does not move (a
    joint of another limb, an end effector before the joint) is refused, naming the joints."""

    def __init__(self, model: Any, joints: tuple[str, ...] | list[str], end_effector: str, max_joint_step: float = 0.02, ranges: dict[str, tuple[float, float]] | None = None) -> None:
        if isinstance(model, (str, os.PathLike)):
            model = mujoco.MjModel.from_xml_path(os.fspath(model))
        if not isinstance(model, mujoco.MjModel):
            raise ParameterError(f"The 'model' parameter of MujocoArm must be a mujoco.MjModel or the path of an XML model. Got {model!r} instead.", "model", repr(model))
        if isinstance(max_joint_step, bool) or not isinstance(max_joint_step, (int, float)) or not math.isfinite(max_joint_step) or not 0 < max_joint_step <= 1:
            raise ParameterError(f"The 'max_joint_step' parameter of MujocoArm must be a number in (0, 1] (a share of each joint's half-range). Got {max_joint_step!r} instead.", "max_joint_step", repr(max_joint_step))
        if isinstance(joints, (str, bytes)) or not joints:
            raise ParameterError(f"The 'joints' parameter of MujocoArm must be a list naming at least one joint. Got {joints!r} instead.", "joints", repr(joints))
        repeated = sorted({str(j) for j in joints if list(joints).count(j) > 1})
        if repeated:
            raise ParameterError(f"The 'joints' parameter of MujocoArm names {', '.join(map(repr, repeated))} more than once; each joint is one coordinate of theta.", "joints", repr(list(joints)))
        self.model, self.data = model, mujoco.MjData(model)
        ranges = self._check_ranges(ranges, joints)
        adr, lo, hi = [], [], []
        for name in joints:
            jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
            if jid < 0:
                known = [model.joint(i).name for i in range(model.njnt)]
                raise ParameterError(f"The 'joints' parameter of MujocoArm names {name!r}, which the model does not have. Its joints: {known}.", "joints", repr(name))
            if model.jnt_type[jid] != mujoco.mjtJoint.mjJNT_HINGE:
                raise ParameterError(f"The 'joints' parameter of MujocoArm must name hinge joints; {name!r} is not one (slide, ball and free joints are not arm joints here).", "joints", repr(name))
            if name in ranges:
                low, high = ranges[name]
            elif model.jnt_limited[jid]:
                low, high = float(model.jnt_range[jid][0]), float(model.jnt_range[jid][1])
            else:
                raise ParameterError(f"The joint {name!r} of MujocoArm has no range in the model (an unlimited hinge); give it one: ranges={{{name!r}: (-3.14, 3.14)}}, in radians.", "ranges", repr(name))
            adr.append(int(model.jnt_qposadr[jid]))
            lo.append(low)
            hi.append(high)
        self._adr = np.array(adr)
        self.low, self.high = np.array(lo), np.array(hi)
        self.mid, self.half = (self.low + self.high) / 2, (self.high - self.low) / 2
        self._site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, end_effector)
        self._body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, end_effector) if self._site < 0 else -1
        if self._site < 0 and self._body < 0:
            raise ParameterError(f"The 'end_effector' parameter of MujocoArm must name a body or site of the model. Got {end_effector!r}.", "end_effector", repr(end_effector))
        self.joint_names, self.end_effector = tuple(joints), end_effector
        self.max_joint_step = float(max_joint_step)
        n = len(adr)
        self.joint_space = Box(-1.0, 1.0, (n,))
        self.action_space = Box(-self.max_joint_step, self.max_joint_step, (n,))
        self.task_space = Box(-1e3, 1e3, (3,))
        self.theta = np.zeros(n)
        self._check_end_effector_moves()

    def __repr__(self) -> str:
        where = "site" if self._site >= 0 else "body"
        return f"MujocoArm(joints={list(self.joint_names)!r}, end_effector={self.end_effector!r} ({where}), max_joint_step={self.max_joint_step:g}, model with {self.model.njnt} joints)"

    @staticmethod
    def _check_ranges(ranges: Any, joints: Any) -> dict[str, tuple[float, float]]:
        if ranges is None:
            return {}
        if not isinstance(ranges, dict):
            raise ParameterError(f"The 'ranges' parameter of MujocoArm must be a dict {{joint name: (low, high)}}. Got {ranges!r} instead.", "ranges", repr(ranges))
        out = {}
        for name, r in ranges.items():
            if name not in joints:
                raise ParameterError(f"The 'ranges' parameter of MujocoArm names {name!r}, which is not one of the chosen joints {list(joints)}.", "ranges", repr(name))
            try:
                low, high = (float(v) for v in r)
            except (TypeError, ValueError):
                raise ParameterError(f"The 'ranges' parameter of MujocoArm must give (low, high) for {name!r}. Got {r!r} instead.", "ranges", repr(r)) from None
            if not (math.isfinite(low) and math.isfinite(high) and low < high and high - low <= 4 * math.pi):
                raise ParameterError(f"The 'ranges' parameter of MujocoArm must give finite low < high, at most 4 pi apart, for {name!r}. Got {r!r} instead.", "ranges", repr(r))
            out[name] = (low, high)
        return out

    def _check_end_effector_moves(self) -> None:
        """Each chosen joint must be on the path from the model's root to the end effector: a
        joint of another limb, or beyond the end effector, never moves it and would be a
        dimension the learner can never learn. (A roll joint whose axis passes through the end
        effector is on the path and kept: it orients what comes after it.)"""
        m = self.model
        b = int(m.site_bodyid[self._site]) if self._site >= 0 else self._body
        path = set()
        while b > 0:
            path.add(b)
            b = int(m.body_parentid[b])
        off = [name for name in self.joint_names if int(m.jnt_bodyid[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)]) not in path]
        if off:
            raise ParameterError(f"The end effector {self.end_effector!r} of MujocoArm does not move when the joints {off} move: they are not on the path from the model's root to it. Choose the joints of its limb, or another end effector.", "end_effector", repr(self.end_effector))

    def joint_angles(self, theta: Any) -> np.ndarray:
        """The model's joint angles (radians) of saggriac's coordinates ``theta``."""
        return self.mid + np.asarray(theta, dtype=np.float64) * self.half

    def forward(self, theta: Any) -> np.ndarray:
        """The end effector's position at ``theta``, by ``mj_kinematics``."""
        self.data.qpos[self._adr] = self.joint_angles(theta)
        mujoco.mj_kinematics(self.model, self.data)
        return (self.data.site_xpos[self._site] if self._site >= 0 else self.data.xpos[self._body]).copy()

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, np.ndarray]:
        # Kinematics only: nothing is random, so the seed is not needed.
        self.data.qpos[:] = self.model.qpos0
        if options and "theta" in options:
            name = f"{type(self).__name__}.reset(options={{'theta': ...}})"
            self.theta = np.array(within_limits(name, joint_vector(name, options["theta"], len(self.theta)), 1.0))
        else:
            self.theta = np.zeros(len(self._adr))
        return self.theta.copy(), self.forward(self.theta)

    def step(self, dtheta: Any) -> tuple[np.ndarray, np.ndarray]:
        self.theta = joint_step(self.theta, dtheta, self.max_joint_step, 1.0)
        return self.theta.copy(), self.forward(self.theta)

    def chain(self, scale: float = 1.0, at_origin: bool = False) -> tuple[float, ...]:
        """This arm's kinematics as saggriac's native chain body (``Config(body="chain",
        chain=...)``): the fixed transforms of the model's bodies from the world to the end
        effector, each chosen hinge's anchor, axis and range. Lengths are multiplied by ``scale``
        (100 gives centimetres for a model in metres). ``at_origin`` moves the arm so that the
        first joint's body sits at the origin (its orientation kept). The run then moves the arm
        with no call into Python or MuJoCo per micro-action; ``tests/bodies/test_mujoco_arm.py`` checks
        it against ``mj_kinematics``."""
        if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not (math.isfinite(scale) and scale > 0):
            raise ParameterError(f"The 'scale' parameter of MujocoArm.chain must be a float > 0. Got {scale!r} instead.", "scale", repr(scale))
        at_origin = check_flag(at_origin, "at_origin", "MujocoArm.chain")
        m = self.model
        ee_body = self._body if self._site < 0 else int(m.site_bodyid[self._site])
        path = []
        b = ee_body
        while b > 0:
            path.append(b)
            b = int(m.body_parentid[b])
        path.reverse()
        chosen = {int(mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, n)): k for k, n in enumerate(self.joint_names)}
        flat: list[float] = []
        pos, quat = np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0])
        order = []
        for b in path:
            pos, quat = pos + _rotate(quat, m.body_pos[b]), _quat_mul(quat, m.body_quat[b])
            for j in range(int(m.body_jntadr[b]), int(m.body_jntadr[b]) + int(m.body_jntnum[b])):
                name = m.joint(j).name
                if j not in chosen:
                    # At qpos0 a hinge or a slide joint does not move its body; other joints can.
                    if int(m.jnt_type[j]) not in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
                        raise ParameterError(f"MujocoArm.chain handles hinge and slide joints between the world and the end effector; {name!r} is a ball or free joint.", "joints", repr(name))
                    continue
                k = chosen[j]
                if at_origin and not order:
                    pos = np.zeros(3)
                offset = float(m.qpos0[m.jnt_qposadr[j]])
                flat += [*(pos * scale), *quat, *(m.jnt_pos[j] * scale), *m.jnt_axis[j], float(self.low[k]) - offset, float(self.high[k]) - offset]
                pos, quat = np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0])
                order.append(k)
        missing = [self.joint_names[k] for k in range(len(self.joint_names)) if k not in order]
        if missing:
            raise ParameterError(f"MujocoArm.chain needs joints between the world and the end effector {self.end_effector!r}; {missing} do not move it.", "joints", repr(missing))
        if order != sorted(order):
            raise ParameterError(f"MujocoArm.chain needs the joints listed from the base to the end effector; the model orders them {[self.joint_names[k] for k in order]}.", "joints", repr(self.joint_names))
        tip = pos + (_rotate(quat, m.site_pos[self._site]) if self._site >= 0 else 0.0)
        return tuple(float(v) for v in (*flat, *(tip * scale)))


def _quat_mul(a: Any, b: Any) -> np.ndarray:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2, w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def _rotate(q: Any, v: Any) -> np.ndarray:
    """v rotated by the unit quaternion q (w, x, y, z)."""
    w, u = q[0], np.asarray(q[1:])
    v = np.asarray(v, dtype=np.float64)
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def pusher_arm(max_joint_step: float = 0.02) -> MujocoArm:
    """The 7-joint arm of Gymnasium's MuJoCo Pusher, end effector ``tips_arm``."""
    return MujocoArm(pusher_model_path(), PUSHER_JOINTS, "tips_arm", max_joint_step=max_joint_step)


def pusher_chain() -> tuple[float, ...]:
    """The Pusher's arm as the ``pusher`` preset's native chain (``saggriac.bodies.PUSHER_CHAIN``):
    shoulder at the origin, scaled to reach 50."""
    from ..config.presets import PUSHER_SCALE

    return pusher_arm().chain(scale=PUSHER_SCALE, at_origin=True)


__all__ = ["MujocoArm", "pusher_arm", "pusher_chain", "pusher_model_path", "PUSHER_JOINTS"]
