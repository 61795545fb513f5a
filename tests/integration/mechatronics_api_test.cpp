// The mechatronics C API (ABI 5) through the plugin table, driven the way a
// CAD host drives it: an mbx_mechatronics object filled from the bundled
// object library and from drives the host adds by CAD constraint id, resolved
// against translated mechanisms (stub assemblies and sample files through the
// file adapter), then queried and exported. Every quantity is checked against
// a hand computation from the library's raw numbers, and every refusal
// against its status code and what the error names.
#include <doctest/doctest.h>

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "support/c_enum_call.h"
#include "support/plugin_fixture.h"
#include "support/temp_dir.h"
#include "../common/file_text.h"

namespace MBX_UNITY_ID {

using namespace itest;
namespace fs = std::filesystem;

namespace {

using mbx_test::read_file;

// ---------------------------------------------------------------------------
// The bundled library's raw numbers (samples/library/mbx_object_library.xml).
// ---------------------------------------------------------------------------
const char* const kKrs = "628F99AAAA7444D5A2A36A6FA1175594";         // Kondo KRS-784ICS
const char* const kRe40 = "5B0E3C1F7A2D4E8C9F61A4B2C3D5E7F9";        // RE40-class 150 W 48 V
const char* const kPlanetary = "0D9A61C4E2B84F7C8A3D5E6F7081920A";   // Planetary 4.3:1
const char* const kStrainWave = "A7C3E5F1092B4D6E8F0A1B2C3D4E5F60";  // Strain-wave 100:1
const char* const kBallScrew = "3E8F2A1B6C4D4E9F8A7B0C1D2E3F4A5B";   // Ball screw 16x5
const char* const kAbsent = "0123456789ABCDEF0123456789ABCDEF";      // in no library

constexpr double kPi = 3.14159265358979323846;

struct Motor {
    double J, Va, Ia, rpm, Ra, ratio;
    double k() const { return (Va - Ra * Ia) / (rpm * 2 * kPi / 60); }
};
constexpr Motor kKrsData{1.2e-7, 8, 1.2, 8200, 0.78, 251};
constexpr Motor kRe40Data{1.42e-5, 48, 3.17, 6940, 1.16, 1};

// Planetary 4.3:1: ratio 4.3, efficiency 0.9, J 9.1e-7; strain-wave: 100, 0.7, 3.3e-6 (written out below).
constexpr double kScrewLead = 5e-3, kScrewEfficiency = 0.9, kScrewJ = 4.0e-5;

std::string library_path() { return std::string(MBX_SAMPLES_DIR) + "/library/mbx_object_library.xml"; }
std::string arm_drives_path() { return std::string(MBX_SAMPLES_DIR) + "/mechatronics/five_axis_arm_drives.xml"; }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// 1-based line of the first occurrence of `marker` in `text` (0 if absent).
int line_of(const std::string& text, const std::string& marker) {
    const size_t at = text.find(marker);
    if (at == std::string::npos) return 0;
    return 1 + int(std::count(text.begin(), text.begin() + ptrdiff_t(at), '\n'));
}

// Relative agreement (the hand computations here are a few roundings from the SDK's).
bool close(double actual, double expected, double rel = 1e-12) {
    if (expected == 0) return std::fabs(actual) <= 1e-15;
    return std::fabs(actual - expected) <= rel * std::fabs(expected);
}
// Each side evaluated once (a side may be a query that REQUIREs).
#define CHECK_CLOSE(actual, expected)                                                      \
    do {                                                                                   \
        const double actual_value = (actual), expected_value = (expected);                 \
        CHECK_MESSAGE(close(actual_value, expected_value),                                 \
                      #actual " = " << actual_value << ", expected " << expected_value);   \
    } while (false)

// ---------------------------------------------------------------------------
// Handles and queries, through the plugin table only.
// ---------------------------------------------------------------------------
struct MechatronicsDeleter {
    void operator()(mbx_mechatronics* m) const { api().mechatronics_destroy(m); }
};
using MechatronicsPtr = std::unique_ptr<mbx_mechatronics, MechatronicsDeleter>;

MechatronicsPtr make_mechatronics(mbx_context* ctx) {
    mbx_mechatronics* m = nullptr;
    REQUIRE(api().mechatronics_create(ctx, &m) == MBX_OK);
    REQUIRE(m != nullptr);
    return MechatronicsPtr(m);
}

// The bundled library, from its file or from its text in memory.
enum class Loader { file, text };

MechatronicsPtr with_library(mbx_context* ctx, Loader how = Loader::file) {
    MechatronicsPtr m = make_mechatronics(ctx);
    if (how == Loader::file) {
        REQUIRE_MESSAGE(api().mechatronics_load_library(ctx, m.get(), library_path().c_str()) == MBX_OK,
                        api().context_last_error(ctx));
    } else {
        const std::string text = read_file(library_path());
        REQUIRE_FALSE(text.empty());
        REQUIRE_MESSAGE(api().mechatronics_load_library_text(ctx, m.get(), text.c_str(), "bundled.xml") == MBX_OK,
                        api().context_last_error(ctx));
    }
    CHECK(api().mechatronics_drive_count(m.get()) == 0);
    return m;
}

// The failure left on the context, strings copied.
struct LastError {
    mbx_status status = MBX_OK;
    std::string message;
    mbx_subject_kind kind = MBX_SUBJECT_NONE;
    std::string subject_id, subject_name, file;
    int line = 0;
};

LastError last_error(const mbx_context* ctx) {
    LastError e;
    e.message = api().context_last_error(ctx);
    mbx_error_info info{};
    info.struct_size = sizeof info;
    REQUIRE(api().context_last_error_info(ctx, &info) == MBX_OK);
    e.status = info.status;
    e.kind = info.subject_kind;
    e.subject_id = info.subject_id ? info.subject_id : "";
    e.subject_name = info.subject_name ? info.subject_name : "";
    e.file = info.file ? info.file : "";
    e.line = info.line;
    CHECK(e.message == (info.message ? info.message : ""));
    return e;
}

mbx_controller_desc controller(double kp, double kd = 0, double output_limit = 0) {
    mbx_controller_desc c{};
    c.struct_size = sizeof c;
    c.kp = kp;
    c.kd = kd;
    c.output_limit = output_limit;
    c.velocity_estimate = MBX_VELOCITY_MEASURED;
    return c;
}

// A voltage-mode drive on the only prismatic/revolute primitive of `constraint`.
mbx_drive_desc drive(const char* name, const char* constraint, const char* motor, const char* transmission,
                     const mbx_controller_desc* c) {
    mbx_drive_desc d{};
    d.struct_size = sizeof d;
    d.name = name;
    d.constraint_id = constraint;
    d.primitive_index = -1;
    d.motor_id = motor;
    d.transmission_id = transmission;
    d.amplifier_mode = MBX_AMPLIFIER_VOLTAGE;
    d.controller = c;
    return d;
}

void add(mbx_context* ctx, mbx_mechatronics* m, const mbx_drive_desc& d) {
    REQUIRE_MESSAGE(api().mechatronics_add_drive(ctx, m, &d) == MBX_OK, api().context_last_error(ctx));
}

mbx_drive_info drive_info(const mbx_mechanism* mech, uint32_t index) {
    mbx_drive_info d{};
    d.struct_size = sizeof d;
    REQUIRE(api().mechanism_get_drive(mech, index, &d) == MBX_OK);
    return d;
}

// Drive infos by name, with the strings copied.
struct DriveView {
    mbx_drive_info info{};
    uint32_t index = 0;
    std::string name, motor, transmission;
};

std::map<std::string, DriveView> drives_by_name(const mbx_mechanism* mech) {
    std::map<std::string, DriveView> out;
    for (uint32_t i = 0; i < api().mechanism_drive_count(mech); ++i) {
        DriveView v;
        v.info = drive_info(mech, i);
        v.index = i;
        v.name = v.info.name;
        v.motor = v.info.motor_name;
        v.transmission = v.info.transmission_name;
        CHECK_MESSAGE(out.emplace(v.name, v).second, "two drives named " << v.name);
    }
    return out;
}

std::array<double, 3> target(const mbx_mechanism* mech, uint32_t index, double t) {
    std::array<double, 3> q{{-1, -1, -1}};
    REQUIRE(api().mechanism_drive_target(mech, index, t, q.data()) == MBX_OK);
    return q;
}

// The CAD constraint a joint came from.
std::string constraint_of(const mbx_mechanism* mech, uint32_t joint_index) {
    return joint(mech, joint_index).constraint_id;
}

// Constraint id of every revolute tree joint, in joint order.
std::vector<std::string> revolute_constraints(const mbx_mechanism* mech) {
    std::vector<std::string> out;
    for (uint32_t i = 0; i < joint_total(mech); ++i) {
        const mbx_joint_info j = joint(mech, i);
        if (j.type == MBX_PRIMITIVE_REVOLUTE && !j.is_cut) out.push_back(j.constraint_id);
    }
    return out;
}

// ---------------------------------------------------------------------------
// A PMXML sample through the file adapter: the adapter outlives the mechanism.
// ---------------------------------------------------------------------------
struct FileRun {
    std::unique_ptr<mbx_files::FileAdapter> adapter;
    ContextPtr context;
    MechanismPtr mechanism;
    mbx_mechanism* get() const { return mechanism.get(); }
    mbx_context* ctx() const { return context.get(); }
};

FileRun translate_sample(const std::string& relative_xml, const std::string& relative_wrl = "") {
    FileRun r;
    mbx_files::FileAdapterOptions options;
    if (!relative_wrl.empty()) options.shapes_path = std::string(MBX_SAMPLES_DIR) + "/" + relative_wrl;
    r.adapter = mbx_files::FileAdapter::open(std::string(MBX_SAMPLES_DIR) + "/" + relative_xml, options);
    r.context = make_context();
    mbx_mechanism* m = nullptr;
    REQUIRE_MESSAGE(api().translate(r.ctx(), r.adapter->table(), nullptr, &m) == MBX_OK,
                    api().context_last_error(r.ctx()));
    r.mechanism.reset(m);
    return r;
}

// Every regular file below `dir`, relative, sorted.
std::vector<std::string> tree_of(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) out.push_back(fs::relative(e.path(), dir).generic_string());
    std::sort(out.begin(), out.end());
    return out;
}

size_t count_of(const std::string& text, const std::string& part) {
    size_t n = 0;
    for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
    return n;
}

}  // namespace

// ===========================================================================
// 5. The plugin table
// ===========================================================================
TEST_CASE("mechatronics api: the plugin table carries the ABI 5 functions, the exported ones") {
    const mbx_api& a = api();
    REQUIRE(a.abi_version >= 5);
    REQUIRE(a.abi_version_fn() >= 5);
    REQUIRE(a.struct_size >= offsetof(mbx_api, mechanism_drive_target) + sizeof(a.mechanism_drive_target));

    // The same functions a host would get from dlsym() by name.
    void* handle = dlopen(plugin_path(), RTLD_NOW | RTLD_NOLOAD | RTLD_LOCAL);
    REQUIRE_MESSAGE(handle != nullptr, "the plugin is not loaded: " << dlerror());
    auto same = [&](const char* name, auto fn) {
        void* symbol = dlsym(handle, name);
        void* entry = nullptr;
        static_assert(sizeof fn == sizeof entry, "function pointers are data-pointer-sized on this platform");
        std::memcpy(&entry, &fn, sizeof entry);
        CHECK_MESSAGE(symbol != nullptr, name);
        CHECK_MESSAGE(entry == symbol, name << " in the table is not the exported function");
    };
    same("mbx_mechatronics_create", a.mechatronics_create);
    same("mbx_mechatronics_destroy", a.mechatronics_destroy);
    same("mbx_mechatronics_load_library", a.mechatronics_load_library);
    same("mbx_mechatronics_load_library_text", a.mechatronics_load_library_text);
    same("mbx_mechatronics_load_drives", a.mechatronics_load_drives);
    same("mbx_mechatronics_add_drive", a.mechatronics_add_drive);
    same("mbx_mechatronics_set_motion", a.mechatronics_set_motion);
    same("mbx_mechatronics_drive_count", a.mechatronics_drive_count);
    same("mbx_mechanism_set_mechatronics", a.mechanism_set_mechatronics);
    same("mbx_mechanism_drive_count", a.mechanism_drive_count);
    same("mbx_mechanism_get_drive", a.mechanism_get_drive);
    same("mbx_mechanism_drive_target", a.mechanism_drive_target);
    // Earlier entries did not move.
    same("mbx_mechanism_export", a.mechanism_export);
    same("mbx_translate", a.translate);
    dlclose(handle);  // drops only the reference taken here
}

// ===========================================================================
// 1. Host-side assignment: quantities and motion targets
// ===========================================================================
TEST_CASE("mechatronics api: drives a host adds by constraint id resolve to the library's numbers") {
    for (Loader how : {Loader::file, Loader::text}) {
        CAPTURE(how == Loader::file ? "load_library" : "load_library_text");
        const Run r = translate_builtin("six_axis_arm");
        REQUIRE(r.status == MBX_OK);
        mbx_context* ctx = r.context.get();
        const std::vector<std::string> ids = revolute_constraints(r.get());
        REQUIRE(ids.size() == 6);

        MechatronicsPtr mt = with_library(ctx, how);
        // J6: the KRS servo on its own (voltage amplifier, output limit 0 = VaNominal 8 V).
        const mbx_controller_desc pd_wrist = controller(50, 0.2, 0);
        add(ctx, mt.get(), drive(nullptr, ids[5].c_str(), kKrs, nullptr, &pd_wrist));
        // J1: the 150 W motor through the strain-wave gear, 48 V.
        const mbx_controller_desc pd_waist = controller(100, 2, 48);
        add(ctx, mt.get(), drive("waist", ids[0].c_str(), kRe40, kStrainWave, &pd_waist));
        // J4: the KRS (251:1 inside) through the planetary: both ratios multiply.
        const mbx_controller_desc pd_roll = controller(30, 0, 6);
        add(ctx, mt.get(), drive("roll", ids[3].c_str(), kKrs, kPlanetary, &pd_roll));
        // J2: current amplifier (0.5 A per unit, +-10) with a velocity loop.
        mbx_controller_desc pi_vel = controller(20, 0.5, 10);
        pi_vel.kv = 3;
        mbx_drive_desc shoulder = drive("shoulder", ids[1].c_str(), kRe40, kPlanetary, &pi_vel);
        shoulder.amplifier_mode = MBX_AMPLIFIER_CURRENT;
        shoulder.amplifier_gain = 0.5;
        add(ctx, mt.get(), shoulder);
        CHECK(api().mechatronics_drive_count(mt.get()) == 4);

        // Motions (SI): linear on J6, smooth on J1, step on J4; J2 keeps none.
        const mbx_motion_point linear[] = {{0, 0}, {1, 0.5}, {3, -0.5}};
        REQUIRE(api().mechatronics_set_motion(ctx, mt.get(), ids[5].c_str(), -1, linear, 3,
                                              MBX_INTERPOLATION_LINEAR) == MBX_OK);
        const mbx_motion_point smooth[] = {{1, 0.2}, {3, 1.0}, {4, 1.0}};
        REQUIRE(api().mechatronics_set_motion(ctx, mt.get(), ids[0].c_str(), -1, smooth, 3,
                                              MBX_INTERPOLATION_SMOOTH) == MBX_OK);
        const mbx_motion_point step[] = {{0, 0.1}, {2, 0.7}};
        REQUIRE(api().mechatronics_set_motion(ctx, mt.get(), ids[3].c_str(), -1, step, 2, MBX_INTERPOLATION_STEP) ==
                MBX_OK);

        REQUIRE_MESSAGE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK,
                        api().context_last_error(ctx));
        REQUIRE(api().mechanism_drive_count(r.get()) == 4);
        CHECK(std::string(api().context_last_error(ctx)).empty());
        const auto d = drives_by_name(r.get());

        // --- J6, KRS-784ICS alone: the name defaults to the joint's name. ---
        const std::string j6_name = joint(r.get(), find_joint(r.get(), ids[5])).name;
        REQUIRE(d.count(j6_name));
        {
            const mbx_drive_info& w = d.at(j6_name).info;
            const double k = (8 - 0.78 * 1.2) / (8200 * 2 * kPi / 60);
            CHECK(w.joint == find_joint(r.get(), ids[5]));
            CHECK(constraint_of(r.get(), w.joint) == ids[5]);
            CHECK(w.linear == 0);
            CHECK(d.at(j6_name).motor == "KRS-784ICS");
            CHECK(d.at(j6_name).transmission.empty());
            CHECK_CLOSE(w.ratio, 251.0);
            CHECK_CLOSE(w.efficiency, 1.0);
            CHECK_CLOSE(w.rotor_inertia, 1.2e-7);
            CHECK_CLOSE(w.armature, 1.2e-7 * 251.0 * 251.0);
            CHECK_CLOSE(w.torque_constant, k);
            CHECK_CLOSE(w.stall_torque, k * 8 / 0.78);
            CHECK_CLOSE(w.no_load_speed, 8 / k);
            CHECK_CLOSE(w.output_limit, 8.0);  // 0 means VaNominal in voltage mode
            CHECK_CLOSE(w.effort_limit, 251 * k * 8 / 0.78);
            CHECK_CLOSE(w.velocity_limit, 8 / k / 251);
            const double G = 251 * k / 0.78;  // joint torque per volt
            CHECK_CLOSE(w.servo_stiffness, G * 50);
            CHECK_CLOSE(w.servo_damping, G * 0.2);
            CHECK_CLOSE(w.emf_damping, 251.0 * 251.0 * k * k / 0.78);
            CHECK(w.motion_point_count == 3);
            // Sanity of the hand numbers: the docs' 7.6e-3 kg m^2.
            CHECK(std::fabs(w.armature - 7.56e-3) < 1e-4);
        }
        // --- J1, RE40 + strain-wave 100:1: armature J_r (N_m N_t)^2 + J_t N_t^2, effort eta N k I_max. ---
        REQUIRE(d.count("waist"));
        {
            const mbx_drive_info& w = d.at("waist").info;
            const double k = kRe40Data.k();
            const double N = kRe40Data.ratio * 100;
            CHECK(constraint_of(r.get(), w.joint) == ids[0]);
            CHECK(d.at("waist").motor == "RE40-class 150 W 48 V");
            CHECK(d.at("waist").transmission == "Strain-wave 100:1");
            CHECK_CLOSE(w.ratio, 100.0);
            CHECK_CLOSE(w.efficiency, 0.7);
            CHECK_CLOSE(w.armature, 1.42e-5 * N * N + 3.3e-6 * 100.0 * 100.0);
            CHECK_CLOSE(w.torque_constant, (48 - 1.16 * 3.17) / (6940 * 2 * kPi / 60));
            CHECK_CLOSE(w.output_limit, 48.0);
            CHECK_CLOSE(w.effort_limit, 0.7 * 100 * k * (48 / 1.16));
            CHECK_CLOSE(w.velocity_limit, 48 / k / 100);
            CHECK_CLOSE(w.emf_damping, 0.7 * 100.0 * 100.0 * k * k / 1.16);
            CHECK_CLOSE(w.servo_stiffness, 0.7 * 100 * k / 1.16 * 100);
            CHECK_CLOSE(w.servo_damping, 0.7 * 100 * k / 1.16 * 2);
        }
        // --- J4, KRS + planetary: the built-in gear and the gearbox multiply, the gearbox's own J sees N_t only. ---
        REQUIRE(d.count("roll"));
        {
            const mbx_drive_info& w = d.at("roll").info;
            const double k = kKrsData.k();
            const double Nm = 251, Nt = 4.3;
            CHECK(d.at("roll").transmission == "Planetary 4.3:1");
            CHECK_CLOSE(w.ratio, Nm * Nt);
            CHECK_CLOSE(w.efficiency, 0.9);
            CHECK_CLOSE(w.armature, 1.2e-7 * (Nm * Nt) * (Nm * Nt) + 9.1e-7 * Nt * Nt);
            CHECK_CLOSE(w.effort_limit, 0.9 * Nm * Nt * k * (6 / 0.78));
            CHECK_CLOSE(w.velocity_limit, 6 / k / (Nm * Nt));
        }
        // --- J2, current amplifier with a velocity loop: I_max = gain * output_limit, no back-EMF braking. ---
        REQUIRE(d.count("shoulder"));
        {
            const mbx_drive_info& w = d.at("shoulder").info;
            const double k = kRe40Data.k();
            const double G = 0.9 * 4.3 * k * 0.5;  // joint torque per unit of output
            CHECK_CLOSE(w.ratio, 4.3);
            CHECK_CLOSE(w.output_limit, 10.0);
            CHECK_CLOSE(w.effort_limit, 0.9 * 4.3 * k * (0.5 * 10));
            CHECK_CLOSE(w.velocity_limit, 48 / k / 4.3);  // VaNominal in current mode
            CHECK(w.emf_damping == 0.0);
            CHECK_CLOSE(w.servo_stiffness, G * 3 * 20);
            CHECK_CLOSE(w.servo_damping, G * 3 * (0.5 + 1));
            CHECK(w.motion_point_count == 0);
        }

        // --- Motion targets against closed forms. ---
        {  // Linear on J6: before, inside both segments, at a point, after.
            const uint32_t i = d.at(j6_name).index;
            struct P {
                double t, q, v;
            };
            for (P p : {P{-1, 0, 0}, P{0.25, 0.125, 0.5}, P{0.5, 0.25, 0.5}, P{2, 0, -0.5}, P{2.5, -0.25, -0.5},
                        P{3, -0.5, 0}, P{10, -0.5, 0}}) {
                CAPTURE(p.t);
                const auto q = target(r.get(), i, p.t);
                CHECK_CLOSE(q[0], p.q);
                CHECK_CLOSE(q[1], p.v);
                CHECK(q[2] == 0.0);
            }
        }
        {  // Smooth on J1: rest-to-rest quintic 10u^3 - 15u^4 + 6u^5 on [1, 3], then holding 1.0.
            const uint32_t i = d.at("waist").index;
            for (double t : {1.0, 1.3, 1.5, 2.0, 2.71, 3.0, 3.5, 4.0, 9.0}) {
                CAPTURE(t);
                double pos = 0.2, vel = 0, acc = 0;
                if (t >= 3) {
                    pos = 1.0;
                } else if (t > 1) {
                    const double T = 2, h = 0.8, u = (t - 1) / T;
                    pos = 0.2 + h * (10 * std::pow(u, 3) - 15 * std::pow(u, 4) + 6 * std::pow(u, 5));
                    vel = h / T * (30 * u * u - 60 * std::pow(u, 3) + 30 * std::pow(u, 4));
                    acc = h / (T * T) * (60 * u - 180 * u * u + 120 * std::pow(u, 3));
                }
                const auto q = target(r.get(), i, t);
                CHECK_CLOSE(q[0], pos);
                CHECK(std::fabs(q[1] - vel) < 1e-12);
                CHECK(std::fabs(q[2] - acc) < 1e-12);
            }
            // Mid-segment: half-way, the fastest point, 15/8 of the mean speed.
            const auto mid = target(r.get(), i, 2.0);
            CHECK_CLOSE(mid[0], 0.6);
            CHECK_CLOSE(mid[1], 1.875 * 0.8 / 2);
        }
        {  // Step on J4: the earlier value holds until the next point.
            const uint32_t i = d.at("roll").index;
            CHECK_CLOSE(target(r.get(), i, 1.999)[0], 0.1);
            CHECK_CLOSE(target(r.get(), i, 2.0)[0], 0.7);
            CHECK(target(r.get(), i, 1.0)[1] == 0.0);
        }
        {  // No motion: hold 0 (the assembly pose).
            const uint32_t i = d.at("shoulder").index;
            for (double t : {-1.0, 0.0, 5.0}) {
                const auto q = target(r.get(), i, t);
                CHECK(q[0] == 0.0);
                CHECK(q[1] == 0.0);
                CHECK(q[2] == 0.0);
            }
        }
    }
}

