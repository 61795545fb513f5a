#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

#include "core/assembly/host_reader.h"
#include "apps/stub_host/assemblies/stub_assembly.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

mbx_pose pose_at(double x, double y, double z, const Mat3& r = Mat3::Identity()) {
    mbx_pose p{};
    p.position[0] = x;
    p.position[1] = y;
    p.position[2] = z;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) p.rotation[3 * i + j] = r(i, j);
    return p;
}

// Two parts in millimetres and grams joined by a revolute about the base
// frame's local x axis; the base frame is given relative to its body.
mbx_stub::Assembly small_assembly() {
    mbx_stub::Assembly a;
    a.name = "small";
    mbx_stub::Body ground;
    ground.id = "g";
    ground.flags = MBX_BODY_GROUND;
    ground.units = {0.001, 0.001, 0};  // mm, g, inertia derived: g mm^2
    ground.mass = 1000;
    ground.inertia[0] = ground.inertia[4] = ground.inertia[8] = 1e6;
    ground.pose = pose_at(0, 0, 0);
    mbx_stub::Body arm = ground;
    arm.id = "arm";
    arm.flags = 0;
    arm.mass = 500;        // 0.5 kg
    arm.com[0] = 100;      // 0.1 m
    arm.inertia[0] = 2e6;  // 2e6 g mm^2 = 2e-3 kg m^2
    arm.inertia[4] = arm.inertia[8] = 3e6;
    const Mat3 turned = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
    arm.pose = pose_at(200, 0, 0, turned);
    a.bodies = {ground, arm};
    mbx_stub::Frame fb;
    fb.id = "fb";
    fb.body_id = "arm";
    fb.reference = MBX_FRAME_IN_BODY;  // 50 mm along the arm's local x = world +y
    fb.units = {0.001, 1, 0};
    fb.pose = pose_at(50, 0, 0);
    mbx_stub::Frame fg;
    fg.id = "fg";
    fg.body_id = "g";
    fg.units = {0.001, 1, 0};
    fg.pose = pose_at(200, 50, 0);
    a.frames = {fg, fb};
    mbx_stub::Constraint c;
    c.id = "hinge";
    c.base_frame_id = "fb";
    c.follower_frame_id = "fg";
    mbx_stub::Primitive p{MBX_PRIMITIVE_REVOLUTE};
    p.axis_reference = MBX_AXIS_IN_BASE_FRAME;
    p.axis[0] = 2; p.axis[1] = 0; p.axis[2] = 0;  // not unit: normalized by the reader
    p.has_limits = true;
    p.lower = -1;
    p.upper = 1;
    c.chain = {p};
    a.constraints = {c};
    return a;
}

Assembly read(const mbx_stub::Host& host, Findings& findings) {
    Progress progress;
    return read_host(host.table(), HostReadOptions{}, progress, findings);
}

// Runs the reader expecting an Error; returns it for inspection.
Error read_error(const mbx_stub::Assembly& a, mbx_stub::Faults faults = {}) {
    mbx_stub::Host host(a, faults);
    Findings findings;
    try {
        read(host, findings);
    } catch (const Error& e) {
        return e;
    }
    FAIL("no error raised");
    return Error(MBX_OK, {}, "");
}

}  // namespace

TEST_CASE("host reader converts units per quantity and resolves frames and axes into world") {
    mbx_stub::Host host(small_assembly());
    Findings findings;
    Assembly a = read(host, findings);
    REQUIRE(a.parts.size() == 2);
    CHECK(a.name == "small");
    const Part& arm = a.parts[1];
    CHECK(arm.mass == mbx_test::relative(0.5, 1e-6));
    CHECK(arm.com.x() == mbx_test::relative(0.1, 1e-6));
    CHECK(arm.inertia(0, 0) == mbx_test::relative(2e-3, 1e-6));  // g*mm^2 -> kg*m^2 is 1e-9
    CHECK(arm.pose.position.x() == mbx_test::relative(0.2, 1e-6));
    // Frame 50 mm along the arm's local x, and the arm is turned +90 deg about z.
    CHECK((a.frames[1].world.position - Vec3(0.2, 0.05, 0)).norm() < 1e-12);
    // Axis local x of that frame -> world +y, unit length.
    CHECK((a.constraints[0].chain[0].axis - Vec3(0, 1, 0)).norm() < 1e-12);
    CHECK(a.constraints[0].chain[0].lower == -1);
    CHECK(findings.empty());
}

