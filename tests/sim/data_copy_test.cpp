// Data objects are values: a rollout forked from another by copying its data
// continues exactly as the original does, and a fresh copy is usable at once.
// (Under the sanitizers this also checks that no workspace copies state it
// never initialised.)
#include <doctest/doctest.h>

#include "tests/export/export_fixture.h"
#include "sim/build_model.h"
#include "sim/integrator.h"
#include "sim/simulation.h"

namespace MBX_UNITY_ID {

using namespace mbx;

TEST_CASE("sim: a copied data object continues exactly as the original") {
    auto t = xtest::translate_builtin("double_cardan");
    const sim::Model model = sim::build_model(*t->mechanism);
    REQUIRE(!model.closures.empty());
    sim::IntegratorSettings settings;
    settings.step = 1e-3;

    const sim::Data untouched(model);
    sim::Data d = untouched;  // a copy of a data object no solve has touched yet
    sim::initial_state(model, d, {{0, 0, true, 3.0}});
    sim::advance(model, d, settings, 0.2);

    sim::Data fork = d;
    sim::advance(model, d, settings, 0.5);
    sim::advance(model, fork, settings, 0.5);
    CHECK(fork.time == d.time);
    CHECK(fork.q == d.q);  // bit for bit: the same arithmetic on the same state
    CHECK(fork.v == d.v);
    CHECK((d.q - model.q_reference).norm() > 0.1);  // it moved

    sim::Data assigned(model);
    assigned = fork;
    sim::advance(model, assigned, settings, 0.6);
    sim::advance(model, d, settings, 0.6);
    CHECK(assigned.q == d.q);
}
}  // namespace MBX_UNITY_ID