TEST_CASE("mechatronics api: one mechatronics object re-applied to a new translation gives the same drives") {
    const Run first = translate_builtin("six_axis_arm");
    const Run second = translate_builtin("six_axis_arm");
    REQUIRE(first.status == MBX_OK);
    REQUIRE(second.status == MBX_OK);
    mbx_context* ctx = first.context.get();
    MechatronicsPtr mt = with_library(ctx);
    const std::vector<std::string> ids = revolute_constraints(first.get());
    const mbx_controller_desc c = controller(40, 1, 8);
    add(ctx, mt.get(), drive("a", ids[2].c_str(), kKrs, kPlanetary, &c));
    add(ctx, mt.get(), drive("b", ids[4].c_str(), kKrs, nullptr, &c));
    REQUIRE(api().mechanism_set_mechatronics(ctx, first.get(), mt.get()) == MBX_OK);
    REQUIRE(api().mechanism_set_mechatronics(second.context.get(), second.get(), mt.get()) == MBX_OK);
    REQUIRE(api().mechanism_drive_count(first.get()) == 2);
    REQUIRE(api().mechanism_drive_count(second.get()) == 2);
    for (uint32_t i = 0; i < 2; ++i) {
        const mbx_drive_info a = drive_info(first.get(), i), b = drive_info(second.get(), i);
        CHECK(std::string(a.name) == b.name);
        CHECK(a.joint == b.joint);
        CHECK(a.armature == b.armature);
        CHECK(a.effort_limit == b.effort_limit);
        CHECK(a.servo_stiffness == b.servo_stiffness);
    }
    // Drives keep the order the host added them in.
    CHECK(std::string(drive_info(first.get(), 0).name) == "a");
    CHECK(std::string(drive_info(first.get(), 1).name) == "b");
}