TEST_CASE("rounded rotations are repaired, a warning only above the rounding level") {
    mbx_stub::Assembly a = small_assembly();
    a.bodies[1].pose.rotation[0] += 2e-7;  // six-digit rounding: silent
    {
        mbx_stub::Host host(a);
        Findings f;
        Assembly out = read(host, f);
        CHECK(f.empty());
        CHECK(orthonormality_error(out.parts[1].pose.rotation) < 1e-12);
    }
    a.bodies[1].pose.rotation[1] += 1e-3;  // a sloppy matrix: repaired and reported
    {
        mbx_stub::Host host(a);
        Findings f;
        Assembly out = read(host, f);
        REQUIRE(f.size() == 1);
        CHECK(f[0].code == MBX_FINDING_ROTATION_REORTHONORMALIZED);
        CHECK(f[0].subject.id == "arm");
        CHECK(orthonormality_error(out.parts[1].pose.rotation) < 1e-12);
    }
}

TEST_CASE("host reader refuses what it cannot repair, naming the subject") {
    SUBCASE("reflection") {
        mbx_stub::Assembly a = small_assembly();
        a.bodies[1].pose.rotation[8] = -1;
        Error e = read_error(a);
        CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
        CHECK(e.subject().id == "arm");
        CHECK(std::string(e.what()).find("reflection") != std::string::npos);
    }
    SUBCASE("NaN mass") {
        Error e = read_error(small_assembly(), mbx_stub::Faults{-1, 1, -1, -1});
        CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
        CHECK(e.subject().kind == MBX_SUBJECT_BODY);
        CHECK(e.subject().id == "arm");
        CHECK(std::string(e.what()).find("mass") != std::string::npos);
    }
    SUBCASE("failing callback") {
        Error e = read_error(small_assembly(), mbx_stub::Faults{1, -1, -1, -1});
        CHECK(e.status() == MBX_ERROR_HOST_CALLBACK);
        CHECK(std::string(e.what()).find("arm") != std::string::npos);
    }
    SUBCASE("duplicate body id") {
        mbx_stub::Assembly a = small_assembly();
        a.bodies[1].id = "g";
        a.frames[1].body_id = "g";
        Error e = read_error(a);
        CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
        CHECK(std::string(e.what()).find("used twice") != std::string::npos);
    }
    SUBCASE("unknown frame reference") {
        mbx_stub::Assembly a = small_assembly();
        a.constraints[0].follower_frame_id = "nowhere";
        Error e = read_error(a);
        CHECK(e.subject().id == "hinge");
        CHECK(std::string(e.what()).find("nowhere") != std::string::npos);
    }
    SUBCASE("frame on an unknown body") {
        mbx_stub::Assembly a = small_assembly();
        a.frames[0].body_id = "ghost";
        Error e = read_error(a);
        CHECK(e.subject().id == "fg");
    }
    SUBCASE("zero axis") {
        mbx_stub::Assembly a = small_assembly();
        a.constraints[0].chain[0].axis[0] = 0;
        Error e = read_error(a);
        CHECK(e.subject().id == "hinge");
        CHECK(std::string(e.what()).find("zero-length axis") != std::string::npos);
    }
    SUBCASE("empty chain") {
        mbx_stub::Assembly a = small_assembly();
        a.constraints[0].chain.clear();
        Error e = read_error(a);
        CHECK(e.subject().id == "hinge");
    }
}

TEST_CASE("inverted limits are dropped with a warning") {
    mbx_stub::Assembly a = small_assembly();
    a.constraints[0].chain[0].lower = 2;
    mbx_stub::Host host(a);
    Findings f;
    Assembly out = read(host, f);
    CHECK_FALSE(out.constraints[0].chain[0].has_limits);
    REQUIRE(f.size() == 1);
    CHECK(f[0].code == MBX_FINDING_LIMITS_INVERTED);
}

