// A host that fails midway, serves NaN, or is cancelled: the SDK must return
// the right status, produce nothing, and say which body or constraint it was.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "support/plugin_fixture.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("host failure: get_body failing midway is MBX_ERROR_HOST_CALLBACK naming the body") {
    for (const char* name : {"fourbar", "six_axis_arm"}) {
        const mbx_stub::Assembly a = builtin(name);
        for (long k : {0L, long(a.bodies.size() / 2), long(a.bodies.size() - 1)}) {
            INFO(name << " fail_at_body " << k);
            mbx_stub::Faults f;
            f.fail_at_body = k;
            const Run r = translate(a, f);
            CHECK(r.status == MBX_ERROR_HOST_CALLBACK);
            CHECK(r.get() == nullptr);
            CHECK_MESSAGE(contains(r.error, a.bodies[size_t(k)].id), r.error);
            CHECK_MESSAGE(contains(r.error, "simulated failure"), "the host's own message is passed on: " << r.error);
            // Translation stopped at the failing body.
            CHECK(r.host->counts().bodies == size_t(k) + 1);
            CHECK(r.host->counts().shapes == 0);
        }
    }
}

TEST_CASE("host failure: get_constraint failing midway is MBX_ERROR_HOST_CALLBACK naming the constraint") {
    const mbx_stub::Assembly a = builtin("double_cardan");
    for (long k : {0L, 3L, long(a.constraints.size() - 1)}) {
        INFO("fail_at_constraint " << k);
        mbx_stub::Faults f;
        f.fail_at_constraint = k;
        const Run r = translate(a, f);
        CHECK(r.status == MBX_ERROR_HOST_CALLBACK);
        CHECK(r.get() == nullptr);
        CHECK_MESSAGE(contains(r.error, a.constraints[size_t(k)].id), r.error);
    }
}

TEST_CASE("host failure: a NaN mass is MBX_ERROR_INVALID_INPUT naming the body") {
    const mbx_stub::Assembly a = builtin("planar_sixbar");
    mbx_stub::Faults f;
    f.nan_at_body = 3;
    const Run r = translate(a, f);
    CHECK(r.status == MBX_ERROR_INVALID_INPUT);
    CHECK(r.get() == nullptr);
    CHECK_MESSAGE(contains(r.error, a.bodies[3].id), r.error);
    CHECK(r.subject_kind == MBX_SUBJECT_BODY);
    CHECK(r.subject_id == a.bodies[3].id);
}

TEST_CASE("host failure: a context recovers after a failed translation") {
    const mbx_stub::Assembly a = builtin("fourbar");
    mbx_stub::Faults f;
    f.fail_at_body = 1;
    mbx_stub::Host failing(a, f), good(a);
    ContextPtr context = make_context();
    mbx_mechanism* m = nullptr;
    CHECK(api().translate(context.get(), failing.table(), nullptr, &m) == MBX_ERROR_HOST_CALLBACK);
    CHECK(m == nullptr);
    CHECK(std::string(api().context_last_error(context.get())) != "");
    REQUIRE(api().translate(context.get(), good.table(), nullptr, &m) == MBX_OK);
    MechanismPtr owned(m);
    CHECK(std::string(api().context_last_error(context.get())) == "");
    CHECK(summary(m).dof == 1);
}

TEST_CASE("host failure: shapes failing later is reported then and leaves the mechanism usable") {
    const mbx_stub::Assembly a = builtin("six_axis_arm");
    mbx_stub::Faults f;
    f.fail_shapes_at_body = 1;  // link1; translation never asks for shapes, so it succeeds
    const Run r = translate(a, f);
    REQUIRE_MESSAGE(r.status == MBX_OK, r.error);
    const uint32_t link1 = find_part(r.get(), a.bodies[1].id);
    mbx_shape_stats stats{};
    stats.struct_size = sizeof stats;
    CHECK(api().mechanism_get_shape_stats(r.context.get(), r.get(), link1, &stats) == MBX_ERROR_HOST_CALLBACK);
    const std::string error = api().context_last_error(r.context.get());
    CHECK_MESSAGE(contains(error, a.bodies[1].id), error);
    // Other bodies still work and the mechanism is intact.
    const uint32_t link3 = find_part(r.get(), "six_axis_arm/link3");
    CHECK(api().mechanism_get_shape_stats(r.context.get(), r.get(), link3, &stats) == MBX_OK);
    CHECK(stats.mesh_count == 1);
    CHECK(summary(r.get()).dof == 6);
}

namespace {

struct ProgressLog {
    long cancel_at = -1;  // call index to return non-zero at; -1 never
    long calls = 0;
    bool sane = true;     // every call had a stage and a fraction in [0, 1]
    static int callback(void* data, const char* stage, double fraction) {
        auto* log = static_cast<ProgressLog*>(data);
        if (!stage || !*stage || !(fraction >= 0.0 && fraction <= 1.0)) log->sane = false;
        return log->calls++ == log->cancel_at ? 1 : 0;
    }
};

mbx_status translate_with_progress(const mbx_stub::Assembly& a, ProgressLog& log, MechanismPtr& out) {
    mbx_stub::Host host(a);
    ContextPtr context = make_context();
    REQUIRE(api().context_set_progress(context.get(), &ProgressLog::callback, &log) == MBX_OK);
    mbx_mechanism* m = nullptr;
    const mbx_status status = api().translate(context.get(), host.table(), nullptr, &m);
    out.reset(m);
    if (m) api().mechanism_release_host(m);  // the host dies here
    return status;
}

}  // namespace

TEST_CASE("cancel: a non-zero return from the progress callback is MBX_ERROR_CANCELLED and produces nothing") {
    const mbx_stub::Assembly a = mbx_stub::generate_assembly(400, 11);
    ProgressLog full;
    MechanismPtr m;
    REQUIRE(translate_with_progress(a, full, m) == MBX_OK);
    CHECK(full.sane);
    REQUIRE_MESSAGE(full.calls >= 2, "progress must be reported during a 400-part translation");

    for (long at : {0L, full.calls / 2, full.calls - 1}) {
        INFO("cancel at progress call " << at << " of " << full.calls);
        ProgressLog log;
        log.cancel_at = at;
        MechanismPtr cancelled;
        CHECK(translate_with_progress(a, log, cancelled) == MBX_ERROR_CANCELLED);
        CHECK(cancelled == nullptr);
        CHECK(log.calls == at + 1);  // no progress call after the cancel
    }
}

TEST_CASE("cancel: a builtin can be cancelled at its first progress call") {
    ProgressLog log;
    log.cancel_at = 0;
    MechanismPtr m;
    const mbx_status status = translate_with_progress(builtin("fourbar"), log, m);
    REQUIRE_MESSAGE(log.calls > 0, "no progress reported for fourbar");
    CHECK(status == MBX_ERROR_CANCELLED);
    CHECK(m == nullptr);
}
}  // namespace MBX_UNITY_ID