TEST_CASE("mechatronics api: an older host's smaller mbx_drive_info is filled only as far as it goes") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    MechatronicsPtr mt = with_library(ctx);
    const mbx_controller_desc c = controller(40);
    add(ctx, mt.get(), drive("wrist", revolute_constraints(r.get())[5].c_str(), kKrs, nullptr, &c));
    REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK);

    mbx_drive_info small;
    std::memset(&small, 0xAB, sizeof small);
    small.struct_size = uint32_t(offsetof(mbx_drive_info, armature));  // up to efficiency
    REQUIRE(api().mechanism_get_drive(r.get(), 0, &small) == MBX_OK);
    CHECK(small.struct_size == offsetof(mbx_drive_info, armature));
    CHECK(std::string(small.name) == "wrist");
    CHECK_CLOSE(small.ratio, 251.0);
    CHECK(small.efficiency == 1.0);
    unsigned char untouched[sizeof(double)];
    std::memset(untouched, 0xAB, sizeof untouched);
    CHECK(std::memcmp(&small.armature, untouched, sizeof untouched) == 0);
    CHECK(std::memcmp(&small.motion_point_count, untouched, sizeof small.motion_point_count) == 0);

    mbx_drive_info tiny{};
    tiny.struct_size = 4;  // not even abi-safe: refused
    CHECK(api().mechanism_get_drive(r.get(), 0, &tiny) == MBX_ERROR_INVALID_ARGUMENT);
}

// ===========================================================================
// 2. Overrides
// ===========================================================================
TEST_CASE("mechatronics api: an editable override changes the drive, a fixed or out-of-bounds one is refused") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::vector<std::string> ids = revolute_constraints(r.get());
    const mbx_controller_desc c = controller(50, 0, 8);

    SUBCASE("KRS Ratio = 100 changes ratio, armature and limits") {
        MechatronicsPtr mt = with_library(ctx);
        const mbx_parameter_override o[] = {{"Ratio", 100}};
        mbx_drive_desc d = drive("wrist", ids[5].c_str(), kKrs, nullptr, &c);
        d.overrides = o;
        d.override_count = 1;
        add(ctx, mt.get(), d);
        REQUIRE_MESSAGE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK,
                        api().context_last_error(ctx));
        const mbx_drive_info w = drive_info(r.get(), 0);
        const double k = kKrsData.k();
        CHECK_CLOSE(w.ratio, 100.0);
        CHECK_CLOSE(w.armature, 1.2e-7 * 100.0 * 100.0);
        CHECK_CLOSE(w.effort_limit, 100 * k * 8 / 0.78);
        CHECK_CLOSE(w.velocity_limit, 8 / k / 100);
        // The motor's own constants do not depend on the gear.
        CHECK_CLOSE(w.torque_constant, k);
        CHECK_CLOSE(w.rotor_inertia, 1.2e-7);
    }
    SUBCASE("gearbox efficiency and ratio overrides reach the transmission's figures") {
        MechatronicsPtr mt = with_library(ctx);
        const mbx_parameter_override o[] = {{"efficiency", 0.5}, {"ratio", 50}};
        mbx_drive_desc d = drive("waist", ids[0].c_str(), kRe40, kStrainWave, &c);
        d.overrides = o;
        d.override_count = 2;
        add(ctx, mt.get(), d);
        REQUIRE_MESSAGE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK,
                        api().context_last_error(ctx));
        const mbx_drive_info w = drive_info(r.get(), 0);
        const double k = kRe40Data.k();
        CHECK_CLOSE(w.efficiency, 0.5);
        CHECK_CLOSE(w.ratio, 50.0);
        CHECK_CLOSE(w.armature, 1.42e-5 * 50.0 * 50.0 + 3.3e-6 * 50.0 * 50.0);
        CHECK_CLOSE(w.effort_limit, 0.5 * 50 * k * 8 / 1.16);
    }
    SUBCASE("refused overrides name the drive and the parameter, and attach nothing") {
        // A drive attached before, which a failing set_mechatronics must leave in place.
        MechatronicsPtr good = with_library(ctx);
        add(ctx, good.get(), drive("previous", ids[1].c_str(), kKrs, nullptr, &c));
        REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), good.get()) == MBX_OK);
        REQUIRE(api().mechanism_drive_count(r.get()) == 1);

        struct Case {
            const char* parameter;
            double value;
            const char* transmission;
            const char* says;
        };
        for (Case bad : {Case{"J_Rotor", 2e-7, nullptr, "not editable"}, Case{"Ratio", 0.5, nullptr, "bounds"},
                         Case{"efficiency", 1.5, kStrainWave, "bounds"}, Case{"J", 1e-6, kStrainWave, "not editable"},
                         Case{"Torque", 1, nullptr, "unknown parameter"}}) {
            CAPTURE(bad.parameter);
            MechatronicsPtr mt = with_library(ctx);
            const mbx_parameter_override o[] = {{bad.parameter, bad.value}};
            mbx_drive_desc d = drive("tuned_wrist", ids[5].c_str(), kKrs, bad.transmission, &c);
            d.overrides = o;
            d.override_count = 1;
            add(ctx, mt.get(), d);  // form only: the library is consulted when resolving
            CHECK(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_ERROR_INVALID_INPUT);
            const LastError e = last_error(ctx);
            CHECK(e.status == MBX_ERROR_INVALID_INPUT);
            CHECK_MESSAGE(contains(e.message, "tuned_wrist"), e.message);
            CHECK_MESSAGE(contains(e.message, bad.parameter), e.message);
            CHECK_MESSAGE(contains(e.message, bad.says), e.message);
            CHECK(e.subject_name == "tuned_wrist");
            // Nothing attached; the previous drive is still there, unchanged.
            REQUIRE(api().mechanism_drive_count(r.get()) == 1);
            CHECK(std::string(drive_info(r.get(), 0).name) == "previous");
        }
    }
}

