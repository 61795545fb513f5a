// A C++ host built against the installed SDK with find_package(mbx): the
// header from C++, handles in unique_ptr, and the pendulum's dynamics at a
// large angle against their closed forms (mass matrix, gravity torque,
// acceleration, potential energy), then the four-bar sample's loop.
// Usage: cpp_host <samples dir> <output dir>. Exit 0 when every check holds.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <mbx/mbx.h>
#include <mbx/mbx_files.h>

#include "pendulum_host.h"

namespace {

int failures = 0;

void check(bool ok, const char* what, int line) {
    if (!ok) {
        std::fprintf(stderr, "cpp_host.cpp:%d: check failed: %s\n", line, what);
        ++failures;
    }
}
#define CHECK(cond) check((cond), #cond, __LINE__)

struct ContextDeleter { void operator()(mbx_context* c) const { mbx_context_destroy(c); } };
struct MechanismDeleter { void operator()(mbx_mechanism* m) const { mbx_mechanism_destroy(m); } };
struct ModelDeleter { void operator()(mbx_sim_model* m) const { mbx_sim_model_destroy(m); } };
struct DataDeleter { void operator()(mbx_sim_data* d) const { mbx_sim_data_destroy(d); } };
struct FilesDeleter { void operator()(mbx_file_host* f) const { mbx_files_close(f); } };

template <class T>
T sized() {
    T t{};
    t.struct_size = sizeof t;
    return t;
}

bool ok(mbx_context* ctx, mbx_status s, const char* what) {
    if (s == MBX_OK) return true;
    std::fprintf(stderr, "cpp_host: %s: %s: %s\n", what, mbx_status_name(s), mbx_context_last_error(ctx));
    ++failures;
    return false;
}

void pendulum(mbx_context* ctx, const std::string& out) {
    const mbx_host host = pendulum_host();
    mbx_mechanism* raw = nullptr;
    if (!ok(ctx, mbx_translate(ctx, &host, nullptr, &raw), "translate")) return;
    std::unique_ptr<mbx_mechanism, MechanismDeleter> m(raw);
    mbx_sim_model* model_raw = nullptr;
    auto options = sized<mbx_sim_options>();
    options.integrator = MBX_INTEGRATOR_RK4;
    if (!ok(ctx, mbx_sim_model_create(ctx, m.get(), &options, &model_raw), "model")) return;
    std::unique_ptr<mbx_sim_model, ModelDeleter> model(model_raw);
    mbx_sim_data* data_raw = nullptr;
    if (!ok(ctx, mbx_sim_data_create(ctx, model.get(), &data_raw), "data")) return;
    std::unique_ptr<mbx_sim_data, DataDeleter> data(data_raw);

    const double M = PENDULUM_M, L = PENDULUM_L, g = PENDULUM_G, I = M * L * L + PENDULUM_IC;
    const double q = 0.7, v = 0;
    ok(ctx, mbx_sim_set_state(ctx, data.get(), 0.0, &q, &v), "set_state");
    double mass = 0, effort = 0, qacc = 0;
    const double zero = 0;
    ok(ctx, mbx_sim_mass_matrix(ctx, data.get(), &mass), "mass_matrix");
    ok(ctx, mbx_sim_inverse_dynamics(ctx, data.get(), &zero, &effort), "inverse_dynamics");
    ok(ctx, mbx_sim_forward_dynamics(ctx, data.get(), &qacc), "forward_dynamics");
    auto energy = sized<mbx_sim_energy>();
    ok(ctx, mbx_sim_get_energy(ctx, data.get(), &energy), "energy");
    CHECK(std::fabs(mass - I) < 1e-12);
    CHECK(std::fabs(effort - M * g * L * std::sin(q)) < 1e-9);  // holding torque
    CHECK(std::fabs(qacc + M * g * L * std::sin(q) / I) < 1e-9);
    CHECK(std::fabs(energy.gravity + M * g * L * std::cos(q)) < 1e-9);  // zero at the pivot's height
    CHECK(std::fabs(energy.kinetic) < 1e-15);

    // A run writes its trajectory; a large swing keeps its energy.
    auto run = sized<mbx_sim_run_options>();
    run.stop_time = 0.5;
    const std::string dir = out + "/cpp_host_pendulum";
    ok(ctx, mbx_sim_run(ctx, data.get(), &run, dir.c_str()), "run");
    CHECK(std::filesystem::exists(dir + "/trajectory.csv"));
    auto after = sized<mbx_sim_energy>();
    ok(ctx, mbx_sim_get_energy(ctx, data.get(), &after), "energy");
    CHECK(std::fabs(after.total - energy.total) < 1e-6 * std::fabs(energy.total));
    std::printf("cpp_host: pendulum effort %.9g (closed form %.9g), energy drift %.3g J\n", effort,
                M * g * L * std::sin(q), after.total - energy.total);
}

void fourbar(mbx_context* ctx, const std::string& samples) {
    const std::string xml = samples + "/fourbar_imperial/fourbar.xml";
    auto error = sized<mbx_files_error>();
    mbx_file_host* files_raw = nullptr;
    if (mbx_files_open(xml.c_str(), nullptr, &files_raw, &error) != 0) {
        std::fprintf(stderr, "cpp_host: %s:%d: %s\n", error.file, error.line, error.message);
        ++failures;
        return;
    }
    std::unique_ptr<mbx_file_host, FilesDeleter> files(files_raw);
    mbx_mechanism* raw = nullptr;
    if (!ok(ctx, mbx_translate(ctx, mbx_files_host(files.get()), nullptr, &raw), "translate fourbar")) return;
    std::unique_ptr<mbx_mechanism, MechanismDeleter> m(raw);
    auto s = sized<mbx_mechanism_summary>();
    ok(ctx, mbx_mechanism_get_summary(m.get(), &s), "summary");
    // samples/fourbar_imperial/README.md, "Expected mechanism".
    CHECK(s.rigid_body_count == 3);
    CHECK(s.revolute_count == 4);
    CHECK(s.loop_count == 1);
    CHECK(s.planar_loop_count == 1);
    CHECK(s.dof == 1);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: cpp_host <samples dir> <output dir>\n");
        return 2;
    }
    mbx_context* raw = nullptr;
    if (mbx_context_create(&raw) != MBX_OK) return 1;
    std::unique_ptr<mbx_context, ContextDeleter> ctx(raw);
    pendulum(ctx.get(), argv[2]);
    fourbar(ctx.get(), argv[1]);
    if (failures == 0) std::printf("cpp_host: all checks passed\n");
    return failures != 0;
}
