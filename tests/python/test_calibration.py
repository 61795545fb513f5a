"""Calibration through Python, the checks of tests/integration's
calibration_api_test on the same EMPS records (skipped without the measured
data beside the repository, as there)."""
import pytest

import mbx
from conftest import EMPS_DRIVES, EMPS_EXPERIMENT, EMPS_XML, SHARED_DATA

pytestmark = pytest.mark.skipif(not (SHARED_DATA / "measured" / "emps" / "emps_train.csv").exists(),
                                reason="EMPS measured data (../shared/data/measured/emps) not present")


def emps():
    m = mbx.translate(EMPS_XML)
    m.attach_drives(EMPS_DRIVES)
    return m


def test_emps_calibrated_written_and_fed_back(tmp_path):
    out = tmp_path / "out"
    with emps() as m:
        c = m.calibrate(EMPS_EXPERIMENT, directory=out)
    # The result outlives the mechanism it came from.
    s = c.summary
    assert s.cause_count == 3 == len(c.causes)
    assert s.baseline_simulated_fit_error > 65
    assert s.final_simulated_fit_error <= 7
    assert s.final_simulated_validation_error <= 10
    assert s.final_validation_error < s.baseline_validation_error
    previous = s.baseline_simulated_validation_error
    for cause in c.causes:
        assert cause.subject_id == "40:-:41" and cause.subject_kind == "constraint"
        assert cause.written
        assert len(cause.evidence) > 10
        assert cause.simulated_validation_error < previous
        previous = cause.simulated_validation_error
        assert cause.parameters and all(p.std_error >= 0 for p in cause.parameters)
    assert {cause.name for cause in c.causes} >= {"coulomb_friction", "viscous_friction"}
    assert len(c.warnings) == s.warning_count
    for f in ("calibration.json", "calibration.html", "description.xml"):
        assert (out / f).exists()
    c.close()

    # The written description, fed back: its model is the calibrated one.
    with mbx.translate(EMPS_XML) as again:
        again.attach_drives(out / "description.xml")
        c2 = again.calibrate(EMPS_EXPERIMENT)
    assert c2.summary.baseline_simulated_fit_error == pytest.approx(s.final_simulated_fit_error, rel=0.02)
    assert c2.summary.baseline_simulated_validation_error == pytest.approx(s.final_simulated_validation_error,
                                                                           rel=0.02)


def test_a_bad_experiment_names_its_file_and_writes_nothing(tmp_path):
    text = EMPS_EXPERIMENT.read_text().replace("force_N", "forse_N")
    records = str(SHARED_DATA / "measured" / "emps") + "/"
    text = text.replace("../../../shared/data/measured/emps/", records)
    bad = tmp_path / "bad.xml"
    bad.write_text(text)
    with emps() as m:
        with pytest.raises(mbx.MbxError) as e:
            m.calibrate(bad, directory=tmp_path / "out")
    assert e.value.status_name == "MBX_ERROR_INVALID_INPUT"
    assert "forse_N" in e.value.message
    assert "bad.xml" in str(e.value)
    assert not (tmp_path / "out").exists()