// ===========================================================================
// 3. Errors, case by case
// ===========================================================================
TEST_CASE("mechatronics api: drives that do not fit the mechanism are refused naming the joint or object") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::vector<std::string> ids = revolute_constraints(r.get());
    const mbx_controller_desc c = controller(50, 0, 8);
    const std::string weld = "six_axis_arm/weld_tube";
    REQUIRE(std::find(ids.begin(), ids.end(), weld) == ids.end());

    struct Case {
        const char* what;
        std::string constraint;
        int primitive;
        const char* motor;
        const char* transmission;
        std::vector<std::string> named;  // all must appear in the message
    };
    const std::vector<Case> cases = {
        {"unknown constraint", "six_axis_arm/J9", -1, kKrs, nullptr, {"six_axis_arm/J9", "no constraint"}},
        {"weld", weld, -1, kKrs, nullptr, {weld, "no prismatic or revolute primitive"}},
        {"weld by primitive", weld, 0, kKrs, nullptr, {weld, "primitive 0"}},
        {"primitive past the chain", ids[0], 3, kKrs, nullptr, {ids[0], "primitive 3"}},
        {"unknown motor", ids[0], -1, kAbsent, nullptr, {kAbsent, "not in the object library"}},
        {"gearbox as motor", ids[0], -1, kStrainWave, nullptr, {kStrainWave, "Strain-wave 100:1", "not a dc_motor"}},
        {"unknown transmission", ids[0], -1, kKrs, kAbsent, {kAbsent, "not in the object library"}},
        {"motor as transmission", ids[0], -1, kKrs, kRe40, {"RE40-class 150 W 48 V", "not a gearbox or ball_screw"}},
        {"ball screw on a revolute", ids[0], -1, kRe40, kBallScrew, {"ball screw", "revolute"}},
    };
    for (const Case& k : cases) {
        CAPTURE(k.what);
        MechatronicsPtr mt = with_library(ctx);
        mbx_drive_desc d = drive("culprit", k.constraint.c_str(), k.motor, k.transmission, &c);
        d.primitive_index = k.primitive;
        add(ctx, mt.get(), d);
        CHECK(api().mechatronics_drive_count(mt.get()) == 1);
        CHECK(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_ERROR_INVALID_INPUT);
        const LastError e = last_error(ctx);
        CHECK(e.status == MBX_ERROR_INVALID_INPUT);
        for (const std::string& part : k.named)
            CHECK_MESSAGE(contains(e.message, part), part << " not in: " << e.message);
        CHECK_MESSAGE(contains(e.message, "culprit"), e.message);
        // The structured error names the CAD joint by its constraint id; a
        // drive the host added has no file, and the message says no ":0:".
        CHECK(e.kind == MBX_SUBJECT_CONSTRAINT);
        CHECK(e.subject_id == k.constraint);
        CHECK(e.subject_name == "culprit");
        CHECK(e.file.empty());
        CHECK(e.line == 0);
        CHECK_MESSAGE(contains(e.message, "\nculprit: "), e.message);
        CHECK_FALSE(contains(e.message, ":0:"));
        CHECK(api().mechanism_drive_count(r.get()) == 0);
    }
}

TEST_CASE("mechatronics api: spherical, cut and multi-primitive joints, prismatic joints need a ball screw") {
    // joints_showcase (PMXML through the file adapter): prismatic, spherical,
    // a cylindrical chain (P z then R z) and a spatial loop.
    FileRun r = translate_sample("joints_showcase/joints_showcase.xml");
    mbx_context* ctx = r.ctx();
    std::string prismatic, spherical, cylindrical;
    std::map<std::string, int> primitives_of;
    for (uint32_t i = 0; i < joint_total(r.get()); ++i) ++primitives_of[joint(r.get(), i).constraint_id];
    for (uint32_t i = 0; i < joint_total(r.get()); ++i) {
        const mbx_joint_info j = joint(r.get(), i);
        if (primitives_of[j.constraint_id] > 1) cylindrical = j.constraint_id;
        else if (j.type == MBX_PRIMITIVE_PRISMATIC) prismatic = j.constraint_id;
        else if (j.type == MBX_PRIMITIVE_SPHERICAL && !j.is_cut) spherical = j.constraint_id;
    }
    REQUIRE_FALSE(prismatic.empty());
    REQUIRE_FALSE(spherical.empty());
    REQUIRE_FALSE(cylindrical.empty());
    REQUIRE(joint(r.get(), find_joint(r.get(), cylindrical, 0)).type == MBX_PRIMITIVE_PRISMATIC);
    REQUIRE(joint(r.get(), find_joint(r.get(), cylindrical, 1)).type == MBX_PRIMITIVE_REVOLUTE);
    const mbx_controller_desc c = controller(2000, 40, 0);
    const double k = kRe40Data.k();
    const double screw = 2 * kPi / kScrewLead;  // motor rad per metre

    SUBCASE("refused") {
        struct Case {
            const char* what;
            std::string constraint;
            int primitive;
            const char* motor;
            const char* transmission;
            std::vector<std::string> named;
        };
        const std::vector<Case> cases = {
            {"spherical", spherical, -1, kKrs, nullptr, {spherical, "no prismatic or revolute primitive"}},
            {"spherical by primitive", spherical, 0, kKrs, nullptr, {"is spherical", "only prismatic and revolute"}},
            {"gearbox on a prismatic", prismatic, -1, kRe40, kStrainWave, {"gearbox cannot drive the prismatic"}},
            {"prismatic without a screw", prismatic, -1, kRe40, nullptr, {"needs a ball_screw"}},
            {"chain without a primitive index", cylindrical, -1, kKrs, nullptr, {cylindrical, "primitive index"}},
            {"screw on the chain's revolute", cylindrical, 1, kRe40, kBallScrew,
             {"ball screw cannot drive the revolute"}},
        };
        for (const Case& k2 : cases) {
            CAPTURE(k2.what);
            MechatronicsPtr mt = with_library(ctx);
            mbx_drive_desc d = drive("culprit", k2.constraint.c_str(), k2.motor, k2.transmission, &c);
            d.primitive_index = k2.primitive;
            add(ctx, mt.get(), d);
            CHECK(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_ERROR_INVALID_INPUT);
            const LastError e = last_error(ctx);
            for (const std::string& part : k2.named)
                CHECK_MESSAGE(contains(e.message, part), part << " not in: " << e.message);
            CHECK(e.kind == MBX_SUBJECT_CONSTRAINT);
            CHECK(e.subject_id == k2.constraint);
            CHECK(api().mechanism_drive_count(r.get()) == 0);
        }
    }
    SUBCASE("a ball screw on the prismatic joint: efforts in N, inertia in kg") {
        MechatronicsPtr mt = with_library(ctx);
        add(ctx, mt.get(), drive("slide", prismatic.c_str(), kRe40, kBallScrew, &c));
        // Both primitives of the cylindrical chain, each by its index.
        mbx_drive_desc lift = drive("lift", cylindrical.c_str(), kRe40, kBallScrew, &c);
        lift.primitive_index = 0;
        add(ctx, mt.get(), lift);
        mbx_drive_desc turn = drive("turn", cylindrical.c_str(), kKrs, nullptr, &c);
        turn.primitive_index = 1;
        add(ctx, mt.get(), turn);
        const mbx_motion_point travel[] = {{0, 0}, {2, 0.1}};
        REQUIRE(api().mechatronics_set_motion(ctx, mt.get(), prismatic.c_str(), -1, travel, 2,
                                              MBX_INTERPOLATION_SMOOTH) == MBX_OK);
        REQUIRE_MESSAGE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK,
                        api().context_last_error(ctx));
        const auto d = drives_by_name(r.get());
        REQUIRE(d.size() == 3);
        const mbx_drive_info& s = d.at("slide").info;
        CHECK(s.linear == 1);
        CHECK(constraint_of(r.get(), s.joint) == prismatic);
        CHECK(d.at("slide").transmission == "Ball screw 16x5");
        CHECK_CLOSE(s.ratio, screw);
        CHECK_CLOSE(s.efficiency, kScrewEfficiency);
        CHECK_CLOSE(s.armature, kRe40Data.J * screw * screw + kScrewJ * screw * screw);  // kg
        CHECK(std::fabs(s.armature - (1.42e-5 + 4e-5) * screw * screw) < 1e-9);
        CHECK(s.armature > 60);  // the docs' "63 kg" for the screw alone, plus the rotor
        CHECK_CLOSE(s.effort_limit, kScrewEfficiency * screw * k * (48 / 1.16));  // N
        CHECK_CLOSE(s.velocity_limit, 48 / k / screw);                            // m/s
        CHECK_CLOSE(target(r.get(), d.at("slide").index, 1.0)[0], 0.05);
        CHECK(joint(r.get(), d.at("lift").info.joint).primitive_index == 0);
        CHECK(d.at("lift").info.linear == 1);
        CHECK(joint(r.get(), d.at("turn").info.joint).primitive_index == 1);
        CHECK(d.at("turn").info.linear == 0);
        CHECK_CLOSE(d.at("turn").info.ratio, 251.0);
    }
}

TEST_CASE("mechatronics api: a cut joint cannot be driven, one joint named twice is driven twice") {
    const Run r = translate_builtin("fourbar");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    std::string cut, tree;
    for (uint32_t i = 0; i < joint_total(r.get()); ++i) {
        const mbx_joint_info j = joint(r.get(), i);
        (j.is_cut ? cut : tree) = j.constraint_id;
    }
    REQUIRE_FALSE(cut.empty());
    REQUIRE_FALSE(tree.empty());
    const mbx_controller_desc c = controller(50, 0, 8);

    {
        MechatronicsPtr mt = with_library(ctx);
        add(ctx, mt.get(), drive("closing", cut.c_str(), kKrs, nullptr, &c));
        CHECK(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_ERROR_INVALID_INPUT);
        const LastError e = last_error(ctx);
        CHECK_MESSAGE(contains(e.message, "cut joint"), e.message);
        CHECK(e.subject_id == cut);
    }
    {
        // The same joint through "its only primitive" and "primitive 0": two
        // drives on one joint; the second is the one refused.
        MechatronicsPtr mt = with_library(ctx);
        add(ctx, mt.get(), drive("first", tree.c_str(), kKrs, nullptr, &c));
        mbx_drive_desc again = drive("second", tree.c_str(), kKrs, nullptr, &c);
        again.primitive_index = 0;
        add(ctx, mt.get(), again);
        CHECK(api().mechatronics_drive_count(mt.get()) == 2);
        CHECK(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_ERROR_INVALID_INPUT);
        const LastError e = last_error(ctx);
        CHECK_MESSAGE(contains(e.message, "driven twice"), e.message);
        CHECK_MESSAGE(contains(e.message, "second: "), e.message);
        CHECK(e.kind == MBX_SUBJECT_CONSTRAINT);
        CHECK(e.subject_id == tree);
        CHECK(e.subject_name == "second");
        CHECK(api().mechanism_drive_count(r.get()) == 0);
    }
}

TEST_CASE("mechatronics api: adding a drive on the same joint again replaces it and keeps its motion") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::string j3 = revolute_constraints(r.get())[2];
    MechatronicsPtr mt = with_library(ctx);
    const mbx_controller_desc soft = controller(10, 0, 8), stiff = controller(40, 0, 8);
    add(ctx, mt.get(), drive("before", j3.c_str(), kKrs, nullptr, &soft));
    const mbx_motion_point program[] = {{0, 0}, {1, 0.3}, {2, 0.3}};
    REQUIRE(api().mechatronics_set_motion(ctx, mt.get(), j3.c_str(), -1, program, 3, MBX_INTERPOLATION_LINEAR) ==
            MBX_OK);
    add(ctx, mt.get(), drive("after", j3.c_str(), kKrs, kPlanetary, &stiff));
    CHECK(api().mechatronics_drive_count(mt.get()) == 1);
    REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK);
    REQUIRE(api().mechanism_drive_count(r.get()) == 1);
    const mbx_drive_info d = drive_info(r.get(), 0);
    CHECK(std::string(d.name) == "after");
    CHECK(std::string(d.transmission_name) == "Planetary 4.3:1");
    CHECK_CLOSE(d.servo_stiffness, 0.9 * 251 * 4.3 * kKrsData.k() / 0.78 * 40);
    CHECK(d.motion_point_count == 3);
    CHECK_CLOSE(target(r.get(), 0, 0.5)[0], 0.15);
    CHECK_CLOSE(target(r.get(), 0, 0.5)[1], 0.3);
}