TEST_CASE("figures in messages are readable: limits of 1e308 are not printed as 309 digits") {
    mbx_stub::Assembly a = small_assembly();
    a.constraints[0].chain[0].lower = 1e308;
    a.constraints[0].chain[0].upper = 2.5e-7;
    mbx_stub::Host host(a);
    Findings f;
    read(host, f);
    REQUIRE(f.size() == 1);
    CHECK(f[0].message.find("has lower limit 1e+308 above upper limit 2.5e-07; the limits are ignored") !=
          std::string::npos);
    CHECK(f[0].message.size() < 120);
}

TEST_CASE("host tables too small or without required callbacks are refused") {
    mbx_stub::Host host(small_assembly());
    mbx_host table = *host.table();
    Progress progress;
    Findings f;
    table.struct_size = 16;
    CHECK_THROWS_AS(read_host(&table, {}, progress, f), Error);
    try {
        read_host(&table, {}, progress, f);
    } catch (const Error& e) {
        CHECK(e.status() == MBX_ERROR_VERSION);
    }
    table = *host.table();
    table.get_primitive = nullptr;
    try {
        read_host(&table, {}, progress, f);
        FAIL("accepted a table without get_primitive");
    } catch (const Error& e) {
        CHECK(e.status() == MBX_ERROR_INVALID_ARGUMENT);
        CHECK(std::string(e.what()).find("get_primitive") != std::string::npos);
    }
}

// Found by fuzz/fuzz_host_table: a count is the host's word, not a size to
// allocate before the first call; a host that claims 2^64-1 bodies, frames or
// constraints (a garbage out-parameter) must fail at the first item it cannot
// deliver, with the host's own message, instead of exhausting memory.
TEST_CASE("a host count far beyond what it delivers fails at the first missing item") {
    mbx_stub::Host host(small_assembly());
    const auto huge = [](void*, size_t* n) -> int {
        *n = ~size_t(0);
        return 0;
    };
    struct Case {
        int (*mbx_host::*count)(void*, size_t*);
        const char* missing;
    };
    for (const Case& c : {Case{&mbx_host::body_count, "body #2"}, Case{&mbx_host::frame_count, "frame #2"},
                          Case{&mbx_host::constraint_count, "constraint #1"}}) {
        CAPTURE(c.missing);
        mbx_host table = *host.table();
        table.*c.count = huge;
        Progress progress;
        Findings f;
        try {
            read_host(&table, {}, progress, f);
            FAIL("accepted a count the host cannot deliver");
        } catch (const Error& e) {
            CHECK(e.status() == MBX_ERROR_HOST_CALLBACK);
            CHECK(std::string(e.what()).find(c.missing) != std::string::npos);
            CHECK(std::string(e.what()).find("memory host: no") != std::string::npos);
        }
    }
}

// Found by fuzz/fuzz_host_table: a C host may put any int into an enum field,
// and the reader must judge it as an int (loading it as the C++ enum type is
// undefined behaviour, which UBSan stops on). Out-of-range frame references,
// primitive types and axis references are refused by name; a diagnostic's
// severity and subject kind fall back to a warning about nothing in particular.
namespace {
const mbx_host* g_wrapped = nullptr;
int g_enum_value = 0;
enum class EnumField { FrameReference, PrimitiveType, AxisReference, Diagnostic };
EnumField g_field = EnumField::FrameReference;

void put_int(void* field, int v) { std::memcpy(field, &v, sizeof v); }

int odd_frame(void* u, size_t i, mbx_frame_desc* out, char* m, size_t n) {
    const int r = g_wrapped->get_frame(u, i, out, m, n);
    if (g_field == EnumField::FrameReference) put_int(&out->reference, g_enum_value);
    return r;
}
int odd_primitive(void* u, size_t c, size_t k, mbx_primitive_desc* out, char* m, size_t n) {
    const int r = g_wrapped->get_primitive(u, c, k, out, m, n);
    if (g_field == EnumField::PrimitiveType) put_int(&out->type, g_enum_value);
    if (g_field == EnumField::AxisReference) put_int(&out->axis_reference, g_enum_value);
    return r;
}
int odd_diagnostic(void* u, size_t i, mbx_host_diagnostic* out) {
    const int r = g_wrapped->get_diagnostic(u, i, out);
    put_int(&out->severity, g_enum_value);
    put_int(&out->subject_kind, g_enum_value);
    return r;
}
}  // namespace

