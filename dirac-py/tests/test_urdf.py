"""Articulated rigid bodies from URDF files: a model read and compiled from Python steps as the
same system written by hand, a floating base runs on SE(3), and a malformed file is a typed
error naming what is wrong."""

import pathlib

import numpy as np
import pytest

import dirac

from sources import function

DATA = pathlib.Path(__file__).resolve().parents[2] / "examples" / "data"

# The double pendulum of examples/data/double_pendulum.urdf written by hand, as the Rust tests of
# the model's system text compare it (rods of mass m_i, centre of mass a_i below the hinge,
# inertia j_i about it, the second hinge l1 below the first, angles about y).
BY_HAND = function("dirac-jit/tests/urdf.rs", "pendulum")


def test_a_double_pendulum_from_its_urdf_file_steps_as_written_by_hand():
    model = dirac.from_urdf(str(DATA / "double_pendulum.urdf"))
    assert isinstance(model, dirac.System)
    assert model.shape == ["shoulder", "elbow"] and model.group == []
    by_hand = dirac.compile(BY_HAND)
    q0, p0 = [0.6, -0.3], [0.2, 0.3]
    a = model.run({"h": 0.01}, steps=1000, method="unreduced", q=q0, p=p0)
    b = by_hand.run({"h": 0.01}, steps=1000, method="unreduced", q=q0, p=p0)
    for name in ["shoulder", "elbow"]:
        scale = max(1.0, np.max(np.abs(b["q"][name])))
        assert np.max(np.abs(a["q"][name] - b["q"][name])) < 1e-12 * scale
        assert np.max(np.abs(a["p"][name] - b["p"][name])) < 1e-12 * max(
            1.0, np.max(np.abs(b["p"][name])))
    # The motion is not trivial: the elbow swings through a wide range.
    assert np.ptp(a["q"]["elbow"]) > 0.5


def test_joint_torques_are_controls_named_after_the_joints():
    model = dirac.from_urdf(str(DATA / "three_link_arm.urdf"), torques=True)
    assert model.controls == ["tau_joint1", "tau_joint2", "tau_joint3"]


def test_a_floating_base_is_a_system_on_rotation_groups():
    body = dirac.from_urdf(str(DATA / "free_body.urdf"))
    assert isinstance(body, dirac.LieSystem)


def test_a_malformed_file_is_a_value_error_naming_the_element(tmp_path):
    bad = tmp_path / "bad.urdf"
    bad.write_text("""<robot name="r"><link name="world"/>
      <link name="arm"><inertial><mass value="-1"/>
        <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
      <joint name="j" type="revolute"><parent link="world"/><child link="arm"/>
        <axis xyz="0 0 1"/></joint></robot>""")
    with pytest.raises(ValueError, match="arm"):
        dirac.from_urdf(str(bad))
    with pytest.raises(OSError):
        dirac.from_urdf(str(tmp_path / "missing.urdf"))


def test_a_free_body_keeps_its_horizontal_momentum_and_its_attitude():
    body = dirac.from_urdf(str(DATA / "free_body.urdf"))
    assert body.parameters == ["h"]
    ((name, kind),) = body.coordinates
    assert kind == "pose"
    pose = np.concatenate([np.eye(3).ravel(), [0.0, 0.0, 1.0]])
    run = body.run({"h": 0.01}, steps=200, q={name: pose},
                   p={name: [0.3, -0.2, 0.5, 1.0, 0.5, 0.0]})
    q, p = run["q"][name], run["p"][name]
    assert q.shape == (201, 12) and p.shape == (201, 6)
    rotations = q[:, :9].reshape(-1, 3, 3)
    defect = np.max(np.abs(np.einsum("kji,kjl->kil", rotations, rotations) - np.eye(3)))
    assert defect < 1e-12
    assert np.max(np.abs(p[:, 3:5] - p[0, 3:5])) < 1e-12
    assert np.ptp(q[:, 9]) > 0.5  # it moves