TEST_CASE("mechatronics api: controllers that cannot work are refused, early when the form is wrong") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::vector<std::string> ids = revolute_constraints(r.get());
    const std::string& j2 = ids[1];
    MechatronicsPtr mt = with_library(ctx);
    const mbx_controller_desc fine = controller(50, 0, 8);
    add(ctx, mt.get(), drive("kept", ids[0].c_str(), kKrs, nullptr, &fine));

    SUBCASE("add_drive: malformed values, each an error naming the constraint, the drive not added") {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        struct Case {
            const char* what;
            mbx_controller_desc c;
            int amplifier;
            double gain;
            const char* says;
        };
        auto with = [&](auto change) {
            mbx_controller_desc c = fine;
            change(c);
            return c;
        };
        const int bad_estimate = 5;
        const std::vector<Case> cases = {
            {"NaN gain", with([&](mbx_controller_desc& c) { c.kd = nan; }), MBX_AMPLIFIER_VOLTAGE, 0, "finite"},
            {"infinite kp", with([&](mbx_controller_desc& c) { c.kp = HUGE_VAL; }), MBX_AMPLIFIER_VOLTAGE, 0, "finite"},
            {"negative delay", with([&](mbx_controller_desc& c) { c.delay = -0.001; }), MBX_AMPLIFIER_VOLTAGE, 0,
             "not negative"},
            {"negative kp", with([&](mbx_controller_desc& c) { c.kp = -1; }), MBX_AMPLIFIER_VOLTAGE, 0, "not negative"},
            {"velocity_estimate 5",
             with([&](mbx_controller_desc& c) { std::memcpy(&c.velocity_estimate, &bad_estimate, sizeof(int)); }),
             MBX_AMPLIFIER_VOLTAGE, 0, "velocity_estimate 5"},
            {"struct_size too small",
             with([&](mbx_controller_desc& c) { c.struct_size = offsetof(mbx_controller_desc, delay); }),
             MBX_AMPLIFIER_VOLTAGE, 0, "struct_size"},
            {"amplifier_mode 7", fine, 7, 1, "amplifier_mode 7"},
            {"amplifier_mode -1", fine, -1, 1, "amplifier_mode -1"},
            {"current mode without a gain", fine, MBX_AMPLIFIER_CURRENT, 0, "amplifier_gain"},
            {"current mode with a NaN gain", fine, MBX_AMPLIFIER_CURRENT, nan, "amplifier_gain"},
        };
        for (const Case& k : cases) {
            CAPTURE(k.what);
            mbx_drive_desc d = drive("bad", j2.c_str(), kKrs, nullptr, &k.c);
            std::memcpy(&d.amplifier_mode, &k.amplifier, sizeof(int));  // a C host may store any int
            d.amplifier_gain = k.gain;
            CHECK(api().mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_INPUT);
            const LastError e = last_error(ctx);
            CHECK_MESSAGE(contains(e.message, k.says), e.message);
            CHECK_MESSAGE(contains(e.message, j2), e.message);
            CHECK(e.kind == MBX_SUBJECT_CONSTRAINT);
            CHECK(e.subject_id == j2);
            CHECK(api().mechatronics_drive_count(mt.get()) == 1);
        }
        // Drive-level form errors.
        mbx_drive_desc d = drive("bad", j2.c_str(), kKrs, nullptr, nullptr);
        CHECK(api().mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_INPUT);
        CHECK_MESSAGE(contains(last_error(ctx).message, "controller is required"), last_error(ctx).message);
        d = drive("bad", j2.c_str(), nullptr, nullptr, &fine);
        CHECK(api().mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_INPUT);
        CHECK(contains(last_error(ctx).message, "motor_id is required"));
        d = drive("bad", "", kKrs, nullptr, &fine);
        CHECK(api().mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_INPUT);
        CHECK(contains(last_error(ctx).message, "constraint_id is required"));
        d = drive("bad", j2.c_str(), kKrs, nullptr, &fine);
        d.override_count = 1;  // overrides NULL
        CHECK(api().mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_INPUT);
        CHECK(contains(last_error(ctx).message, "overrides is NULL"));
        const mbx_parameter_override unnamed[] = {{nullptr, 100}};
        d.overrides = unnamed;
        CHECK(api().mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_INPUT);
        CHECK(contains(last_error(ctx).message, "override 0 has no name"));
        const mbx_parameter_override not_finite[] = {{"Ratio", nan}};
        d.overrides = not_finite;
        CHECK(api().mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_INPUT);
        CHECK(contains(last_error(ctx).message, "'Ratio' is not finite"));
        CHECK(api().mechatronics_drive_count(mt.get()) == 1);
        // Still usable: the good drive resolves.
        REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK);
        CHECK(api().mechanism_drive_count(r.get()) == 1);
    }

    SUBCASE("set_mechatronics: well-formed but unusable controllers; their working neighbours pass") {
        struct Case {
            const char* what;
            mbx_controller_desc c;
            int amplifier;
            const char* says;  // nullptr: must resolve
        };
        auto with = [&](auto change) {
            mbx_controller_desc c = fine;
            change(c);
            return c;
        };
        const std::vector<Case> cases = {
            {"kp 0", with([](mbx_controller_desc& c) { c.kp = 0; }), MBX_AMPLIFIER_VOLTAGE, "kp must be positive"},
            {"kvi without kv", with([](mbx_controller_desc& c) { c.kvi = 1; }), MBX_AMPLIFIER_VOLTAGE,
             "kvi needs a velocity loop"},
            {"kvi with kv", with([](mbx_controller_desc& c) { c.kvi = 1, c.kv = 2; }), MBX_AMPLIFIER_VOLTAGE, nullptr},
            {"delay 2.5 samples", with([](mbx_controller_desc& c) { c.sample_period = 0.001, c.delay = 0.0025; }),
             MBX_AMPLIFIER_VOLTAGE, "whole number of sample periods"},
            {"delay 3 samples", with([](mbx_controller_desc& c) { c.sample_period = 0.001, c.delay = 0.003; }),
             MBX_AMPLIFIER_VOLTAGE, nullptr},
            {"a delay in continuous time", with([](mbx_controller_desc& c) { c.delay = 0.0025; }),
             MBX_AMPLIFIER_VOLTAGE, nullptr},
            {"difference without a sample period",
             with([](mbx_controller_desc& c) { c.velocity_estimate = MBX_VELOCITY_DIFFERENCE; }),
             MBX_AMPLIFIER_VOLTAGE, "needs a sample period"},
            {"filtered difference without a sample period",
             with([](mbx_controller_desc& c) { c.velocity_estimate = MBX_VELOCITY_FILTERED_DIFFERENCE; }),
             MBX_AMPLIFIER_VOLTAGE, "needs a sample period"},
            {"filtered difference sampled",
             with([](mbx_controller_desc& c) {
                 c.velocity_estimate = MBX_VELOCITY_FILTERED_DIFFERENCE, c.sample_period = 0.001;
             }),
             MBX_AMPLIFIER_VOLTAGE, nullptr},
            {"current mode without an output limit", with([](mbx_controller_desc& c) { c.output_limit = 0; }),
             MBX_AMPLIFIER_CURRENT, "output limit"},
        };
        for (const Case& k : cases) {
            CAPTURE(k.what);
            MechatronicsPtr one = with_library(ctx);
            mbx_drive_desc d = drive("tested", j2.c_str(), kKrs, nullptr, &k.c);
            d.amplifier_mode = mbx_amplifier_mode(k.amplifier);
            d.amplifier_gain = 0.5;
            add(ctx, one.get(), d);
            const mbx_status s = api().mechanism_set_mechatronics(ctx, r.get(), one.get());
            if (!k.says) {
                CHECK_MESSAGE(s == MBX_OK, api().context_last_error(ctx));
                CHECK(api().mechanism_drive_count(r.get()) == 1);
                continue;
            }
            CHECK(s == MBX_ERROR_INVALID_INPUT);
            const LastError e = last_error(ctx);
            CHECK_MESSAGE(contains(e.message, k.says), e.message);
            CHECK_MESSAGE(contains(e.message, "tested"), e.message);
            CHECK(e.subject_id == j2);
        }
    }
}

TEST_CASE("mechatronics api: motions are checked, and a refused one leaves the previous motion") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::vector<std::string> ids = revolute_constraints(r.get());
    MechatronicsPtr mt = with_library(ctx);
    const mbx_controller_desc c = controller(50, 0, 8);
    add(ctx, mt.get(), drive("moving", ids[0].c_str(), kKrs, nullptr, &c));
    const mbx_motion_point good[] = {{0, 0}, {1, 1}};
    REQUIRE(api().mechatronics_set_motion(ctx, mt.get(), ids[0].c_str(), -1, good, 2, MBX_INTERPOLATION_LINEAR) ==
            MBX_OK);

    // An interpolation outside the enum: an error, not undefined behaviour.
    // A C host may pass any int there; C++ cannot hold 9 in the enum without
    // UB of its own, so the call is made from C (support/c_enum_call.c).
    CHECK(mbx_test_set_motion_with_raw_interpolation(api().mechatronics_set_motion, ctx, mt.get(), ids[0].c_str(), -1,
                                                     good, 2, 9) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK_MESSAGE(contains(last_error(ctx).message, "interpolation 9"), last_error(ctx).message);
    CHECK(last_error(ctx).subject_id == ids[0]);

    const mbx_motion_point backwards[] = {{0, 0}, {1, 1}, {1, 2}};
    CHECK(api().mechatronics_set_motion(ctx, mt.get(), ids[0].c_str(), -1, backwards, 3,
                                        MBX_INTERPOLATION_SMOOTH) == MBX_ERROR_INVALID_INPUT);
    {
        const LastError e = last_error(ctx);
        CHECK_MESSAGE(contains(e.message, "point 3"), e.message);
        CHECK_MESSAGE(contains(e.message, "increase"), e.message);
        CHECK_MESSAGE(contains(e.message, ids[0]), e.message);
        CHECK(e.kind == MBX_SUBJECT_CONSTRAINT);
        CHECK(e.subject_id == ids[0]);
    }
    const mbx_motion_point not_finite[] = {{0, 0}, {1, std::numeric_limits<double>::quiet_NaN()}};
    CHECK(api().mechatronics_set_motion(ctx, mt.get(), ids[0].c_str(), -1, not_finite, 2,
                                        MBX_INTERPOLATION_LINEAR) == MBX_ERROR_INVALID_INPUT);
    CHECK(contains(last_error(ctx).message, "not a finite number"));
    // Without a drive on that joint.
    CHECK(api().mechatronics_set_motion(ctx, mt.get(), ids[1].c_str(), -1, good, 2, MBX_INTERPOLATION_LINEAR) ==
          MBX_ERROR_INVALID_INPUT);
    CHECK(contains(last_error(ctx).message, "add the drive first"));
    CHECK(last_error(ctx).subject_id == ids[1]);
    // By explicit primitive index when the drive was added with -1: another key.
    CHECK(api().mechatronics_set_motion(ctx, mt.get(), ids[0].c_str(), 0, good, 2, MBX_INTERPOLATION_LINEAR) ==
          MBX_ERROR_INVALID_INPUT);

    // The refusals left the linear program in place.
    REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK);
    CHECK(drive_info(r.get(), 0).motion_point_count == 2);
    CHECK_CLOSE(target(r.get(), 0, 0.25)[0], 0.25);
    CHECK_CLOSE(target(r.get(), 0, 0.25)[1], 1.0);

    // count 0 clears the motion: the joint holds 0.
    REQUIRE(api().mechatronics_set_motion(ctx, mt.get(), ids[0].c_str(), -1, nullptr, 0, MBX_INTERPOLATION_LINEAR) ==
            MBX_OK);
    REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK);
    CHECK(drive_info(r.get(), 0).motion_point_count == 0);
    CHECK(target(r.get(), 0, 0.25)[0] == 0.0);
}

