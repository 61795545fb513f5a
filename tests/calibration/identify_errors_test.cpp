// The inverse-dynamics figures of a cause set recomputed at its values
// (recompute_errors, what calibrate() does after the transmission stage
// changed the causes): on identify()'s own causes they equal the joint fit's
// final figures, without causes they are the baseline's, and a dropped cause
// takes its share of the error back.
#include <doctest/doctest.h>

#include "calibration/identification/identify.h"
#include "calibration/identification/regression_rows.h"
#include "hidden_effects.h"
#include "sim/build_model.h"
#include "temp_dir.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;
using namespace mbx::calibration;

TEST_CASE("calibration: a cause set's figures at its values agree with the joint fit, and follow a dropped cause") {
    mbx_test::TempDir dir("mbx_identify_errors");
    mbx_test::CaseSpec spec;
    spec.name = "arm";
    spec.mechanism = "two_link_arm";
    spec.seed = 7;
    spec.fit_seconds = 4, spec.validation_seconds = 2;
    spec.effects = {{"viscous_friction", "two_link_arm/elbow", 0.3, 0.3}};
    const mbx_test::GeneratedCase g = mbx_test::generate_case(spec, dir.file(spec.name));
    const auto opened = mbx_test::open_mechanism(spec.mechanism);
    const sim::Model m = sim::build_model(*opened->mechanism);
    const std::vector<Record> records = load_records(load_experiment(g.experiment_path), m);
    std::vector<const Record*> fit_records, validation_records;
    for (const Record& r : records) (r.role == Role::Fit ? fit_records : validation_records).push_back(&r);
    const IdentifyOptions options;
    const RegressionRows fit = regression_rows(m, fit_records, options);
    const RegressionRows validation = regression_rows(m, validation_records, options, &fit.weight);
    const Identification id = identify(m, fit, validation, options);
    REQUIRE_FALSE(id.causes.empty());
    REQUIRE(id.final_validation_error < 0.5 * id.baseline_validation_error);

    // The causes at the joint fit's values: the same residual, reached by
    // another road (the columns times the values, not the least squares).
    Identification again = id;
    recompute_errors(again, fit, validation);
    CHECK(again.final_fit_error == mbx_test::relative(id.final_fit_error, 1e-9));
    CHECK(again.final_validation_error == mbx_test::relative(id.final_validation_error, 1e-9));
    CHECK(again.causes.back().validation_error == mbx_test::relative(id.final_validation_error, 1e-9));
    double before = id.baseline_validation_error;
    for (const SelectedCause& c : again.causes) {
        CHECK(c.validation_gain == mbx_test::relative(before - c.validation_error, 1e-12));
        before = c.validation_error;
    }

    // No cause: the model as given.
    Identification none = id;
    none.causes.clear();
    recompute_errors(none, fit, validation);
    CHECK(none.final_fit_error == mbx_test::relative(id.baseline_fit_error, 1e-9));
    CHECK(none.final_validation_error == mbx_test::relative(id.baseline_validation_error, 1e-9));

    // The elbow's damping dropped: most of what it explained comes back.
    Identification dropped = id;
    size_t at = dropped.causes.size();
    for (size_t i = 0; i < dropped.causes.size(); ++i)
        if (dropped.causes[i].candidate.cause == "viscous_friction") at = i;
    REQUIRE(at < dropped.causes.size());
    dropped.causes.erase(dropped.causes.begin() + long(at));
    recompute_errors(dropped, fit, validation);
    CHECK(dropped.final_validation_error > 2 * id.final_validation_error);
    CHECK(dropped.final_validation_error <= id.baseline_validation_error * 1.001);
}

}  // namespace MBX_UNITY_ID