TEST_CASE("enum fields outside their range are judged as ints: refused by name, or a plain warning") {
    mbx_stub::Assembly a = small_assembly();
    mbx_stub::Diagnostic d;
    d.code = "odd";
    d.message = "a diagnostic with nonsense enums";
    a.diagnostics = {d};
    mbx_stub::Host host(a);
    g_wrapped = host.table();
    mbx_host table = *host.table();
    table.get_frame = odd_frame;
    table.get_primitive = odd_primitive;
    table.get_diagnostic = odd_diagnostic;
    struct Case {
        EnumField field;
        const char* says;
    };
    for (int value : {-4, 99, 1 << 30}) {
        g_enum_value = value;
        for (const Case& c : {Case{EnumField::FrameReference, "has unknown reference "},
                              Case{EnumField::PrimitiveType, "has unknown type "},
                              Case{EnumField::AxisReference, "has unknown axis reference "}}) {
            g_field = c.field;
            CAPTURE(value);
            CAPTURE(c.says);
            Progress progress;
            Findings f;
            try {
                read_host(&table, {}, progress, f);
                FAIL("accepted an enum value outside its range");
            } catch (const Error& e) {
                CHECK(e.status() == MBX_ERROR_INVALID_INPUT);
                CHECK(std::string(e.what()).find(c.says + std::to_string(value)) != std::string::npos);
            }
        }
        g_field = EnumField::Diagnostic;
        Progress progress;
        Findings f;
        read_host(&table, {}, progress, f);
        REQUIRE(f.size() == 1);
        CHECK(f[0].severity == MBX_SEVERITY_WARNING);
        CHECK(f[0].subject.kind == MBX_SUBJECT_NONE);
        CHECK(f[0].message == "a diagnostic with nonsense enums");
    }
}

TEST_CASE("progress callback can cancel") {
    mbx_stub::Host host(small_assembly());
    Findings f;
    int calls = 0;
    auto cancel = [](void* user, const char*, double) -> int { return ++*static_cast<int*>(user) >= 2; };
    Progress progress(cancel, &calls);
    try {
        read_host(host.table(), {}, progress, f);
        FAIL("not cancelled");
    } catch (const Error& e) {
        CHECK(e.status() == MBX_ERROR_CANCELLED);
    }
}

TEST_CASE("host diagnostics (ABI 3) become findings that keep the host's code, file and line") {
    mbx_stub::Assembly a = small_assembly();
    mbx_stub::Diagnostic d;
    d.severity = MBX_SEVERITY_WARNING;
    d.code = "mesh_file_missing";
    d.subject_kind = MBX_SUBJECT_BODY;
    d.subject_id = "arm";
    d.file = "model.xml";
    d.line = 42;
    d.message = "geometry file 'arm.stl' of body 'arm' not found";
    a.diagnostics.push_back(d);
    mbx_stub::Host host(a);
    Findings f;
    read(host, f);
    REQUIRE(f.size() == 1);
    CHECK(f[0].code == MBX_FINDING_HOST_DIAGNOSTIC);
    CHECK(std::string(f[0].code_name()) == "mesh_file_missing");
    CHECK(f[0].subject.id == "arm");
    CHECK(f[0].file == "model.xml");
    CHECK(f[0].line == 42);

    // A version-2 table ends before the diagnostic callbacks: they are not read.
    mbx_host v2 = *host.table();
    v2.struct_size = uint32_t(offsetof(mbx_host, diagnostic_count));
    v2.abi_version = 2;
    Findings none;
    Progress progress;
    read_host(&v2, {}, progress, none);
    CHECK(none.empty());
}
}  // namespace MBX_UNITY_ID