TEST_CASE("mechatronics api: NULL arguments and short structs are MBX_ERROR_INVALID_ARGUMENT") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::string j1 = revolute_constraints(r.get())[0];
    const mbx_api& a = api();

    mbx_mechatronics* out = nullptr;
    CHECK(a.mechatronics_create(nullptr, &out) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(out == nullptr);
    CHECK(a.mechatronics_create(ctx, nullptr) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(contains(a.context_last_error(ctx), "out_mechatronics"));

    MechatronicsPtr mt = with_library(ctx);
    const mbx_controller_desc c = controller(50, 0, 8);
    add(ctx, mt.get(), drive("kept", j1.c_str(), kKrs, nullptr, &c));
    const std::string text = read_file(library_path());

    CHECK(a.mechatronics_load_library(nullptr, mt.get(), library_path().c_str()) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_library(ctx, nullptr, library_path().c_str()) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK_FALSE(std::string(a.context_last_error(ctx)).empty());
    CHECK(a.mechatronics_load_library(ctx, mt.get(), nullptr) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_library(ctx, mt.get(), "") == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_library_text(nullptr, mt.get(), text.c_str(), "x") == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_library_text(ctx, nullptr, text.c_str(), "x") == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_library_text(ctx, mt.get(), nullptr, "x") == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_drives(nullptr, mt.get(), arm_drives_path().c_str()) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_drives(ctx, nullptr, arm_drives_path().c_str()) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_drives(ctx, mt.get(), nullptr) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_drives(ctx, mt.get(), "") == MBX_ERROR_INVALID_ARGUMENT);

    mbx_drive_desc d = drive("new", j1.c_str(), kKrs, nullptr, &c);
    CHECK(a.mechatronics_add_drive(nullptr, mt.get(), &d) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_add_drive(ctx, nullptr, &d) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_add_drive(ctx, mt.get(), nullptr) == MBX_ERROR_INVALID_ARGUMENT);
    // A drive struct from before its last field: refused, not read past its end.
    d.struct_size = uint32_t(offsetof(mbx_drive_desc, override_count));
    CHECK(a.mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK_MESSAGE(contains(a.context_last_error(ctx), "struct_size"), a.context_last_error(ctx));
    d.struct_size = 0;
    CHECK(a.mechatronics_add_drive(ctx, mt.get(), &d) == MBX_ERROR_INVALID_ARGUMENT);

    const mbx_motion_point p[] = {{0, 0}, {1, 1}};
    CHECK(a.mechatronics_set_motion(nullptr, mt.get(), j1.c_str(), -1, p, 2, MBX_INTERPOLATION_LINEAR) ==
          MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_set_motion(ctx, nullptr, j1.c_str(), -1, p, 2, MBX_INTERPOLATION_LINEAR) ==
          MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_set_motion(ctx, mt.get(), nullptr, -1, p, 2, MBX_INTERPOLATION_LINEAR) ==
          MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_set_motion(ctx, mt.get(), j1.c_str(), -1, nullptr, 2, MBX_INTERPOLATION_LINEAR) ==
          MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_drive_count(nullptr) == 0);
    CHECK(a.mechatronics_drive_count(mt.get()) == 1);  // nothing above added or dropped a drive

    CHECK(a.mechanism_set_mechatronics(nullptr, r.get(), mt.get()) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechanism_set_mechatronics(ctx, nullptr, mt.get()) == MBX_ERROR_INVALID_ARGUMENT);
    REQUIRE(a.mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK);
    REQUIRE(a.mechanism_drive_count(r.get()) == 1);
    CHECK(a.mechanism_drive_count(nullptr) == 0);

    mbx_drive_info info{};
    info.struct_size = sizeof info;
    CHECK(a.mechanism_get_drive(nullptr, 0, &info) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechanism_get_drive(r.get(), 0, nullptr) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechanism_get_drive(r.get(), 1, &info) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(info.name == nullptr);  // untouched by the refusals

    double q[3] = {7, 7, 7};
    CHECK(a.mechanism_drive_target(nullptr, 0, 0.5, q) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechanism_drive_target(r.get(), 0, 0.5, nullptr) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechanism_drive_target(r.get(), 1, 0.5, q) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechanism_drive_target(r.get(), 0, std::numeric_limits<double>::quiet_NaN(), q) ==
          MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechanism_drive_target(r.get(), 0, HUGE_VAL, q) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK((q[0] == 7 && q[1] == 7 && q[2] == 7));
    a.mechatronics_destroy(nullptr);  // allowed, as free(NULL)
}

TEST_CASE("mechatronics api: a library with problems changes nothing and lists every problem with file:line") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::vector<std::string> ids = revolute_constraints(r.get());
    MechatronicsPtr mt = with_library(ctx);
    const mbx_controller_desc c = controller(50, 0, 8);
    add(ctx, mt.get(), drive("kept", ids[0].c_str(), kKrs, nullptr, &c));

    // One good object and three bad ones, each on a line of its own.
    const std::string text =
        "<?xml version=\"1.0\"?>\n"
        "<object_library version=\"1\">\n"
        "  <object_folder name=\"Test motors\">\n"
        "    <object_class name=\"Test DC machine\" kind=\"dc_motor\" modelica=\"X.DC\">\n"
        "      <parameter name=\"J_Rotor\" unit=\"kg.m2\" lower=\"0\"/>\n"
        "      <parameter name=\"VaNominal\" unit=\"V\"/>\n"
        "      <parameter name=\"IaNominal\" unit=\"A\"/>\n"
        "      <parameter name=\"rpmNominal\" unit=\"rpm\"/>\n"
        "      <parameter name=\"Ra\" unit=\"Ohm\"/>\n"
        "      <object name=\"good\" ID=\"11111111111111111111111111111111\">\n"
        "        <parameter name=\"J_Rotor\" value=\"1e-6\"/> <parameter name=\"VaNominal\" value=\"12\"/>\n"
        "        <parameter name=\"IaNominal\" value=\"1\"/> <parameter name=\"rpmNominal\" value=\"3000\"/>\n"
        "        <parameter name=\"Ra\" value=\"2\"/>\n"
        "      </object>\n"
        "      <object name=\"short id\" ID=\"12345\">\n"
        "        <parameter name=\"J_Rotor\" value=\"1e-6\"/> <parameter name=\"VaNominal\" value=\"12\"/>\n"
        "        <parameter name=\"IaNominal\" value=\"1\"/> <parameter name=\"rpmNominal\" value=\"3000\"/>\n"
        "        <parameter name=\"Ra\" value=\"2\"/>\n"
        "      </object>\n"
        "      <object name=\"typo\" ID=\"22222222222222222222222222222222\">\n"
        "        <parameter name=\"J_Rotor\" value=\"1e-6\"/> <parameter name=\"VaNominal\" value=\"12\"/>\n"
        "        <parameter name=\"IaNominal\" value=\"1\"/> <parameter name=\"rpmNominal\" value=\"3000\"/>\n"
        "        <parameter name=\"Ra\" value=\"2\"/> <parameter name=\"Torque\" value=\"1\"/>\n"
        "      </object>\n"
        "      <object name=\"clone\" ID=\"628f99aaaa7444d5a2a36a6fa1175594\">\n"
        "        <parameter name=\"J_Rotor\" value=\"1e-6\"/> <parameter name=\"VaNominal\" value=\"12\"/>\n"
        "        <parameter name=\"IaNominal\" value=\"1\"/> <parameter name=\"rpmNominal\" value=\"3000\"/>\n"
        "        <parameter name=\"Ra\" value=\"2\"/>\n"
        "      </object>\n"
        "    </object_class>\n"
        "  </object_folder>\n"
        "</object_library>\n";
    const int short_id = line_of(text, "name=\"short id\""), typo = line_of(text, "\"Torque\""),
              clone = line_of(text, "name=\"clone\"");
    REQUIRE((short_id > 0 && typo > short_id && clone > typo));

    TempDir dir("mbx_mechatronics_api");
    const std::string path = dir.file("broken_library.xml");
    { std::ofstream(path, std::ios::binary) << text; }

    auto check_refused = [&](const std::string& file) {
        const LastError e = last_error(ctx);
        CHECK(e.status == MBX_ERROR_INVALID_INPUT);
        CHECK_MESSAGE(contains(e.message, "3 problems"), e.message);
        CHECK_MESSAGE(contains(e.message, file + ":" + std::to_string(short_id) + ": Test DC machine/short id: "),
                      e.message);
        CHECK_MESSAGE(contains(e.message, file + ":" + std::to_string(typo) + ": Test DC machine/typo: "), e.message);
        CHECK_MESSAGE(contains(e.message, "Torque"), e.message);
        CHECK_MESSAGE(contains(e.message, file + ":" + std::to_string(clone) + ": Test DC machine/clone: "), e.message);
        CHECK_MESSAGE(contains(e.message, "duplicate ID 628F99AAAA7444D5A2A36A6FA1175594"), e.message);
        CHECK_MESSAGE(contains(e.message, library_path()), "the duplicate's first use is named: " << e.message);
        // The structured error: the file, and the first problem's line and object.
        CHECK(e.kind == MBX_SUBJECT_FILE);
        CHECK(e.subject_id == file);
        CHECK(e.subject_name == "Test DC machine/short id");
        CHECK(e.file == file);
        CHECK(e.line == short_id);
    };
    CHECK(api().mechatronics_load_library(ctx, mt.get(), path.c_str()) == MBX_ERROR_INVALID_INPUT);
    check_refused(path);
    CHECK(api().mechatronics_load_library_text(ctx, mt.get(), text.c_str(), "memory.xml") == MBX_ERROR_INVALID_INPUT);
    check_refused("memory.xml");
    CHECK(api().mechatronics_load_library(ctx, mt.get(), dir.file("absent.xml").c_str()) == MBX_ERROR_INVALID_INPUT);
    CHECK(contains(last_error(ctx).message, dir.file("absent.xml")));
    CHECK(last_error(ctx).file == dir.file("absent.xml"));
    CHECK(api().mechatronics_load_library_text(ctx, mt.get(), "<object_library", nullptr) == MBX_ERROR_INVALID_INPUT);
    CHECK(contains(last_error(ctx).message, "not well-formed"));

    // Nothing changed: the drive is there, the bundled objects resolve, and
    // the refused file's good object was not kept.
    CHECK(api().mechatronics_drive_count(mt.get()) == 1);
    REQUIRE_MESSAGE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK,
                    api().context_last_error(ctx));
    CHECK(std::string(drive_info(r.get(), 0).motor_name) == "KRS-784ICS");
    add(ctx, mt.get(), drive("from the refused file", ids[1].c_str(), "11111111111111111111111111111111", nullptr, &c));
    CHECK(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_ERROR_INVALID_INPUT);
    CHECK(contains(last_error(ctx).message, "11111111111111111111111111111111' is not in the object library"));
    CHECK(api().mechanism_drive_count(r.get()) == 1);

    // The same file without its bad objects loads, next to the bundled library.
    std::string fixed = text;
    for (const char* name : {"short id", "typo", "clone"}) {
        const size_t from = fixed.find("      <object name=\"" + std::string(name) + "\"");
        const size_t to = fixed.find("</object>\n", from) + 10;
        fixed.erase(from, to - from);
    }
    REQUIRE_MESSAGE(api().mechatronics_load_library_text(ctx, mt.get(), fixed.c_str(), "fixed.xml") == MBX_OK,
                    api().context_last_error(ctx));
    REQUIRE_MESSAGE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK,
                    api().context_last_error(ctx));
    CHECK(api().mechanism_drive_count(r.get()) == 2);
    const mbx_drive_info own = drives_by_name(r.get()).at("from the refused file").info;
    CHECK_CLOSE(own.torque_constant, (12 - 2 * 1) / (3000 * 2 * kPi / 60));
}

TEST_CASE("mechatronics api: a drive file with problems changes nothing and lists every problem with file:line") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::vector<std::string> ids = revolute_constraints(r.get());
    const std::string text =
        "<?xml version=\"1.0\"?>\n"
        "<mechatronics version=\"1\">\n"
        "  <library file=\"" + library_path() + "\"/>\n"
        "  <drive name=\"good\" constraint=\"" + ids[0] + "\" motor=\"" + kKrs + "\">\n"
        "    <controller kp=\"10\"/>\n"
        "  </drive>\n"
        "  <drive name=\"typo\" constraint=\"" + ids[1] + "\" motor=\"" + kKrs + "\">\n"
        "    <controller kp=\"10\" kdd=\"1\"/>\n"
        "  </drive>\n"
        "  <drive name=\"negative\" constraint=\"" + ids[2] + "\" motor=\"" + kKrs + "\">\n"
        "    <controller kp=\"-1\"/>\n"
        "  </drive>\n"
        "  <drive name=\"backwards\" constraint=\"" + ids[3] + "\" motor=\"" + kKrs + "\">\n"
        "    <controller kp=\"10\"/>\n"
        "    <motion><point t=\"1\" q=\"0\"/>\n"
        "      <point t=\"0.5\" q=\"1\"/></motion>\n"
        "  </drive>\n"
        "  <drive name=\"fractional\" constraint=\"" + ids[4] + "\" motor=\"" + kKrs + "\">\n"
        "    <controller kp=\"10\" sample_period=\"0.001\" delay=\"0.0015\"/>\n"
        "  </drive>\n"
        "</mechatronics>\n";
    const int typo = line_of(text, "kdd="), negative = line_of(text, "kp=\"-1\""),
              backwards = line_of(text, "t=\"0.5\""), fractional = line_of(text, "delay=\"0.0015\"");
    TempDir dir("mbx_mechatronics_api");
    const std::string path = dir.file("broken_drives.xml");
    { std::ofstream(path, std::ios::binary) << text; }

    MechatronicsPtr mt = make_mechatronics(ctx);  // no library: the file's own must not stay behind
    CHECK(api().mechatronics_load_drives(ctx, mt.get(), path.c_str()) == MBX_ERROR_INVALID_INPUT);
    const LastError e = last_error(ctx);
    CHECK_MESSAGE(contains(e.message, "4 problems"), e.message);
    for (auto [line, who_, what] : {std::tuple<int, const char*, const char*>{typo, "typo", "kdd"},
                                   {negative, "negative", "kp must not be negative"},
                                   {backwards, "backwards", "increase strictly"},
                                   {fractional, "fractional", "whole number of sample periods"}}) {
        const char* who = who_;  // (CAPTURE cannot capture a structured binding)
        CAPTURE(who);
        CHECK_MESSAGE(contains(e.message, path + ":" + std::to_string(line) + ": " + who + ": "), e.message);
        CHECK_MESSAGE(contains(e.message, what), e.message);
    }
    CHECK_FALSE(contains(e.message, "good"));
    CHECK(e.kind == MBX_SUBJECT_FILE);
    CHECK(e.subject_id == path);
    CHECK(e.subject_name == "typo");
    CHECK(e.file == path);
    CHECK(e.line == typo);

    // Nothing kept: no drive, and not the library either (loading it now
    // would otherwise find every ID twice).
    CHECK(api().mechatronics_drive_count(mt.get()) == 0);
    REQUIRE_MESSAGE(api().mechatronics_load_library(ctx, mt.get(), library_path().c_str()) == MBX_OK,
                    api().context_last_error(ctx));
    // A file that cannot be read is refused the same way.
    CHECK(api().mechatronics_load_drives(ctx, mt.get(), dir.file("absent.xml").c_str()) == MBX_ERROR_INVALID_INPUT);
    CHECK(last_error(ctx).file == dir.file("absent.xml"));
    CHECK(api().mechatronics_drive_count(mt.get()) == 0);
}

TEST_CASE("mechatronics api: a failing set_mechatronics attaches nothing and lists every problem, NULL detaches") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const std::vector<std::string> ids = revolute_constraints(r.get());
    const mbx_controller_desc c = controller(50, 0, 8);

    MechatronicsPtr two = with_library(ctx);
    add(ctx, two.get(), drive("one", ids[0].c_str(), kKrs, nullptr, &c));
    add(ctx, two.get(), drive("two", ids[1].c_str(), kKrs, nullptr, &c));
    REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), two.get()) == MBX_OK);
    REQUIRE(api().mechanism_drive_count(r.get()) == 2);

    MechatronicsPtr mixed = with_library(ctx);
    add(ctx, mixed.get(), drive("fine", ids[2].c_str(), kKrs, nullptr, &c));
    add(ctx, mixed.get(), drive("lost", "six_axis_arm/nowhere", kKrs, nullptr, &c));
    add(ctx, mixed.get(), drive("fine too", ids[3].c_str(), kKrs, nullptr, &c));
    add(ctx, mixed.get(), drive("unknown motor", ids[4].c_str(), kAbsent, nullptr, &c));
    const mbx_controller_desc zero = controller(0);
    add(ctx, mixed.get(), drive("no gain", ids[5].c_str(), kKrs, nullptr, &zero));
    CHECK(api().mechanism_set_mechatronics(ctx, r.get(), mixed.get()) == MBX_ERROR_INVALID_INPUT);
    const LastError e = last_error(ctx);
    CHECK_MESSAGE(contains(e.message, "3 problems"), e.message);
    CHECK(contains(e.message, "\nlost: no constraint with id 'six_axis_arm/nowhere'"));
    CHECK(contains(e.message, "\nunknown motor: motor '" + std::string(kAbsent) + "'"));
    CHECK(contains(e.message, "\nno gain: controller kp must be positive"));
    CHECK_FALSE(contains(e.message, "fine"));
    // The first problem is the structured one.
    CHECK(e.kind == MBX_SUBJECT_CONSTRAINT);
    CHECK(e.subject_id == "six_axis_arm/nowhere");
    CHECK(e.subject_name == "lost");
    // Attached nothing: the two earlier drives stay.
    REQUIRE(api().mechanism_drive_count(r.get()) == 2);
    CHECK(std::string(drive_info(r.get(), 0).name) == "one");
    CHECK(std::string(drive_info(r.get(), 1).name) == "two");

    // A later success replaces them all; NULL detaches.
    MechatronicsPtr one = with_library(ctx);
    add(ctx, one.get(), drive("only", ids[5].c_str(), kKrs, nullptr, &c));
    REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), one.get()) == MBX_OK);
    REQUIRE(api().mechanism_drive_count(r.get()) == 1);
    CHECK(std::string(drive_info(r.get(), 0).name) == "only");
    REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), nullptr) == MBX_OK);
    CHECK(api().mechanism_drive_count(r.get()) == 0);
    mbx_drive_info gone{};
    gone.struct_size = sizeof gone;
    CHECK(api().mechanism_get_drive(r.get(), 0, &gone) == MBX_ERROR_INVALID_ARGUMENT);
    double q[3];
    CHECK(api().mechanism_drive_target(r.get(), 0, 0, q) == MBX_ERROR_INVALID_ARGUMENT);
}

