// The calibration C API (ABI 8) through the plugin table, as a CAD host
// calls it: the EMPS sample translated by the file adapter, its drive file
// attached, calibrated against the rig's measured records
// (../shared/data/measured/emps), and the written description.xml fed back
// in: the model it describes must replay with the calibrated errors.
#include <doctest/doctest.h>

#include <dlfcn.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "support/plugin_fixture.h"
#include "support/temp_dir.h"
#include "../common/file_text.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace itest;
namespace fs = std::filesystem;

namespace {

struct MechatronicsDeleter {
    void operator()(mbx_mechatronics* m) const { api().mechatronics_destroy(m); }
};
struct CalibrationDeleter {
    void operator()(mbx_calibration* c) const { api().calibration_destroy(c); }
};
using CalibrationPtr = std::unique_ptr<mbx_calibration, CalibrationDeleter>;

// The EMPS axis with the drives of `description` attached; the adapter and
// the mechatronics object outlive the mechanism.
struct Emps {
    std::unique_ptr<mbx_files::FileAdapter> adapter;
    ContextPtr context;
    std::unique_ptr<mbx_mechatronics, MechatronicsDeleter> mechatronics;
    MechanismPtr mechanism;
    mbx_context* ctx() const { return context.get(); }
};

std::unique_ptr<Emps> open_emps(const std::string& description) {
    auto e = std::make_unique<Emps>();
    const mbx_api& a = api();
    e->adapter = mbx_files::FileAdapter::open(std::string(MBX_SAMPLES_DIR) + "/emps_axis/emps_axis.xml", {});
    e->context = make_context();
    mbx_mechanism* m = nullptr;
    REQUIRE(a.translate(e->ctx(), e->adapter->table(), nullptr, &m) == MBX_OK);
    e->mechanism.reset(m);
    mbx_mechatronics* mt = nullptr;
    REQUIRE(a.mechatronics_create(e->ctx(), &mt) == MBX_OK);
    e->mechatronics.reset(mt);
    REQUIRE_MESSAGE(a.mechatronics_load_drives(e->ctx(), mt, description.c_str()) == MBX_OK,
                    a.context_last_error(e->ctx()));
    REQUIRE_MESSAGE(a.mechanism_set_mechatronics(e->ctx(), m, mt) == MBX_OK, a.context_last_error(e->ctx()));
    return e;
}

const std::string kDrives = std::string(MBX_SAMPLES_DIR) + "/mechatronics/emps_axis_drives.xml";
const std::string kExperiment = std::string(MBX_SAMPLES_DIR) + "/calibration/emps.xml";

mbx_calibrate_options options_for(const char* experiment, const char* description, const char* directory) {
    mbx_calibrate_options o{};
    o.struct_size = sizeof o;
    o.experiment = experiment, o.description = description, o.directory = directory;
    return o;
}

mbx_calibration_summary summary_of(const mbx_calibration* c) {
    mbx_calibration_summary s{};
    s.struct_size = sizeof s;
    REQUIRE(api().calibration_get_summary(c, &s) == MBX_OK);
    return s;
}

}  // namespace

TEST_CASE("calibration api: the plugin table carries the ABI 8 functions, the exported ones") {
    const mbx_api& a = api();
    REQUIRE(a.abi_version >= 8);
    REQUIRE(a.struct_size >= offsetof(mbx_api, calibration_get_warning) + sizeof(a.calibration_get_warning));
    void* handle = dlopen(plugin_path(), RTLD_NOW | RTLD_NOLOAD | RTLD_LOCAL);
    REQUIRE(handle != nullptr);
    auto same = [&](const char* name, auto fn) {
        void* symbol = dlsym(handle, name);
        void* entry = nullptr;
        std::memcpy(&entry, &fn, sizeof entry);
        CHECK_MESSAGE(symbol != nullptr, name);
        CHECK_MESSAGE(entry == symbol, name);
    };
    same("mbx_calibrate", a.calibrate);
    same("mbx_calibration_destroy", a.calibration_destroy);
    same("mbx_calibration_get_summary", a.calibration_get_summary);
    same("mbx_calibration_get_cause", a.calibration_get_cause);
    same("mbx_calibration_get_parameter", a.calibration_get_parameter);
    same("mbx_calibration_get_warning", a.calibration_get_warning);
    same("mbx_mechatronics_set_joint_dynamics", a.mechatronics_set_joint_dynamics);
    dlclose(handle);
}

