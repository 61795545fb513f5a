// `mbx excite`: translate an input with its description file and design the
// motion of a calibration record through the C API (docs/calibration.md,
// "Excitation design"): excitation.csv, experiment.xml, excitation.json and
// excitation.html, and a short summary of the predicted standard errors.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "commands.h"
#include "mechanism_input.h"
#include "progress_line.h"

namespace mbx_cli {
namespace {

const std::string kExciteUsage = std::string(
    "usage: mbx excite <input> -o <dir> [--calibration <calibration.json>] [--cause <name>]... [--joint <name>]...\n"
    "                  [--period <s>] [--harmonics <n>] [--periods <n>] [--margin <share>]\n"
    "                  [--acceleration-limit <rad/s^2>] [--limit <joint>=<lower>:<upper>:<speed>:<acceleration>:<effort>]...\n"
    "                  [--sample-rate <Hz>] [--cutoff <Hz>] [--evaluations <n>] [--seed <n>] [--progress]\n"
    "                  [--shapes <file.wrl>] [--mesh-dir <dir>]... [--library <file.xml>]... [--drives <file.xml>]\n"
    "\n"
    "  -o <dir>    output directory (created): excitation.csv (the references at the sample rate),\n"
    "              experiment.xml (the record to make along them), excitation.json and excitation.html\n"
    "  --calibration <file>  a calibration.json of mbx calibrate: design for the causes it named and the\n"
    "              groups its warnings could not tell apart (give its description.xml with --drives)\n"
    "  --cause <name>  a cause to make identifiable: a catalogue name, or \"cause on subject\" as\n"
    "              calibration.json writes it (\"armature on joint 'elbow'\"); repeatable (default: viscous\n"
    "              and Coulomb friction, armature and effort offset on every joint, every moving body's mass)\n"
    "  --joint <name>  a joint to move (CAD id or name; repeatable; default: the driven joints, else the\n"
    "              joints with a rated speed or effort, else every joint of a model without loops)\n"
    "  --period <s>, --harmonics <n>, --periods <n>  the Fourier series (default 10 s, 6, 2)\n"
    "  --margin <share>  of every limit (of the position range) left free for tracking (default 0.1)\n"
    "  --acceleration-limit <v>  for every joint without one (default: none)\n"
    "  --limit <joint>=<lower>:<upper>:<speed>:<acceleration>:<effort>  SI; an empty field keeps the model's,\n"
    "              'inf' removes it (repeatable)\n"
    "  --sample-rate <Hz>, --cutoff <Hz>  the records' rate (default 1000) and filter (default rate/40)\n"
    "  --evaluations <n>, --seed <n>  the search's length (default 2400) and random seed\n") +
    kInputOptionsHelp;

struct LimitText {
    std::string joint;
    double values[5];
};

// "<joint>=a:b:c:d:e", an empty field NaN (keep the model's).
bool parse_limit(const std::string& text, LimitText& out) {
    const size_t eq = text.rfind('=');
    if (eq == std::string::npos || eq == 0) return false;
    out.joint = text.substr(0, eq);
    std::string rest = text.substr(eq + 1);
    for (int k = 0; k < 5; ++k) {
        const size_t colon = rest.find(':');
        if ((colon == std::string::npos) != (k == 4)) return false;
        const std::string field = rest.substr(0, colon);
        if (field.empty()) out.values[k] = std::numeric_limits<double>::quiet_NaN();
        else if (field == "inf") out.values[k] = k == 0 ? -INFINITY : INFINITY;
        else if (!parse_number(field, out.values[k])) return false;
        rest = colon == std::string::npos ? "" : rest.substr(colon + 1);
    }
    return true;
}

bool parse_count(const std::string& text, uint32_t& out) {
    double v = 0;
    if (!parse_number(text, v) || v < 1 || v > 1e9 || v != std::floor(v)) return false;
    out = uint32_t(v);
    return true;
}

}  // namespace

int run_excite(const std::vector<std::string>& args) {
    InputOptions in;
    std::string out_dir, calibration;
    std::vector<std::string> causes, joints;
    std::vector<LimitText> limit_texts;
    mbx_excite_options o{};
    o.struct_size = sizeof o;
    auto usage_error = [&](const std::string& what) {
        std::fprintf(stderr, "mbx excite: %s\n\n%s", what.c_str(), kExciteUsage.c_str());
        return 2;
    };
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const int input_option = parse_input_option(args, i, in, "excite");
        if (input_option == 2) return 2;
        if (input_option == 1) continue;
        const bool has_value = i + 1 < args.size();
        double number = 0;
        if (a == "-h" || a == "--help") {
            std::fputs(kExciteUsage.c_str(), stdout);
            return 0;
        } else if ((a == "-o" || a == "--output") && has_value) {
            out_dir = args[++i];
        } else if (a == "--calibration" && has_value) {
            calibration = args[++i];
        } else if (a == "--cause" && has_value) {
            causes.push_back(args[++i]);
        } else if (a == "--joint" && has_value) {
            joints.push_back(args[++i]);
        } else if (a == "--limit" && has_value) {
            LimitText l;
            if (!parse_limit(args[++i], l)) return usage_error("--limit '" + args[i] + "' is not <joint>=<lower>:<upper>:<speed>:<acceleration>:<effort>");
            limit_texts.push_back(l);
        } else if ((a == "--period" || a == "--margin" || a == "--acceleration-limit" || a == "--sample-rate" ||
                    a == "--cutoff") && has_value) {
            if (!parse_number(args[++i], number)) return usage_error(a + " '" + args[i] + "' is not a number");
            if (a == "--period") o.period = number;
            if (a == "--margin") o.margin = number, o.flags |= MBX_EXCITE_SET_MARGIN;
            if (a == "--acceleration-limit") o.acceleration_limit = number;
            if (a == "--sample-rate") o.sample_rate = number;
            if (a == "--cutoff") o.cutoff = number;
        } else if ((a == "--harmonics" || a == "--periods" || a == "--evaluations" || a == "--seed") && has_value) {
            uint32_t n = 0;
            if (!parse_count(args[++i], n)) return usage_error(a + " '" + args[i] + "' is not a whole number from 1");
            (a == "--harmonics" ? o.harmonics : a == "--periods" ? o.periods : a == "--evaluations" ? o.evaluations : o.seed) = n;
        } else if (!a.empty() && a[0] == '-') {
            return usage_error("unknown or incomplete option '" + a + "'");
        } else if (in.input.empty()) {
            in.input = a;
        } else {
            std::fprintf(stderr, "mbx excite: more than one input ('%s', '%s')\n", in.input.c_str(), a.c_str());
            return 2;
        }
    }
    if (in.input.empty() || out_dir.empty()) {
        std::fputs(kExciteUsage.c_str(), stderr);
        return 2;
    }
    in.mass_check = false;  // a report matter; the design needs no meshes
    const bool progress = in.progress;
    in.progress = false;
    OpenedInput c;
    if (const int code = open_input(in, "excite", c)) return code;

