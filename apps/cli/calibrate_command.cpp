// `mbx calibrate`: translate an input with its description file, run the
// calibration loop of docs/calibration.md through the C API against an
// experiment's measured records, write calibration.json, calibration.html
// and the extended description.xml, and print a short summary.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.h"
#include "mechanism_input.h"
#include "progress_line.h"

namespace mbx_cli {
namespace {

const std::string kCalibrateUsage = std::string(
    "usage: mbx calibrate <input> --experiment <file.xml> -o <dir> [--progress]\n"
    "                     [--shapes <file.wrl>] [--mesh-dir <dir>]... [--library <file.xml>]... [--drives <file.xml>]\n"
    "\n"
    "  --experiment <file.xml>  the measured records, which column is which quantity, how the model is\n"
    "              driven along them and which signals are compared (docs/calibration.md)\n"
    "  -o <dir>    output directory (created): calibration.json, calibration.html and description.xml, the\n"
    "              --drives file extended with the identified joint dynamics (feed it back with --drives)\n"
    "  --write-urdf <file.urdf>  (a URDF input) also write the input URDF with the calibrated joint damping,\n"
    "              friction and link inertials in it, every other byte kept (docs/urdf.md)\n") +
    kInputOptionsHelp;

}  // namespace

int run_calibrate(const std::vector<std::string>& args) {
    InputOptions in;
    std::string out_dir, experiment, urdf_out;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const int input_option = parse_input_option(args, i, in, "calibrate");
        if (input_option == 2) return 2;
        if (input_option == 1) continue;
        const bool has_value = i + 1 < args.size();
        if (a == "-h" || a == "--help") {
            std::fputs(kCalibrateUsage.c_str(), stdout);
            return 0;
        } else if ((a == "-o" || a == "--output") && has_value) {
            out_dir = args[++i];
        } else if (a == "--experiment" && has_value) {
            experiment = args[++i];
        } else if (a == "--write-urdf" && has_value) {
            urdf_out = args[++i];
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "mbx calibrate: unknown or incomplete option '%s'\n\n%s", a.c_str(), kCalibrateUsage.c_str());
            return 2;
        } else if (in.input.empty()) {
            in.input = a;
        } else {
            std::fprintf(stderr, "mbx calibrate: more than one input ('%s', '%s')\n", in.input.c_str(), a.c_str());
            return 2;
        }
    }
    if (in.input.empty() || out_dir.empty() || experiment.empty()) {
        std::fputs(kCalibrateUsage.c_str(), stderr);
        return 2;
    }
    if (!urdf_out.empty()) {
        const mbx_files::InputFormat* format = mbx_files::input_format_of(in.input);
        if (!format || std::string(format->name) != "urdf") {
            std::fprintf(stderr, "mbx calibrate: --write-urdf needs a URDF input; '%s' is %s\n", in.input.c_str(),
                         format ? format->name : "no file of a known format");
            return 2;
        }
    }
    in.mass_check = false;  // a report matter; calibration needs no meshes
    const bool progress = in.progress;
    in.progress = false;
    OpenedInput c;
    if (const int code = open_input(in, "calibrate", c)) return code;

    mbx_calibrate_options options{};
    options.struct_size = sizeof options;
    options.experiment = experiment.c_str();
    options.description = in.drives_path.empty() ? nullptr : in.drives_path.c_str();
    options.directory = out_dir.c_str();
    ProgressLine line;
    if (progress) mbx_context_set_progress(c.ctx, ProgressLine::callback, &line);
    struct Handle {
        mbx_calibration* h = nullptr;
        ~Handle() { mbx_calibration_destroy(h); }
    } cal;
    const mbx_status status = mbx_calibrate(c.ctx, c.mech, &options, &cal.h);
    if (progress) mbx_context_set_progress(c.ctx, nullptr, nullptr);
    if (status != MBX_OK) return fail(c, status, "calibration");

    mbx_calibration_summary s{};
    s.struct_size = sizeof s;
    mbx_calibration_get_summary(cal.h, &s);
    // A contact calibration has no inverse dynamics (NaN): its figures are the replays'.
    const bool id = std::isfinite(s.baseline_fit_error);
    std::printf("%s: baseline error %.2f %% fit, %.2f %% validation (replay)", in.input.c_str(),
                s.baseline_simulated_fit_error, s.baseline_simulated_validation_error);
    if (id) std::printf("; inverse dynamics %.2f %% / %.2f %%", s.baseline_fit_error, s.baseline_validation_error);
    std::printf("\n");
    if (s.cause_count == 0) std::printf("no cause named\n");
    for (uint32_t i = 0; i < s.cause_count; ++i) {
        mbx_calibration_cause cause{};
        cause.struct_size = sizeof cause;
        mbx_calibration_get_cause(cal.h, i, &cause);
        std::printf("  + %s on %s '%s':", cause.name, cause.subject_kind == MBX_SUBJECT_CONSTRAINT ? "joint" : "body",
                    cause.subject_name);
        for (uint32_t k = 0; k < cause.parameter_count; ++k) {
            mbx_calibration_parameter par{};
            par.struct_size = sizeof par;
            mbx_calibration_get_parameter(cal.h, i, k, &par);
            std::printf(" %s = %.4g +- %.2g", par.name, par.value, par.std_error);
        }
        std::printf(" -> %.2f %% / %.2f %%%s\n", cause.simulated_fit_error, cause.simulated_validation_error,
                    cause.written ? "" : " (reported only)");
    }
    std::printf("calibrated error %.2f %% fit, %.2f %% validation (replay)", s.final_simulated_fit_error,
                s.final_simulated_validation_error);
    if (id) std::printf("; inverse dynamics %.2f %% / %.2f %%", s.final_fit_error, s.final_validation_error);
    std::printf("\n");
    if (id && std::isfinite(s.noise_level)) {
        // The residual against the records' own noise floor (both in the
        // inverse-dynamics measure): what a cause could still explain.
        const double above = std::sqrt(std::max(0.0, s.final_validation_error * s.final_validation_error -
                                                         s.noise_level * s.noise_level));
        if (s.explained_to_noise == 1)
            std::printf("explained to the noise: the records' own noise is %.2f %% of the effort\n", s.noise_level);
        else
            std::printf("%.2f %% of the effort RMS left above the noise (the records' own noise: %.2f %%)\n", above,
                        s.noise_level);
        for (uint32_t i = 0; i < s.residual_note_count; ++i)
            std::printf("  %s\n", mbx_calibration_get_residual_note(cal.h, i));
    }
    for (uint32_t i = 0; i < s.warning_count; ++i) std::printf("warning: %s\n", mbx_calibration_get_warning(cal.h, i));
    std::printf("report: %s/calibration.html\ndata: %s/calibration.json\ndescription: %s/description.xml (%.1f s)\n",
                out_dir.c_str(), out_dir.c_str(), out_dir.c_str(), s.wall_time);
    if (!urdf_out.empty()) {
        // The model as description.xml holds it, written into the user's URDF.
        const uint32_t known = mbx_mechanism_finding_count(c.mech);
        if (const int code = attach_description(in, out_dir + "/description.xml", c)) return code;
        if (const mbx_status st = mbx_mechanism_update_urdf(c.ctx, c.mech, in.input.c_str(), urdf_out.c_str()); st != MBX_OK)
            return fail(c, st, "writing the calibrated URDF");
        std::printf("urdf: %s\n", urdf_out.c_str());
        for (uint32_t i = known; i < mbx_mechanism_finding_count(c.mech); ++i) {
            mbx_finding f{};
            f.struct_size = sizeof f;
            if (mbx_mechanism_get_finding(c.mech, i, &f) == MBX_OK) std::printf("note: %s\n", f.message);
        }
    }
    return 0;
}

}  // namespace mbx_cli