// ===========================================================================
// 6. The mechanism keeps its own copy
// ===========================================================================
TEST_CASE("mechatronics api: drives outlive the mechatronics object and the host's strings") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    {
        MechatronicsPtr mt = with_library(ctx);
        // Every string the host hands over lives only in this scope.
        auto name = std::make_unique<std::string>("temporary wrist drive name, long enough to be on the heap");
        auto constraint = std::make_unique<std::string>(revolute_constraints(r.get())[4]);
        auto motor = std::make_unique<std::string>(kKrs);
        auto gear = std::make_unique<std::string>(kPlanetary);
        auto c = std::make_unique<mbx_controller_desc>(controller(30, 1, 8));
        const mbx_drive_desc d = drive(name->c_str(), constraint->c_str(), motor->c_str(), gear->c_str(), c.get());
        add(ctx, mt.get(), d);
        auto points = std::make_unique<std::vector<mbx_motion_point>>(
            std::vector<mbx_motion_point>{{0, 0}, {2, 0.4}});
        REQUIRE(api().mechatronics_set_motion(ctx, mt.get(), constraint->c_str(), -1, points->data(), 2,
                                              MBX_INTERPOLATION_SMOOTH) == MBX_OK);
        std::memset(&(*name)[0], 'x', name->size());
        std::memset(&(*constraint)[0], 'x', constraint->size());
        name.reset();
        constraint.reset();
        motor.reset();
        gear.reset();
        c.reset();
        points.reset();
        REQUIRE_MESSAGE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK,
                        api().context_last_error(ctx));
    }  // the mechatronics object is destroyed here
    REQUIRE(api().mechanism_drive_count(r.get()) == 1);
    const mbx_drive_info d = drive_info(r.get(), 0);
    CHECK(std::string(d.name) == "temporary wrist drive name, long enough to be on the heap");
    CHECK(std::string(d.motor_name) == "KRS-784ICS");
    CHECK(std::string(d.transmission_name) == "Planetary 4.3:1");
    CHECK(joint(r.get(), d.joint).constraint_id == revolute_constraints(r.get())[4]);
    CHECK_CLOSE(d.ratio, 251 * 4.3);
    CHECK_CLOSE(target(r.get(), 0, 1.0)[0], 0.2);
    CHECK_CLOSE(target(r.get(), 0, 1.0)[1], 1.875 * 0.4 / 2);
    // The strings stay valid across other calls on the mechanism.
    const std::string exported_name = d.name;
    CHECK(summary(r.get()).joint_count == 6);
    CHECK(std::string(d.name) == exported_name);
}

