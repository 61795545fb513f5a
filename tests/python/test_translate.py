"""Translation and the report through Python: the same samples and the same
numbers as the C tests (tests/integration, tests/install/consumer) and the
samples' READMEs ("Expected mechanism")."""
import json

import numpy as np
import pytest

import mbx
from conftest import ARM_WRL, ARM_XML, SAMPLES, SHARED_DATA


def test_version_matches_the_header():
    header = (SAMPLES.parent / "sdk" / "include" / "mbx" / "mbx.h").read_text()
    assert f'#define MBX_VERSION_STRING "{mbx.version()}"' in header
    assert mbx.abi_version() >= 9


def test_five_axis_arm_summary(arm):
    s = arm.summary
    assert (s.part_count, s.cad_part_count, s.weld_count) == (8, 7, 2)
    assert (s.rigid_body_count, s.joint_node_count, s.joint_count, s.revolute_count) == (5, 0, 5, 5)
    assert (s.loop_count, s.dof, s.gruebler_dof, s.redundant_constraint_count) == (0, 5, 5, 0)
    assert (s.warning_count, s.error_count) == (0, 0)
    assert arm.findings == []


def test_five_axis_arm_bodies_and_joints(arm):
    bodies = arm.rigid_bodies
    assert bodies[0].kind == "ground"
    assert [b.name for b in bodies[1:]] == ["WAIST", "UPPER_ARM", "FOREARM", "WRIST_PITCH", "WRIST_ROLL"]
    for b in bodies[1:]:
        assert b.mass > 0
        assert np.allclose(b.inertia, b.inertia.T)
        assert np.allclose(b.rotation @ b.rotation.T, np.eye(3), atol=1e-9)
    # The upper arm is the three-part sub-assembly, one rigid body.
    assert bodies[2].part_count == 1 or bodies[2].part_count == 3
    joints = arm.joints
    assert [j.constraint_id for j in joints] == ["40:-:41", "41:-:42", "42:-:43", "43:-:44", "44:-:45"]
    assert all(j.type == "revolute" and not j.is_cut for j in joints)
    # README geometry (mm): waist axis z at (0, 0, 150), shoulder about y at (0, 0, 300).
    assert np.allclose(np.abs(joints[0].axis), [0, 0, 1], atol=1e-9)
    assert np.allclose(joints[0].position[:2], [0, 0], atol=1e-9)
    assert np.allclose(np.abs(joints[1].axis), [0, 1, 0], atol=1e-9)
    assert np.allclose(joints[1].position, [0, 0, 0.3], atol=1e-9)
    # Elbow E = S + 250 mm along (sin 30, 0, cos 30).
    e = np.array([0, 0, 0.3]) + 0.25 * np.array([np.sin(np.pi / 6), 0, np.cos(np.pi / 6)])
    assert np.allclose(joints[2].position, e, atol=1e-6)
    assert arm.find_part(bodies[3].id) == 3


def test_fourbar_and_joints_showcase():
    with mbx.translate(SAMPLES / "fourbar_imperial" / "fourbar.xml") as m:
        s = m.summary
        assert (s.rigid_body_count, s.revolute_count, s.loop_count, s.planar_loop_count, s.dof) == (3, 4, 1, 1, 1)
        assert [j.is_cut for j in m.joints].count(True) == 1
    with mbx.translate(SAMPLES / "joints_showcase" / "joints_showcase.xml") as m:
        s = m.summary
        assert (s.rigid_body_count, s.joint_node_count) == (4, 1)
        assert (s.prismatic_count, s.revolute_count, s.spherical_count) == (2, 1, 3)
        # README: the loop has 3 freedoms; the pendulum's spherical joint adds 3 more.
        assert (s.loop_count, s.dof, s.gruebler_dof, s.redundant_constraint_count) == (1, 6, 6, 0)


def test_report_json_agrees_with_the_queries(arm, tmp_path):
    report = arm.write_report(tmp_path / "report")
    assert (tmp_path / "report" / "report.txt").exists()
    assert report == json.loads((tmp_path / "report" / "report.json").read_text())
    text = json.dumps(report)
    for body in arm.rigid_bodies[1:]:
        assert body.name in text
    for joint in arm.joints:
        assert joint.constraint_id in text


def test_a_missing_file_raises_with_the_file():
    with pytest.raises(mbx.MbxError) as e:
        mbx.translate(SAMPLES / "no_such_assembly.xml")
    assert e.value.status_name == "MBX_ERROR_INVALID_INPUT"
    assert e.value.subject_kind == "file"
    assert e.value.file.endswith("no_such_assembly.xml")
    assert "no_such_assembly.xml" in str(e.value)


