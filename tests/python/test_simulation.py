"""Simulation through Python, checked against closed forms computed from the
mechanism's own data (gravity torques, potential energy), the mass matrix,
energy conservation, and the five-axis arm following its motion program."""
import math

import numpy as np
import pytest

import mbx
from conftest import ARM_DRIVES, ARM_WRL, ARM_XML

G = np.array([0.0, 0.0, -9.81])


def world_com(body):
    return body.position + body.rotation @ body.com


def subtree(joints, root_body):
    bodies, grew = {root_body}, True
    while grew:
        grew = False
        for j in joints:
            if not j.is_cut and j.parent in bodies and j.child not in bodies:
                bodies.add(j.child)
                grew = True
    return bodies


def test_model_layout(arm):
    sim = arm.simulation()
    assert (sim.nq, sim.nv, sim.drive_count, sim.loop_closure_count) == (5, 5, 0, 0)
    assert np.allclose(sim.gravity, G)
    assert [j.kind for j in sim.joints] == ["revolute"] * 5
    assert [j.q_index for j in sim.joints] == [0, 1, 2, 3, 4]
    assert sim.joint("40:-:41").index == 0
    assert sim.joint("WAIST--UPPER_ARM").index == 1
    with pytest.raises(mbx.MbxError) as e:
        sim.joint("no such joint")
    assert e.value.subject_id == "no such joint"


def test_gravity_torques_and_potential_are_the_closed_forms(arm):
    """At rest at the CAD pose, inverse dynamics with zero acceleration is the
    torque that holds each joint's subtree against gravity: the moment of the
    subtree's weights about the joint axis, from the bodies' masses and
    centres of mass as the mechanism reports them."""
    bodies, joints = arm.rigid_bodies, arm.joints
    sim = arm.simulation()
    sim.initialize()
    effort = sim.inverse_dynamics(np.zeros(sim.nv))
    expected = []
    for j in joints:
        moment = sum(np.cross(world_com(bodies[i]) - j.position, bodies[i].mass * G)
                     for i in subtree(joints, j.child))
        expected.append(-moment @ j.axis)
    assert np.allclose(effort, expected, rtol=1e-9, atol=1e-9)
    assert abs(effort[1]) > 1.0  # the shoulder carries the arm: not a vacuous zero
    potential = sum(b.mass * 9.81 * world_com(b)[2] for b in bodies[1:])
    e = sim.energy()
    assert e.gravity == pytest.approx(potential, rel=1e-12)
    assert e.kinetic == 0.0


def test_mass_matrix_inverse_and_forward_dynamics_agree(arm):
    sim = arm.simulation(gravity=(0, 0, 0))
    sim.initialize({"41:-:42": 0.3, "42:-:43": -0.5})
    assert sim.q[1] == pytest.approx(0.3) and sim.q[2] == pytest.approx(-0.5)
    m = sim.mass_matrix()
    assert np.allclose(m, m.T, rtol=1e-12, atol=1e-15)
    assert np.all(np.linalg.eigvalsh(m) > 0)
    qacc = np.array([0.5, -1.0, 2.0, 0.25, -3.0])
    assert np.allclose(sim.inverse_dynamics(qacc), m @ qacc, rtol=1e-10, atol=1e-12)
    # An effort produces the acceleration M^-1 effort (at rest, no gravity).
    effort = np.array([1.0, 2.0, -1.0, 0.1, 0.01])
    sim.set_effort(effort)
    assert np.allclose(sim.forward_dynamics(), np.linalg.solve(m, effort), rtol=1e-9)
    # Kinetic energy is v^T M v / 2.
    v = np.array([0.2, -0.1, 0.3, 0.5, 1.0])
    sim.set_effort(np.zeros(5))
    sim.set_state(v=v)
    assert sim.energy().kinetic == pytest.approx(0.5 * v @ m @ v, rel=1e-12)