def test_out_of_gravity_a_floating_base_is_reduced_by_its_rigid_motions():
    body = dirac.from_urdf(str(DATA / "free_body.urdf"), gravity=[0.0, 0.0, 0.0])
    ((name, _),) = body.coordinates
    assert body.symmetry == ("rigid motions", [name])
    # Far from the origin and drifting: the momentum about the origin is mostly x × p.
    pose = np.concatenate([np.eye(3).ravel(), [40.0, -25.0, 10.0]])
    start = dict(q={name: pose}, p={name: [0.3, -0.2, 0.5, 3.0, 1.0, -2.0]})
    reduced = body.run({"h": 0.01}, steps=2000, method="reduced", **start)
    unreduced = body.run({"h": 0.01}, steps=2000, method="unreduced", **start)
    q, p = reduced["q"][name], reduced["p"][name]
    # The linear momentum is the run's parameter, copied bit for bit; the angular momentum
    # about the origin R Π + x × p is held at every step.
    assert np.all(p[:, 3:] == p[0, 3:])
    rotations = q[:, :9].reshape(-1, 3, 3)
    angular = np.einsum("kij,kj->ki", rotations, p[:, :3]) + np.cross(q[:, 9:], p[:, 3:])
    drift = np.max(np.abs(angular - angular[0])) / np.linalg.norm(angular[0])
    assert drift < 1e-14
    assert np.max(np.abs(q - unreduced["q"][name])[:200]) < 1e-11 * 50
    with pytest.raises(ValueError, match="three"):
        dirac.from_urdf(str(DATA / "free_body.urdf"), gravity=[0.0, 0.0])


def double_pendulum_in_python():
    """The double pendulum of examples/data/double_pendulum.urdf, link by link."""
    arm = dirac.Model("world")
    arm.body("rod1", mass=1.3, com=[0, 0, -0.45],
             inertia=[[0.11, 0, 0], [0, 0.11, 0], [0, 0, 0.002]])
    arm.body("rod2", mass=0.7, com=[0, 0, -0.6],
             inertia=[[0.08, 0, 0], [0, 0.08, 0], [0, 0, 0.001]])
    arm.frame("tip")
    arm.joint("shoulder", "continuous", parent="world", child="rod1", axis=[0, 1, 0])
    arm.joint("elbow", "continuous", parent="rod1", child="rod2", axis=[0, 1, 0],
              xyz=[0, 0, -1.0])
    arm.joint("tip_joint", "fixed", parent="rod2", child="tip", xyz=[0, 0, -1.2])
    return arm


def test_a_model_built_in_python_runs_as_its_urdf_file():
    built = double_pendulum_in_python().compile()
    read = dirac.from_urdf(str(DATA / "double_pendulum.urdf"))
    assert isinstance(built, dirac.System)
    start = dict(q=[0.6, -0.3], p=[0.2, 0.3])
    a = built.run({"h": 0.01}, steps=1000, method="unreduced", **start)
    b = read.run({"h": 0.01}, steps=1000, method="unreduced", **start)
    for name in ("shoulder", "elbow"):
        assert np.array_equal(a["q"][name], b["q"][name])
        assert np.array_equal(a["p"][name], b["p"][name])
    assert double_pendulum_in_python().compile(torques=True).controls == [
        "tau_shoulder", "tau_elbow"]


def test_a_model_built_in_python_is_checked_naming_the_element():
    arm = dirac.Model("world")
    arm.body("rod", mass=-1.0, inertia=[[1, 0, 0], [0, 1, 0], [0, 0, 1]])
    arm.joint("hinge", "revolute", parent="world", child="rod", axis=[0, 1, 0])
    with pytest.raises(ValueError, match="rod"):
        arm.compile()
    with pytest.raises(ValueError, match="unknown kind"):
        dirac.Model("world").joint("j", "planar", parent="world", child="rod")
    with pytest.raises(ValueError, match="three"):
        dirac.Model("world").body("rod", mass=1.0, com=[0, 0], inertia=[[1, 0, 0]] * 3)
    # A ball joint: a system on rotation groups.
    ball = dirac.Model("world")
    ball.body("bob", mass=1.0, com=[0, 0, -1], inertia=[[0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.01]])
    ball.joint("ball", "spherical", parent="world", child="bob")
    assert isinstance(ball.compile(), dirac.LieSystem)
