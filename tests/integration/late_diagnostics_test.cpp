// A mesh that passes the host's open-time check but fails when the SDK first
// asks for it lazily: a version-4 host appends a diagnostic while it serves
// get_shapes, and the SDK turns it into a finding of the mechanism (so the
// report written afterwards has it). An older host's diagnostics are pulled
// once, before translation, as their list may not only grow.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "../common/file_text.h"
#include "support/plugin_fixture.h"
#include "support/temp_dir.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

// The fourbar builtin whose crank "mesh file" breaks at load time: the shape
// source reports it through the host and serves no mesh for it.
struct LateHost {
    std::unique_ptr<mbx_stub::Host> host;
    std::string crank_id;
    int failures = 0;

    LateHost() {
        mbx_stub::Assembly a = builtin("fourbar");
        for (const auto& b : a.bodies)
            if (b.name == "Crank") crank_id = b.id;
        REQUIRE(!crank_id.empty());
        a.shapes.erase(crank_id);
        mbx_memory::ShapeSource source = [this](const mbx_memory::Body& body, std::vector<mbx_memory::Mesh>&,
                                                std::string&) {
            if (body.id != crank_id) return true;
            ++failures;
            mbx_memory::Diagnostic d;
            d.code = "mesh_file_unreadable";
            d.subject_kind = MBX_SUBJECT_BODY;
            d.subject_id = body.id;
            d.subject_name = body.name;
            d.file = "fourbar.xml";
            d.line = 42;
            d.message = "mesh file 'crank.stl' of body 'Crank' could not be read: truncated";
            host->add_diagnostic(d);
            return true;  // the body just has no shape
        };
        host = std::make_unique<mbx_stub::Host>(std::move(a), mbx_stub::Faults{}, std::move(source));
    }
};

int late_findings(const mbx_mechanism* m, mbx_finding* out = nullptr) {
    int n = 0;
    const uint32_t count = api().mechanism_finding_count(m);
    for (uint32_t i = 0; i < count; ++i) {
        mbx_finding f{};
        f.struct_size = sizeof f;
        REQUIRE(api().mechanism_get_finding(m, i, &f) == MBX_OK);
        if (f.code == MBX_FINDING_HOST_DIAGNOSTIC && std::strcmp(f.code_name, "mesh_file_unreadable") == 0) {
            ++n;
            if (out) *out = f;
        }
    }
    return n;
}

mbx_shape_stats stats(mbx_context* c, mbx_mechanism* m, uint32_t body) {
    mbx_shape_stats s{};
    s.struct_size = sizeof s;
    REQUIRE(api().mechanism_get_shape_stats(c, m, body, &s) == MBX_OK);
    return s;
}

}  // namespace

TEST_CASE("late host diagnostics: a mesh failing on lazy load becomes a finding and reaches the report") {
    LateHost h;
    ContextPtr ctx = make_context();
    mbx_mechanism* raw = nullptr;
    REQUIRE(api().translate(ctx.get(), h.host->table(), nullptr, &raw) == MBX_OK);
    MechanismPtr mech(raw);
    CHECK(late_findings(mech.get()) == 0);  // nothing loaded yet
    const uint32_t warnings_before = summary(mech.get()).warning_count;

    const uint32_t crank = find_part(mech.get(), h.crank_id);
    CHECK(stats(ctx.get(), mech.get(), crank).mesh_count == 0);
    CHECK(h.failures == 1);
    mbx_finding f{};
    REQUIRE(late_findings(mech.get(), &f) == 1);
    CHECK(f.severity == MBX_SEVERITY_WARNING);
    CHECK(f.subject_kind == MBX_SUBJECT_BODY);
    CHECK(std::string(f.subject_id) == h.crank_id);
    CHECK(std::string(f.file) == "fourbar.xml");
    CHECK(f.line == 42);
    CHECK(std::string(f.message).find("truncated") != std::string::npos);
    CHECK(summary(mech.get()).warning_count == warnings_before + 1);

    // Cached shapes are not asked for again, so the finding is not repeated;
    // other bodies' loads add nothing.
    stats(ctx.get(), mech.get(), crank);
    for (uint32_t b = 0; b < body_total(mech.get()); ++b) stats(ctx.get(), mech.get(), b);
    CHECK(late_findings(mech.get()) == 1);

    TempDir dir;
    REQUIRE(api().mechanism_write_report(ctx.get(), mech.get(), dir.path.string().c_str()) == MBX_OK);
    const std::string json = mbx_test::read_file(dir.path / "report.json");
    CHECK(json.find("\"mesh_file_unreadable\"") != std::string::npos);
    CHECK(mbx_test::read_file(dir.path / "report.txt").find("crank.stl") != std::string::npos);
}