def test_a_broken_xml_raises_with_file_and_line(tmp_path):
    text = ARM_XML.read_text().splitlines(keepends=True)
    # Cut the file inside its body: the reader must name a line, not crash.
    broken = tmp_path / "broken.xml"
    broken.write_text("".join(text[: len(text) // 2]) + "<unclosed attr=\n")
    with pytest.raises(mbx.MbxError) as e:
        mbx.translate(broken)
    assert e.value.file.endswith("broken.xml")
    assert e.value.line > 0
    assert f"broken.xml:{e.value.line}:" in str(e.value)


def test_a_missing_shapes_file_raises_naming_it(tmp_path):
    with pytest.raises(mbx.MbxError) as e:
        mbx.translate(ARM_XML, shapes=tmp_path / "none.wrl")
    assert "none.wrl" in e.value.file + e.value.message


def test_closed_mechanism_refuses_use():
    m = mbx.translate(ARM_XML, shapes=ARM_WRL)
    m.close()
    m.close()
    with pytest.raises(mbx.MbxError):
        m.summary


def test_simscape_double_pendulum_on_its_step_levers():
    """The second-generation Simscape sample through the same call: its
    levers' STEP files from ../shared, both hinges along the world's y."""
    steps = SHARED_DATA / "step" / "dfki_double_pendulum"
    if not (steps / "lever_200.STEP").exists():
        pytest.skip(f"no {steps}")
    with mbx.translate(SAMPLES / "double_pendulum_simscape" / "double_pendulum.xml", mesh_dirs=[steps]) as m:
        s = m.summary
        assert (s.rigid_body_count, s.revolute_count, s.loop_count, s.dof) == (2, 2, 0, 2)
        assert (s.warning_count, s.error_count) == (0, 0)
        assert [j.constraint_id for j in m.joints] == ["shoulder", "elbow"]
        for j in m.joints:
            assert np.allclose(np.abs(j.axis), [0, 1, 0], atol=1e-12)
        assert np.allclose(m.joints[1].position, [-0.0, 0.0642, -0.2], atol=1e-12)
        assert [b.name for b in m.rigid_bodies[1:]] == ["lever_200 <1>", "lever_300 <1>"]
        assert abs(m.rigid_bodies[1].mass - 0.67087) < 1e-12


def test_urdf_panda_with_its_packages_and_joint_dynamics(tmp_path):
    """A robot's URDF through the same call: package:// meshes through
    package_paths, the joints named as in the file, its <dynamics> attached as
    the file's own description (the report lists them) and kept under a
    description file the user attaches."""
    robots = SHARED_DATA / "urdf"
    urdf = robots / "panda_description" / "urdf" / "panda.urdf"
    if not urdf.exists():
        pytest.skip(f"no {urdf}")
    with mbx.translate(urdf, package_paths={"example-robot-data/robots": robots}) as m:
        s = m.summary
        assert (s.revolute_count, s.prismatic_count, s.dof) == (7, 2, 9)
        assert [j.constraint_id for j in m.joints][:2] == ["panda_joint1", "panda_joint2"]
        assert not [f for f in m.findings if f.code == "mesh_file_missing"]
        m.write_report(tmp_path / "r")
        report = (tmp_path / "r" / "report.txt").read_text()
        assert "'panda_joint1': damping 0.003 N m s/rad" in report
        # A description of the user's own refines the file's: joint 1's damping replaced, joint 2's kept.
        own = tmp_path / "d.xml"
        own.write_text('<mechatronics version="1"><joint constraint="panda_joint1" damping="0.5"/></mechatronics>\n')
        m.attach_drives(own)
        m.write_report(tmp_path / "r2")
        report = (tmp_path / "r2" / "report.txt").read_text()
        assert "'panda_joint1': damping 0.5 N m s/rad" in report
        assert "'panda_joint2': damping 0.003 N m s/rad" in report
    with mbx.translate(urdf, package_paths={"example-robot-data/robots": robots}, floating_base=True) as m:
        assert m.summary.dof == 15


def test_urdf_update_writes_the_description_into_the_users_file(tmp_path):
    """update_urdf: the attached description's damping and a body's mass go
    into a copy of the user's URDF, the rest of its text unchanged, and the
    copy reads back with them as its own."""
    urdf = SHARED_DATA / "measured" / "dfki_double_pendulum_c0" / "identified_model_3.1_acrobot.urdf"
    if not urdf.exists():
        pytest.skip(f"no {urdf}")
    description = tmp_path / "d.xml"
    description.write_text('<mechatronics version="1"><joint constraint="Joint1" damping="0.25"/>'
                           '<body id="Link1" mass_scale="2"/></mechatronics>\n')
    out = tmp_path / "calibrated.urdf"
    with mbx.translate(urdf, mass_check=False) as m:
        mass = next(b.mass for b in m.rigid_bodies if b.id == "Link1")
        m.attach_drives(description)
        m.update_urdf(out)
    before, after = urdf.read_text().splitlines(), out.read_text().splitlines()
    changed = [(a, b) for a, b in zip(before, after) if a != b]
    assert len(before) == len(after) and len(changed) == 3  # Joint1's dynamics, Link1's mass and inertia
    assert changed[2] == ('    <dynamics damping="0.0" friction="0.0" />', '    <dynamics damping="0.25" friction="0.0" />')
    with mbx.translate(out, mass_check=False) as m:
        assert abs(next(b.mass for b in m.rigid_bodies if b.id == "Link1") - 2 * mass) < 1e-12
        m.write_report(tmp_path / "r")
        assert "'Joint1': damping 0.25 N m s/rad" in (tmp_path / "r" / "report.txt").read_text()
