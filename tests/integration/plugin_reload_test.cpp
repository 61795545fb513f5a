// A CAD host loads the plugin when the user opens the tool and unloads it
// when they close it, many times in one session. Each round here loads
// libmbx, translates the EMPS sample, calibrates it against the rig's
// records (the Ceres-linked stage included), simulates it, frees all of it
// and unloads the library; afterwards the library must be gone from the
// process (not pinned by -z nodelete, a unique symbol or a thread-local
// destructor), and the second round must give the first round's numbers.
// Its own process: the other integration tests keep the plugin loaded.
#include <doctest/doctest.h>

#include <dlfcn.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "apps/stub_host/loader/plugin_loader.h"
#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;

struct Round {
    uint32_t causes = 0;
    double first_value = NAN, final_validation = NAN;
    std::string trajectory;
};

bool plugin_mapped() {
    void* h = dlopen(MBX_PLUGIN_PATH, RTLD_NOW | RTLD_NOLOAD | RTLD_LOCAL);
    if (h) dlclose(h);
    return h != nullptr;
}

std::string text_of(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

Round use_plugin(const fs::path& dir) {
    Round out;
    mbx_stub::Plugin plugin;
    std::string error;
    REQUIRE_MESSAGE(plugin.load(MBX_PLUGIN_PATH, &error), error);
    const mbx_api& a = *plugin.api();
    const std::string samples = MBX_SAMPLES_DIR;
    const std::string drives = samples + "/mechatronics/emps_axis_drives.xml";
    const std::string experiment = samples + "/calibration/emps.xml";
    auto adapter = mbx_files::FileAdapter::open(samples + "/emps_axis/emps_axis.xml", {});
    mbx_context* ctx = nullptr;
    REQUIRE(a.context_create(&ctx) == MBX_OK);
    mbx_mechanism* m = nullptr;
    REQUIRE_MESSAGE(a.translate(ctx, adapter->table(), nullptr, &m) == MBX_OK, a.context_last_error(ctx));
    mbx_mechatronics* mt = nullptr;
    REQUIRE(a.mechatronics_create(ctx, &mt) == MBX_OK);
    REQUIRE_MESSAGE(a.mechatronics_load_drives(ctx, mt, drives.c_str()) == MBX_OK, a.context_last_error(ctx));
    REQUIRE_MESSAGE(a.mechanism_set_mechatronics(ctx, m, mt) == MBX_OK, a.context_last_error(ctx));

    mbx_calibrate_options co{};
    co.struct_size = sizeof co;
    co.experiment = experiment.c_str();
    co.description = drives.c_str();
    const std::string calibration_dir = (dir / "calibration").string();
    co.directory = calibration_dir.c_str();
    mbx_calibration* c = nullptr;
    REQUIRE_MESSAGE(a.calibrate(ctx, m, &co, &c) == MBX_OK, a.context_last_error(ctx));
    mbx_calibration_summary s{};
    s.struct_size = sizeof s;
    REQUIRE(a.calibration_get_summary(c, &s) == MBX_OK);
    out.causes = s.cause_count;
    out.final_validation = s.final_validation_error;
    mbx_calibration_parameter p{};
    p.struct_size = sizeof p;
    REQUIRE(a.calibration_get_parameter(c, 0, 0, &p) == MBX_OK);
    out.first_value = p.value;
    a.calibration_destroy(c);

    mbx_sim_options so{};
    so.struct_size = sizeof so;
    mbx_sim_model* sm = nullptr;
    REQUIRE_MESSAGE(a.sim_model_create(ctx, m, &so, &sm) == MBX_OK, a.context_last_error(ctx));
    mbx_sim_data* sd = nullptr;
    REQUIRE(a.sim_data_create(ctx, sm, &sd) == MBX_OK);
    mbx_sim_run_options ro{};
    ro.struct_size = sizeof ro;
    ro.stop_time = 0.5;
    const std::string sim_dir = (dir / "sim").string();
    REQUIRE_MESSAGE(a.sim_run(ctx, sd, &ro, sim_dir.c_str()) == MBX_OK, a.context_last_error(ctx));
    out.trajectory = text_of(fs::path(sim_dir) / "trajectory.csv");
    a.sim_data_destroy(sd);
    a.sim_model_destroy(sm);

    a.mechanism_destroy(m);
    a.mechatronics_destroy(mt);
    a.context_destroy(ctx);
    adapter.reset();
    plugin.unload();
    return out;
}

}  // namespace

TEST_CASE("plugin reload: loaded, used (calibration included) and unloaded twice, gone after each, the same numbers") {
    REQUIRE_FALSE(plugin_mapped());
    mbx_test::TempDir dir("mbx_plugin_reload");
    const Round first = use_plugin(dir.path / "1");
    CHECK_FALSE(plugin_mapped());
    const Round second = use_plugin(dir.path / "2");
    CHECK_FALSE(plugin_mapped());
    // The EMPS calibration's three causes (docs/calibration.md).
    CHECK(first.causes == 3);
    CHECK(std::isfinite(first.first_value));
    CHECK(first.trajectory.size() > 100);
    // A reload starts from nothing the first round left behind.
    CHECK(second.causes == first.causes);
    CHECK(second.first_value == first.first_value);
    CHECK(second.final_validation == first.final_validation);
    CHECK(second.trajectory == first.trajectory);
}