TEST_CASE("late host diagnostics: an export that loads the meshes brings them into the findings") {
    LateHost h;
    ContextPtr ctx = make_context();
    mbx_mechanism* raw = nullptr;
    REQUIRE(api().translate(ctx.get(), h.host->table(), nullptr, &raw) == MBX_OK);
    MechanismPtr mech(raw);
    TempDir dir;
    mbx_export_options o{};
    o.struct_size = sizeof o;
    o.formats = MBX_EXPORT_MESHES;
    REQUIRE(api().mechanism_export(ctx.get(), mech.get(), &o, dir.path.string().c_str()) == MBX_OK);
    CHECK(late_findings(mech.get()) == 1);
}

TEST_CASE("late host diagnostics: the mass check's shape loads during translation count too") {
    LateHost h;
    ContextPtr ctx = make_context();
    mbx_translate_options o{};
    o.struct_size = sizeof o;
    o.flags = MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES;
    mbx_mechanism* raw = nullptr;
    REQUIRE(api().translate(ctx.get(), h.host->table(), &o, &raw) == MBX_OK);
    MechanismPtr mech(raw);
    CHECK(late_findings(mech.get()) == 1);
}

TEST_CASE("late host diagnostics: a version-3 host's list is pulled only once") {
    LateHost h;
    mbx_host v3 = *h.host->table();
    v3.abi_version = 3;
    v3.struct_size = uint32_t(offsetof(mbx_host, get_diagnostic) + sizeof v3.get_diagnostic);
    ContextPtr ctx = make_context();
    mbx_mechanism* raw = nullptr;
    REQUIRE(api().translate(ctx.get(), &v3, nullptr, &raw) == MBX_OK);
    MechanismPtr mech(raw);
    stats(ctx.get(), mech.get(), find_part(mech.get(), h.crank_id));
    CHECK(h.failures == 1);
    CHECK(late_findings(mech.get()) == 0);
}

TEST_CASE("late host diagnostics: what the host appended before failing get_shapes is kept with the error") {
    mbx_stub::Assembly a = builtin("fourbar");
    std::string crank_id;
    for (const auto& b : a.bodies)
        if (b.name == "Crank") crank_id = b.id;
    std::unique_ptr<mbx_stub::Host> host;
    mbx_memory::ShapeSource source = [&](const mbx_memory::Body& body, std::vector<mbx_memory::Mesh>&,
                                         std::string& error) {
        if (body.id != crank_id) return true;
        mbx_memory::Diagnostic d;
        d.severity = MBX_SEVERITY_ERROR;
        d.code = "cad_kernel_crashed";
        d.subject_kind = MBX_SUBJECT_BODY;
        d.subject_id = body.id;
        d.message = "the CAD kernel crashed tessellating 'Crank'";
        host->add_diagnostic(d);
        error = "tessellation failed";
        return false;
    };
    host = std::make_unique<mbx_stub::Host>(std::move(a), mbx_stub::Faults{}, std::move(source));
    ContextPtr ctx = make_context();
    mbx_mechanism* raw = nullptr;
    REQUIRE(api().translate(ctx.get(), host->table(), nullptr, &raw) == MBX_OK);
    MechanismPtr mech(raw);
    mbx_shape_stats s{};
    s.struct_size = sizeof s;
    CHECK(api().mechanism_get_shape_stats(ctx.get(), mech.get(), find_part(mech.get(), crank_id), &s) ==
          MBX_ERROR_HOST_CALLBACK);
    CHECK(std::string(api().context_last_error(ctx.get())).find("tessellation failed") != std::string::npos);
    int found = 0;
    for (uint32_t i = 0; i < api().mechanism_finding_count(mech.get()); ++i) {
        mbx_finding f{};
        f.struct_size = sizeof f;
        REQUIRE(api().mechanism_get_finding(mech.get(), i, &f) == MBX_OK);
        if (std::strcmp(f.code_name, "cad_kernel_crashed") == 0) {
            ++found;
            CHECK(f.severity == MBX_SEVERITY_ERROR);
        }
    }
    CHECK(found == 1);
    CHECK(summary(mech.get()).error_count >= 1);
}
}  // namespace MBX_UNITY_ID