TEST_CASE("calibration api: EMPS calibrated, written, and the written description replays as calibrated") {
    const mbx_api& a = api();
    mbx_test::TempDir dir("mbx_calibration_api");
    const std::string out = (dir.path / "out").string();
    CalibrationPtr first;
    {
        auto e = open_emps(kDrives);
        const mbx_calibrate_options o = options_for(kExperiment.c_str(), kDrives.c_str(), out.c_str());
        mbx_calibration* c = nullptr;
        REQUIRE_MESSAGE(a.calibrate(e->ctx(), e->mechanism.get(), &o, &c) == MBX_OK, a.context_last_error(e->ctx()));
        first.reset(c);
    }
    // The handle outlives the mechanism and context it came from.
    const mbx_calibration_summary s = summary_of(first.get());
    CHECK(s.cause_count == 3);
    CHECK(s.baseline_simulated_fit_error > 65);
    CHECK(s.final_simulated_fit_error <= 7);
    CHECK(s.final_simulated_validation_error <= 10);
    CHECK(s.final_validation_error < s.baseline_validation_error);
    double previous = s.baseline_simulated_validation_error;
    for (uint32_t i = 0; i < s.cause_count; ++i) {
        mbx_calibration_cause cause{};
        cause.struct_size = sizeof cause;
        REQUIRE(a.calibration_get_cause(first.get(), i, &cause) == MBX_OK);
        CHECK(std::string(cause.subject_id) == "40:-:41");
        CHECK(cause.subject_kind == MBX_SUBJECT_CONSTRAINT);
        CHECK(cause.written == 1);
        CHECK(std::strlen(cause.evidence) > 10);
        CHECK(cause.simulated_validation_error < previous);
        previous = cause.simulated_validation_error;
        REQUIRE(cause.parameter_count >= 1);
        mbx_calibration_parameter p{};
        p.struct_size = sizeof p;
        REQUIRE(a.calibration_get_parameter(first.get(), i, 0, &p) == MBX_OK);
        CHECK(std::isfinite(p.value));
        CHECK(p.std_error >= 0);
        CHECK(a.calibration_get_parameter(first.get(), i, cause.parameter_count, &p) == MBX_ERROR_INVALID_ARGUMENT);
    }
    mbx_calibration_cause none{};
    none.struct_size = sizeof none;
    CHECK(a.calibration_get_cause(first.get(), s.cause_count, &none) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.calibration_get_warning(first.get(), s.warning_count) == nullptr);
    for (const char* f : {"calibration.json", "calibration.html", "description.xml"}) CHECK(fs::exists(fs::path(out) / f));

    // The written description, fed back: its model is the calibrated one.
    auto again = open_emps((fs::path(out) / "description.xml").string());
    const mbx_calibrate_options o = options_for(kExperiment.c_str(), nullptr, nullptr);
    mbx_calibration* c = nullptr;
    REQUIRE_MESSAGE(a.calibrate(again->ctx(), again->mechanism.get(), &o, &c) == MBX_OK, a.context_last_error(again->ctx()));
    CalibrationPtr second(c);
    const mbx_calibration_summary s2 = summary_of(second.get());
    MESSAGE("calibrated " << s.final_simulated_fit_error << " / " << s.final_simulated_validation_error
                          << " %; fed back " << s2.baseline_simulated_fit_error << " / " << s2.baseline_simulated_validation_error << " %");
    CHECK(s2.baseline_simulated_fit_error == mbx_test::relative(s.final_simulated_fit_error, 1e-9));
    CHECK(s2.baseline_simulated_validation_error == mbx_test::relative(s.final_simulated_validation_error, 1e-9));
}

