"""Exports and drives through Python, as tests/integration's
mechatronics_api_test checks them through C: the five-axis arm's drive file
attaches 5 drives with the library's numbers, and every export carries them."""
import math

import pytest

import mbx
from conftest import ARM_DRIVES, SAMPLES

DEG = math.pi / 180


def test_drive_file_resolves_to_the_library_numbers(driven_arm):
    drives = {d.name: d for d in driven_arm.drives}
    assert sorted(drives) == sorted(["waist", "shoulder", "elbow", "wrist_pitch", "wrist_roll"])
    joints = driven_arm.joints
    constraint = {"waist": "40:-:41", "shoulder": "41:-:42", "elbow": "42:-:43", "wrist_pitch": "43:-:44",
                  "wrist_roll": "44:-:45"}
    for name, d in drives.items():
        assert joints[d.joint].constraint_id == constraint[name]
        assert not d.linear
        assert d.motion_point_count == 5
    assert drives["waist"].ratio == pytest.approx(100.0)
    assert drives["waist"].armature == pytest.approx(1.42e-5 * 1e4 + 3.3e-6 * 1e4)
    assert drives["elbow"].ratio == pytest.approx(4.3)
    assert drives["elbow"].efficiency == pytest.approx(0.9)
    assert drives["wrist_roll"].ratio == pytest.approx(251.0)
    assert drives["wrist_roll"].armature == pytest.approx(1.2e-7 * 251.0 ** 2)
    # The waist's smooth (quintic) move 0 -> 45 deg over 0.5 .. 2 s: half-way, half the angle at 1.875x the mean speed.
    w = drives["waist"].index
    assert driven_arm.drive_target(w, 0.5)[0] == pytest.approx(0.0, abs=1e-12)
    half = driven_arm.drive_target(w, 1.25)
    assert half[0] == pytest.approx(22.5 * DEG)
    assert half[1] == pytest.approx(1.875 * 45 * DEG / 1.5)
    assert driven_arm.drive_target(w, 5.0)[0] == pytest.approx(45 * DEG)
    assert driven_arm.drive_target(drives["elbow"].index, 6.0)[0] == pytest.approx(-30 * DEG)
    with pytest.raises(mbx.MbxError):
        driven_arm.drive_target(5, 0.0)


def test_exports_carry_the_drives_and_repeat_byte_for_byte(driven_arm, tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    driven_arm.export(a, formats=("mjcf", "urdf"), model_name="arm")
    driven_arm.export(b, formats=("mjcf", "urdf"), model_name="arm")
    mjcf = (a / "mjcf" / "arm.xml").read_text()
    urdf = (a / "urdf" / "arm.urdf").read_text()
    actuators = mjcf[mjcf.index("<actuator>"):mjcf.index("</actuator>")]
    assert actuators.count("<general ") + actuators.count("<motor ") == 5
    assert urdf.count("<transmission ") == 5
    assert urdf.count("<mechanicalReduction>251</mechanicalReduction>") == 2
    files = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    for f in files:
        assert (a / f).read_bytes() == (b / f).read_bytes(), f
    # Detached, the same mechanism exports passive.
    driven_arm.attach_drives(None)
    assert driven_arm.drives == []
    driven_arm.export(tmp_path / "passive", formats=("mjcf",), model_name="arm")
    assert "<actuator" not in (tmp_path / "passive" / "mjcf" / "arm.xml").read_text()


def test_all_formats(arm, tmp_path):
    arm.export(tmp_path, model_name="arm", mesh_format="gltf")
    assert (tmp_path / "scene.glb").stat().st_size > 1000
    assert any((tmp_path / "modelica").rglob("*.mo"))
    assert (tmp_path / "urdf" / "arm.urdf").exists()
    with pytest.raises(mbx.MbxError):
        arm.export(tmp_path / "x", formats=("step",))


def test_drives_that_do_not_fit_name_the_constraint():
    with mbx.translate(SAMPLES / "fourbar_imperial" / "fourbar.xml") as fourbar:
        with pytest.raises(mbx.MbxError) as e:
            fourbar.attach_drives(ARM_DRIVES)
        assert e.value.status_name == "MBX_ERROR_INVALID_INPUT"
        # The four-bar has constraints 40..43 too: the wrist drives are the ones that cannot fit.
        assert "no constraint with id '44:-:45'" in e.value.message
        assert e.value.file.endswith("five_axis_arm_drives.xml") and e.value.line > 0
        assert fourbar.drives == []


def test_view_page_is_self_contained_and_refuses_a_foreign_trajectory(arm, tmp_path):
    import mbx
    page = arm.write_view(tmp_path, title="arm")
    text = open(page, encoding="utf-8").read()
    assert "<title>arm</title>" in text and "THREE.GLTFLoader" in text
    assert "<script src" not in text
    assert "const MBX_MOTION = null;" in text
    bad = tmp_path / "trajectory.csv"
    bad.write_text("time,nothing\n0,1\n")
    with pytest.raises(mbx.MbxError) as error:
        arm.write_view(tmp_path / "v", trajectory=bad)
    assert "trajectory.csv: no column" in str(error.value)
    assert not (tmp_path / "v" / "view.html").exists()