// ===========================================================================
// 4. The drive file path: five-axis arm sample, exports
// ===========================================================================
TEST_CASE("mechatronics api: the five-axis arm's drive file attaches 5 drives and every export carries them") {
    FileRun r = translate_sample("five_axis_arm/five_axis_arm.xml", "five_axis_arm/five_axis_arm_a.wrl");
    mbx_context* ctx = r.ctx();
    MechatronicsPtr mt = make_mechatronics(ctx);
    REQUIRE_MESSAGE(api().mechatronics_load_drives(ctx, mt.get(), arm_drives_path().c_str()) == MBX_OK,
                    api().context_last_error(ctx));
    REQUIRE(api().mechatronics_drive_count(mt.get()) == 5);
    REQUIRE_MESSAGE(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK,
                    api().context_last_error(ctx));
    REQUIRE(api().mechanism_drive_count(r.get()) == 5);

    const auto d = drives_by_name(r.get());
    const std::map<std::string, std::string> constraint_of_drive = {
        {"waist", "40:-:41"}, {"shoulder", "41:-:42"}, {"elbow", "42:-:43"}, {"wrist_pitch", "43:-:44"},
        {"wrist_roll", "44:-:45"}};
    for (const auto& [name_, constraint] : constraint_of_drive) {
        const std::string& name = name_;  // (CAPTURE cannot capture a structured binding)
        CAPTURE(name);
        REQUIRE(d.count(name));
        CHECK(constraint_of(r.get(), d.at(name).info.joint) == constraint);
        CHECK(d.at(name).info.linear == 0);
        CHECK(d.at(name).info.motion_point_count == 5);
    }
    const double deg = kPi / 180;
    {  // waist: RE40 + strain-wave, 48 V.
        const mbx_drive_info& w = d.at("waist").info;
        CHECK_CLOSE(w.ratio, 100.0);
        CHECK_CLOSE(w.armature, 1.42e-5 * 1e4 + 3.3e-6 * 1e4);
        CHECK_CLOSE(w.effort_limit, 0.7 * 100 * kRe40Data.k() * 48 / 1.16);
        const uint32_t i = d.at("waist").index;
        CHECK_CLOSE(target(r.get(), i, 0.5)[0], 0.0);
        CHECK_CLOSE(target(r.get(), i, 1.25)[0], 22.5 * deg);  // half-way through 0.5 .. 2 s, 0 -> 45 deg
        CHECK_CLOSE(target(r.get(), i, 1.25)[1], 1.875 * 45 * deg / 1.5);
        CHECK_CLOSE(target(r.get(), i, 5.0)[0], 45 * deg);
        CHECK(target(r.get(), i, 5.0)[1] == 0.0);
        CHECK_CLOSE(target(r.get(), i, 20.0)[0], 0.0);
    }
    {  // elbow: RE40 + planetary.
        const mbx_drive_info& w = d.at("elbow").info;
        CHECK_CLOSE(w.ratio, 4.3);
        CHECK_CLOSE(w.efficiency, 0.9);
        CHECK_CLOSE(w.servo_damping, 0.9 * 4.3 * kRe40Data.k() / 1.16 * 8);
        CHECK_CLOSE(target(r.get(), d.at("elbow").index, 6.0)[0], -30 * deg);
    }
    {  // wrist: the KRS servo, 8 V.
        const mbx_drive_info& w = d.at("wrist_roll").info;
        CHECK_CLOSE(w.ratio, 251.0);
        CHECK_CLOSE(w.armature, 1.2e-7 * 251.0 * 251.0);
        CHECK_CLOSE(w.effort_limit, 251 * kKrsData.k() * 8 / 0.78);
        CHECK_CLOSE(target(r.get(), d.at("wrist_roll").index, 6.5)[0], 60 * deg);
    }

    // Export: an actuator per drive in MJCF, a transmission per drive in URDF.
    auto export_to = [&](const fs::path& dir) {
        mbx_export_options o{};
        o.struct_size = sizeof o;
        o.formats = MBX_EXPORT_MJCF | MBX_EXPORT_URDF;
        o.model_name = "arm";
        REQUIRE_MESSAGE(api().mechanism_export(ctx, r.get(), &o, dir.string().c_str()) == MBX_OK,
                        api().context_last_error(ctx));
    };
    TempDir a("mbx_mechatronics_api"), b("mbx_mechatronics_api"), passive("mbx_mechatronics_api");
    export_to(a.path);
    const std::string mjcf = read_file(a.path / "mjcf" / "arm.xml");
    const std::string urdf = read_file(a.path / "urdf" / "arm.urdf");
    REQUIRE_FALSE(mjcf.empty());
    REQUIRE_FALSE(urdf.empty());
    const size_t from = mjcf.find("<actuator>"), to = mjcf.find("</actuator>");
    REQUIRE(from != std::string::npos);
    REQUIRE(to != std::string::npos);
    const std::string actuators = mjcf.substr(from, to - from);
    CHECK(count_of(actuators, "<general ") + count_of(actuators, "<motor ") == 5);
    CHECK(count_of(mjcf, "armature=\"") == 5);
    CHECK(count_of(urdf, "<transmission ") == 5);
    CHECK(count_of(urdf, "<mechanicalReduction>100</mechanicalReduction>") == 2);
    CHECK(count_of(urdf, "<mechanicalReduction>251</mechanicalReduction>") == 2);

    // Re-exporting is byte-identical, into a fresh directory and over the old one.
    export_to(b.path);
    export_to(a.path);
    const std::vector<std::string> files = tree_of(a.path);
    REQUIRE(files == tree_of(b.path));
    for (const std::string& f : files) {
        CAPTURE(f);
        CHECK(read_file(a.path / f) == read_file(b.path / f));
    }
    CHECK(read_file(a.path / "mjcf" / "arm.xml") == mjcf);

    // Detached, the same mechanism exports passive.
    REQUIRE(api().mechanism_set_mechatronics(ctx, r.get(), nullptr) == MBX_OK);
    export_to(passive.path);
    CHECK_FALSE(contains(read_file(passive.path / "mjcf" / "arm.xml"), "<actuator"));
    CHECK_FALSE(contains(read_file(passive.path / "urdf" / "arm.urdf"), "<transmission"));
}

TEST_CASE("mechatronics api: drives from a file that do not fit name the file, line and constraint") {
    // The five-axis arm's drives against a different assembly: every constraint is unknown.
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    MechatronicsPtr mt = make_mechatronics(ctx);
    REQUIRE(api().mechatronics_load_drives(ctx, mt.get(), arm_drives_path().c_str()) == MBX_OK);
    CHECK(api().mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_ERROR_INVALID_INPUT);
    const LastError e = last_error(ctx);
    const std::string text = read_file(arm_drives_path());
    CHECK_MESSAGE(contains(e.message, "5 problems"), e.message);
    for (const char* name : {"waist", "shoulder", "elbow", "wrist_pitch", "wrist_roll"}) {
        const int line = line_of(text, "<drive name=\"" + std::string(name) + "\"");
        REQUIRE(line > 0);
        CHECK_MESSAGE(contains(e.message, arm_drives_path() + ":" + std::to_string(line) + ": " + name +
                                              ": no constraint with id"),
                      e.message);
    }
    CHECK(e.kind == MBX_SUBJECT_CONSTRAINT);
    CHECK(e.subject_id == "40:-:41");
    CHECK(e.subject_name == "waist");
    CHECK(e.file == arm_drives_path());
    CHECK(e.line == line_of(text, "<drive name=\"waist\""));
    CHECK(api().mechanism_drive_count(r.get()) == 0);
}
}  // namespace MBX_UNITY_ID

namespace MBX_UNITY_ID {

TEST_CASE("mechatronics api: a description given as text (ABI 11) loads as its file does, its errors name the text and line") {
    const Run r = translate_builtin("six_axis_arm");
    REQUIRE(r.status == MBX_OK);
    mbx_context* ctx = r.context.get();
    const mbx_api& a = api();
    REQUIRE(a.struct_size >= offsetof(mbx_api, mechatronics_load_drives_text) + sizeof(void*));
    const std::string j1 = revolute_constraints(r.get())[0];
    MechatronicsPtr mt = make_mechatronics(ctx);
    const std::string good = "<mechatronics version=\"1\">\n  <joint constraint=\"" + j1 + "\" damping=\"0.5\" coulomb=\"2\"/>\n</mechatronics>\n";
    REQUIRE_MESSAGE(a.mechatronics_load_drives_text(ctx, mt.get(), good.c_str(), "robot.urdf") == MBX_OK,
                    a.context_last_error(ctx));
    REQUIRE_MESSAGE(a.mechanism_set_mechatronics(ctx, r.get(), mt.get()) == MBX_OK, a.context_last_error(ctx));
    // The same text from a file gives the same report section.
    TempDir dir("mbx_drives_text");
    { std::ofstream(dir.file("d.xml")) << good; }
    MechatronicsPtr from_file = make_mechatronics(ctx);
    REQUIRE(a.mechatronics_load_drives(ctx, from_file.get(), dir.file("d.xml").c_str()) == MBX_OK);

    const std::string bad = "<mechatronics version=\"1\">\n  <joint constraint=\"" + j1 + "\" damping=\"-1\"/>\n</mechatronics>\n";
    CHECK(a.mechatronics_load_drives_text(ctx, mt.get(), bad.c_str(), "robot.urdf") == MBX_ERROR_INVALID_INPUT);
    const LastError e = last_error(ctx);
    CHECK(contains(e.message, "robot.urdf"));
    CHECK(e.line == 2);
    CHECK(a.mechatronics_load_drives_text(ctx, mt.get(), "<mechatronics", nullptr) == MBX_ERROR_INVALID_INPUT);
    CHECK(contains(last_error(ctx).message, "<description text>"));
    CHECK(a.mechatronics_load_drives_text(nullptr, mt.get(), good.c_str(), "x") == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_drives_text(ctx, nullptr, good.c_str(), "x") == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.mechatronics_load_drives_text(ctx, mt.get(), nullptr, "x") == MBX_ERROR_INVALID_ARGUMENT);
}

}  // namespace MBX_UNITY_ID