    std::vector<const char*> cause_ptrs, joint_ptrs;
    for (const std::string& s : causes) cause_ptrs.push_back(s.c_str());
    for (const std::string& s : joints) joint_ptrs.push_back(s.c_str());
    std::vector<mbx_joint_limits> limits;
    for (const LimitText& l : limit_texts) {
        mbx_joint_limits j{};
        j.struct_size = sizeof j;
        j.joint = l.joint.c_str();
        j.lower = l.values[0], j.upper = l.values[1], j.velocity = l.values[2], j.acceleration = l.values[3],
        j.effort = l.values[4];
        limits.push_back(j);
    }
    o.causes = cause_ptrs.data(), o.cause_count = uint32_t(cause_ptrs.size());
    o.joints = joint_ptrs.data(), o.joint_count = uint32_t(joint_ptrs.size());
    o.limits = limits.data(), o.limit_count = uint32_t(limits.size());
    o.calibration = calibration.empty() ? nullptr : calibration.c_str();
    o.directory = out_dir.c_str();
    ProgressLine line;
    if (progress) mbx_context_set_progress(c.ctx, ProgressLine::callback, &line);
    struct Handle {
        mbx_excitation* h = nullptr;
        ~Handle() { mbx_excitation_destroy(h); }
    } e;
    const mbx_status status = mbx_excite(c.ctx, c.mech, &o, &e.h);
    if (progress) mbx_context_set_progress(c.ctx, nullptr, nullptr);
    if (status != MBX_OK) return fail(c, status, "excitation design");

    mbx_excitation_summary s{};
    s.struct_size = sizeof s;
    mbx_excitation_get_summary(e.h, &s);
    std::printf("%s: %u joints, %g s x %u periods, %u evaluations (%.1f s)\n", in.input.c_str(), s.joint_count, s.period,
                s.periods, s.evaluations, s.wall_time);
    for (uint32_t i = 0; i < s.joint_count; ++i) {
        mbx_excitation_joint j{};
        j.struct_size = sizeof j;
        mbx_excitation_get_joint(e.h, i, &j);
        std::printf("  %s: %.4g .. %.4g, speed %.3g, acceleration %.3g, effort %.3g (limits from %s)\n", j.name, j.lowest,
                    j.highest, j.peak_velocity, j.peak_acceleration, j.peak_effort, j.limit_source);
    }
    std::printf("predicted standard errors (design / random multi-sine within the same limits%s):\n",
                calibration.empty() ? "" : " / the records calibration.json gave");
    for (uint32_t k = 0; k < s.parameter_count; ++k) {
        mbx_excitation_parameter p{};
        p.struct_size = sizeof p;
        mbx_excitation_get_parameter(e.h, k, &p);
        std::printf("  %s: %.3g / %.3g", p.name, p.std_error, p.random_multisine_std_error);
        if (std::isfinite(p.measured_std_error)) std::printf(" / %.3g", p.measured_std_error);
        std::printf("\n");
    }
    for (uint32_t k = 0; k < s.dropped_count; ++k)
        std::printf("left out: %s (the efforts show it not at all, or only as the others)\n", mbx_excitation_get_dropped(e.h, k));
    std::printf("references: %s/excitation.csv\nexperiment: %s/experiment.xml\nreport: %s/excitation.html\n",
                out_dir.c_str(), out_dir.c_str(), out_dir.c_str());
    return 0;
}

}  // namespace mbx_cli