def test_a_passive_swing_keeps_its_energy(arm):
    sim = arm.simulation(integrator="rk4", step=1e-3)
    sim.initialize(velocities={"41:-:42": 1.0, "44:-:45": 3.0})
    before = sim.energy().total
    sim.step(200)
    assert sim.time == pytest.approx(0.2)
    sim.integrate(0.5)
    assert sim.time == pytest.approx(0.5, abs=1e-12)
    assert sim.energy().total == pytest.approx(before, rel=1e-7)
    assert sim.stats().steps >= 500
    assert not np.allclose(sim.q, 0)


def test_state_and_joint_state_round_trip(arm):
    sim = arm.simulation()
    q, v = np.linspace(0.1, 0.5, 5), np.linspace(-1, 1, 5)
    sim.set_state(q, v, time=1.5)
    assert sim.time == 1.5
    assert np.array_equal(sim.q, q) and np.array_equal(sim.v, v)
    jq, jv = sim.joint_state("43:-:44")
    assert jq[0] == q[3] and jv[0] == v[3]
    sim.set_joint_state("43:-:44", q=0.9)
    assert sim.q[3] == 0.9 and sim.v[3] == v[3]


def test_bad_state_raises_naming_the_joint(arm):
    sim = arm.simulation()
    q = np.zeros(5)
    q[2] = math.nan
    with pytest.raises(mbx.MbxError) as e:
        sim.set_state(q)
    assert e.value.status_name == "MBX_ERROR_INVALID_INPUT"
    assert "UPPER_ARM--FOREARM" in e.value.message or e.value.subject_id == "42:-:43"
    with pytest.raises(mbx.MbxError):
        sim.set_state(np.zeros(4))
    with pytest.raises(mbx.MbxError):
        arm.simulation(integrator="leapfrog")


def test_the_arm_follows_its_motion_program(driven_arm):
    """Drives in the loop: the waist turns 0 -> 45 deg between 0.5 and 2 s and
    holds (samples/mechatronics/five_axis_arm_drives.xml). Without drives the
    waist (vertical axis) would not move at all."""
    sim = driven_arm.simulation()
    sim.initialize()
    traj = sim.record(stop_time=2.5, output_step=0.01)
    assert traj.time[0] == 0.0 and traj.time[-1] == pytest.approx(2.5)
    assert traj.q.shape == (len(traj.time), 5) and traj.drive_target.shape == (len(traj.time), 5)
    waist = traj.drive("waist")
    # Drive signals are those of the last dynamics evaluation, at most one
    # 1 ms step behind the sample time: the target within one step's change.
    for k in (0, 100, 125, 200):
        t = traj.time[k]
        now, before = driven_arm.drive_target(waist, t)[0], driven_arm.drive_target(waist, max(0.0, t - 1e-3))[0]
        assert traj.drive_target[k, waist] == pytest.approx(now, abs=abs(now - before) + 1e-12)
    q_waist = traj.joint_q("40:-:41")
    assert math.degrees(q_waist[-1]) == pytest.approx(45.0, abs=0.1)
    assert np.max(np.abs(q_waist - traj.drive_target[:, waist])) < math.radians(5)
    assert np.any(traj.drive_current[:, waist] != 0)
    signals = sim.drive_signals("waist")
    assert signals.target == pytest.approx(math.radians(45))


def test_run_writes_the_trajectory_it_integrates(driven_arm, tmp_path):
    sim = driven_arm.simulation()
    sim.initialize()
    sim.run(tmp_path, stop_time=1.0, output_step=0.05)
    assert (tmp_path / "simulation.json").exists()
    table = mbx.read_trajectory_csv(tmp_path / "trajectory.csv")
    assert table["time"][-1] == pytest.approx(1.0)
    assert len(table["time"]) == 21
    columns = [c for c in table if c != "time"]
    assert len(columns) >= 10
    # The last row is the state the simulation ended in.
    assert sim.time == pytest.approx(1.0)
    first_q = [c for c in columns if "BASE--WAIST" in c or "waist" in c.lower()]
    assert first_q
