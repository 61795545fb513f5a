// `mbx simulate`: translate an input, build its simulation model through the
// C API (with the description file's drives), fix the coordinates the user
// sets, run to the stop time and write trajectory.csv and simulation.json.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "commands.h"
#include "mechanism_input.h"
#include "progress_line.h"

namespace mbx_cli {
namespace {

const std::string kSimulateUsage = std::string(
    "usage: mbx simulate <input> -o <dir> [--set <joint>.q=<v>]... [--set <joint>.qd=<v>]...\n"
    "                    [--gravity gx,gy,gz] [--stop-time <s>] [--integrator accurate|rk4|euler]\n"
    "                    [--step <s>] [--tolerance <rel>] [--output-step <s>] [--progress]\n"
    "                    [--shapes <file.wrl>] [--mesh-dir <dir>]... [--library <file.xml>]... [--drives <file.xml>]\n"
    "\n"
    "  -o <dir>    output directory: trajectory.csv and simulation.json (created if missing)\n") +
    kInputOptionsHelp +
    "  --set <joint>.q=<v>   initial position of a joint (rad or m), by its report name or CAD constraint id;\n"
    "  --set <joint>.qd=<v>  initial rate (repeatable). Coordinates not set are solved so that the loops\n"
    "              close (positions from the CAD pose), or are zero\n"
    "  --gravity gx,gy,gz  m/s^2 (default 0,0,-9.81)\n"
    "  --stop-time <s>  end of the run (default 1)\n"
    "  --integrator accurate|rk4|euler  variable step with error control and stick/slip friction, or fixed\n"
    "              step RK4 (default) or semi-implicit Euler\n"
    "  --step <s>  fixed step, or the accurate mode's largest step (default 0.001)\n"
    "  --tolerance <rel>  accurate mode relative tolerance (default 1e-8)\n"
    "  --output-step <s>  trajectory sample interval, a whole number of steps (default 0.01)\n"
    "\n"
    "The description file (--drives) may give collision shapes and contact materials (<collision>, <contact>;\n"
    "docs/contact.md): the run then has contact, in every integrator.\n"
    "\n"
    "trajectory.csv holds time, then per joint <joint>.q and <joint>.qd (a spherical joint .qw .qx .qy .qz and\n"
    ".wx .wy .wz; a floating body .x .y .z .qw .qx .qy .qz .vx .vy .vz .wx .wy .wz), then per drive .target,\n"
    ".u, .current and .effort. A run that fails writes nothing and says why (exit code 1).\n";

bool parse_positive(const std::string& option, const std::string& text, double& out) {
    if (parse_number(text, out) && out > 0) return true;
    std::fprintf(stderr, "mbx simulate: %s needs a positive number (got '%s')\n", option.c_str(), text.c_str());
    return false;
}

struct Setting {
    std::string joint;
    bool velocity = false;
    double value = 0;
};

}  // namespace

int run_simulate(const std::vector<std::string>& args) {
    InputOptions in;
    std::string out_dir;
    std::vector<Setting> settings;
    mbx_sim_options options{};
    options.struct_size = sizeof options;
    mbx_sim_run_options run{};
    run.struct_size = sizeof run;
    run.stop_time = 1.0;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const int input_option = parse_input_option(args, i, in, "simulate");
        if (input_option == 2) return 2;
        if (input_option == 1) continue;
        const bool has_value = i + 1 < args.size();
        if (a == "-h" || a == "--help") {
            std::fputs(kSimulateUsage.c_str(), stdout);
            return 0;
        } else if ((a == "-o" || a == "--output") && has_value) {
            out_dir = args[++i];
        } else if (a == "--set" && has_value) {
            const std::string text = args[++i];
            const size_t eq = text.find('=');
            const size_t dot = eq == std::string::npos ? std::string::npos : text.rfind('.', eq);
            Setting s;
            const std::string what = dot == std::string::npos ? "" : text.substr(dot + 1, eq - dot - 1);
            if (dot == std::string::npos || dot == 0 || (what != "q" && what != "qd") ||
                !parse_number(text.substr(eq + 1), s.value)) {
                std::fprintf(stderr, "mbx simulate: --set takes <joint>.q=<value> or <joint>.qd=<value> (got '%s')\n",
                             text.c_str());
                return 2;
            }
            s.joint = text.substr(0, dot);
            s.velocity = what == "qd";
            settings.push_back(s);
        } else if (a == "--gravity" && has_value) {
            const std::string text = args[++i];
            // Exactly three numbers: a fourth value or trailing junk is a typo, not something to drop.
            double g[3];
            size_t start = 0;
            int n = 0;
            bool ok = true;
            for (;;) {
                const size_t comma = text.find(',', start);
                const std::string piece = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
                ok = ok && n < 3 && parse_number(piece, g[n]);
                ++n;
                if (comma == std::string::npos) break;
                start = comma + 1;
            }
            if (!ok || n != 3) {
                std::fprintf(stderr, "mbx simulate: --gravity takes three numbers gx,gy,gz (got '%s')\n", text.c_str());
                return 2;
            }
            options.flags |= MBX_SIM_SET_GRAVITY;
            for (int k = 0; k < 3; ++k) options.gravity[k] = g[k];
        } else if (a == "--stop-time" && has_value) {
            if (!parse_positive(a, args[++i], run.stop_time)) return 2;
        } else if (a == "--integrator" && has_value) {
            const std::string k = args[++i];
            if (k == "rk4") options.integrator = MBX_INTEGRATOR_RK4;
            else if (k == "euler") options.integrator = MBX_INTEGRATOR_EULER;
            else if (k == "accurate") options.integrator = MBX_INTEGRATOR_ACCURATE;
            else {
                std::fprintf(stderr, "mbx simulate: --integrator takes accurate, rk4 or euler (got '%s')\n", k.c_str());
                return 2;
            }
        } else if (a == "--step" && has_value) {
            if (!parse_positive(a, args[++i], options.step)) return 2;
        } else if (a == "--tolerance" && has_value) {
            if (!parse_positive(a, args[++i], options.tolerance) || !(options.tolerance < 1)) {
                if (options.tolerance >= 1) std::fprintf(stderr, "mbx simulate: --tolerance must be below 1\n");
                return 2;
            }
        } else if (a == "--output-step" && has_value) {
            if (!parse_positive(a, args[++i], run.output_step)) return 2;
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "mbx simulate: unknown or incomplete option '%s'\n\n%s", a.c_str(), kSimulateUsage.c_str());
            return 2;
        } else if (in.input.empty()) {
            in.input = a;
        } else {
            std::fprintf(stderr, "mbx simulate: more than one input ('%s', '%s')\n", in.input.c_str(), a.c_str());
            return 2;
        }
    }
    if (in.input.empty() || out_dir.empty()) {
        std::fputs(kSimulateUsage.c_str(), stderr);
        return 2;
    }
    // The mesh check is a translation report matter; a simulation needs no meshes.
    in.mass_check = false;
    const bool progress = in.progress;
    in.progress = false;
    OpenedInput c;
    if (const int code = open_input(in, "simulate", c)) return code;

    struct Sim {
        mbx_sim_model* model = nullptr;
        mbx_sim_data* data = nullptr;
        ~Sim() {
            mbx_sim_data_destroy(data);
            mbx_sim_model_destroy(model);
        }
    } sim;
    mbx_status status = mbx_sim_model_create(c.ctx, c.mech, &options, &sim.model);
    if (status != MBX_OK) return fail(c, status, "building the simulation model");
    status = mbx_sim_data_create(c.ctx, sim.model, &sim.data);
    if (status != MBX_OK) return fail(c, status, "creating the simulation data");

    std::vector<mbx_sim_fixed_value> fixed;
    for (const Setting& s : settings) {
        uint32_t joint = 0;
        if (mbx_sim_model_find_joint(sim.model, s.joint.c_str(), &joint) != MBX_OK) {
            std::fprintf(stderr, "mbx simulate: no joint '%s' (or several): use a joint name of report.json or a CAD constraint id\n",
                         s.joint.c_str());
            return 1;
        }
        mbx_sim_joint_info info{};
        info.struct_size = sizeof info;
        mbx_sim_model_get_joint(sim.model, joint, &info);
        if (info.nv != 1) {
            std::fprintf(stderr, "mbx simulate: joint '%s' is %s: --set takes revolute and prismatic joints\n",
                         s.joint.c_str(), info.kind == MBX_SIM_JOINT_SPHERICAL ? "spherical" : "not a single coordinate");
            return 1;
        }
        fixed.push_back({joint, 0, s.velocity ? 1 : 0, s.value});
    }
    status = mbx_sim_initialize(c.ctx, sim.data, fixed.data(), uint32_t(fixed.size()));
    if (status != MBX_OK) return fail(c, status, "initialisation");

    ProgressLine line(run.stop_time, "s simulated");
    if (progress) mbx_context_set_progress(c.ctx, ProgressLine::callback, &line);
    status = mbx_sim_run(c.ctx, sim.data, &run, out_dir.c_str());
    if (progress) mbx_context_set_progress(c.ctx, nullptr, nullptr);
    if (status != MBX_OK) return fail(c, status, "simulation");

    mbx_sim_stats stats{};
    stats.struct_size = sizeof stats;
    mbx_sim_get_stats(sim.data, &stats);
    mbx_sim_model_info info{};
    info.struct_size = sizeof info;
    mbx_sim_model_get_info(sim.model, &info);
    std::printf("%s: %u coordinates, %u loop closures, %u drives; %llu steps, %llu evaluations, largest loop gap %.3g m\n",
                in.input.c_str(), info.nv, info.loop_closure_count, info.drive_count, (unsigned long long)stats.steps,
                (unsigned long long)stats.evaluations, stats.max_closure_residual);
    if (const uint32_t shapes = mbx_mechanism_collision_shape_count(c.mech))
        std::printf("contact: %u collision shapes\n", shapes);
    std::printf("trajectory: %s/trajectory.csv\nsummary: %s/simulation.json\n", out_dir.c_str(), out_dir.c_str());
    return 0;
}

}  // namespace mbx_cli