TEST_CASE("calibration api: bad arguments, bad files and cancellation write nothing") {
    const mbx_api& a = api();
    mbx_test::TempDir dir("mbx_calibration_api_bad");
    auto e = open_emps(kDrives);
    mbx_calibration* c = nullptr;
    CHECK(a.calibrate(nullptr, e->mechanism.get(), nullptr, &c) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(a.calibrate(e->ctx(), e->mechanism.get(), nullptr, &c) == MBX_ERROR_INVALID_ARGUMENT);
    mbx_calibrate_options o = options_for(nullptr, nullptr, nullptr);
    CHECK(a.calibrate(e->ctx(), e->mechanism.get(), &o, &c) == MBX_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(a.context_last_error(e->ctx())).find("experiment") != std::string::npos);
    CHECK(c == nullptr);

    // An experiment naming a column the records lack: the file and line of the column.
    const std::string bad = (dir.path / "bad.xml").string();
    std::string text = mbx_test::read_file(kExperiment);
    text.replace(text.find("force_N"), 7, "forse_N");
    // The records' paths are relative to the experiment file.
    const std::string records = std::string(MBX_SAMPLES_DIR) + "/../../shared/data/measured/emps/";
    for (size_t at = text.find("../../../shared/data/measured/emps/"); at != std::string::npos;
         at = text.find("../../../shared/data/measured/emps/"))
        text.replace(at, 35, records);
    std::ofstream(bad) << text;
    const std::string out = (dir.path / "out").string();
    o = options_for(bad.c_str(), nullptr, out.c_str());
    CHECK(a.calibrate(e->ctx(), e->mechanism.get(), &o, &c) == MBX_ERROR_INVALID_INPUT);
    const std::string message = a.context_last_error(e->ctx());
    CHECK(message.find("forse_N") != std::string::npos);
    CHECK(message.find("bad.xml:") != std::string::npos);
    CHECK(!fs::exists(out));

    // Cancelled from the progress callback: nothing written.
    int calls = 0;
    auto cancel = [](void* user, const char*, double) {
        return ++*static_cast<int*>(user) >= 2 ? 1 : 0;
    };
    a.context_set_progress(e->ctx(), cancel, &calls);
    o = options_for(kExperiment.c_str(), kDrives.c_str(), out.c_str());
    CHECK(a.calibrate(e->ctx(), e->mechanism.get(), &o, &c) == MBX_ERROR_CANCELLED);
    a.context_set_progress(e->ctx(), nullptr, nullptr);
    CHECK(calls == 2);
    CHECK(c == nullptr);
    CHECK(!fs::exists(fs::path(out) / "calibration.json"));
}

TEST_CASE("calibration api: a description's <body mass_scale> corrects the attached mechanism, every time from CAD") {
    const mbx_api& a = api();
    mbx_test::TempDir dir("mbx_body_mass_api");
    auto e = open_emps(kDrives);
    // The carriage: the one dynamic body with mass.
    uint32_t carriage = UINT32_MAX;
    mbx_rigid_body_info info{};
    info.struct_size = sizeof info;
    for (uint32_t b = 0; a.mechanism_get_rigid_body(e->mechanism.get(), b, &info) == MBX_OK; ++b)
        if (info.kind == MBX_RIGID_BODY_DYNAMIC && info.mass > 0) carriage = b;
    REQUIRE(carriage != UINT32_MAX);
    const mbx_rigid_body_info cad = rigid_body(e->mechanism.get(), carriage);
    // A description that corrects the carriage's mass, keyed by its part id.
    const std::string path = (dir.path / "d.xml").string();
    std::ofstream(path) << "<mechatronics version=\"1\"><body id=\"" << cad.id << "\" mass_scale=\"1.5\"/></mechatronics>";
    mbx_mechatronics* mt = nullptr;
    REQUIRE(a.mechatronics_create(e->ctx(), &mt) == MBX_OK);
    std::unique_ptr<mbx_mechatronics, MechatronicsDeleter> owned(mt);
    REQUIRE_MESSAGE(a.mechatronics_load_drives(e->ctx(), mt, path.c_str()) == MBX_OK, a.context_last_error(e->ctx()));
    for (int twice = 0; twice < 2; ++twice) {  // attaching again does not compound
        REQUIRE(a.mechanism_set_mechatronics(e->ctx(), e->mechanism.get(), mt) == MBX_OK);
        const mbx_rigid_body_info now = rigid_body(e->mechanism.get(), carriage);
        CHECK(now.mass == mbx_test::relative(1.5 * cad.mass, 1e-6));
        CHECK(now.inertia[0] == mbx_test::relative(1.5 * cad.inertia[0], 1e-6));
        CHECK(now.com[0] == cad.com[0]);
    }
    // Detached: the CAD mass again.
    REQUIRE(a.mechanism_set_mechatronics(e->ctx(), e->mechanism.get(), nullptr) == MBX_OK);
    CHECK(rigid_body(e->mechanism.get(), carriage).mass == cad.mass);
    // An unknown body: refused with the file and line, nothing changed.
    std::ofstream(path) << "<mechatronics version=\"1\">\n<body id=\"no_such_part\" mass_scale=\"2\"/>\n</mechatronics>";
    mbx_mechatronics* bad = nullptr;
    REQUIRE(a.mechatronics_create(e->ctx(), &bad) == MBX_OK);
    std::unique_ptr<mbx_mechatronics, MechatronicsDeleter> owned_bad(bad);
    REQUIRE(a.mechatronics_load_drives(e->ctx(), bad, path.c_str()) == MBX_OK);
    CHECK(a.mechanism_set_mechatronics(e->ctx(), e->mechanism.get(), bad) == MBX_ERROR_INVALID_INPUT);
    const std::string message = a.context_last_error(e->ctx());
    CHECK(message.find("d.xml:2") != std::string::npos);
    CHECK(message.find("no_such_part") != std::string::npos);
    CHECK(rigid_body(e->mechanism.get(), carriage).mass == cad.mass);
}
}  // namespace MBX_UNITY_ID
