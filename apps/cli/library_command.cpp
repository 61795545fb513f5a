// `mbx library <file.xml>...`: checks object library files and shows each
// object with what mbx derives from it (motor constants, reflected inertia).
// Until drives reach the C API (mechatronics issue) this reads the library
// through the SDK's own module.
#include <cstdio>

#include "commands.h"
#include "core/mechatronics/drive_quantities.h"
#include "core/mechatronics/object_library.h"

namespace mbx_cli {

int run_library(const std::vector<std::string>& args) {
    if (args.empty() || args[0] == "-h" || args[0] == "--help") {
        std::fputs("usage: mbx library <library.xml>...\n"
                   "  checks object library files (errors as 'file:line: class/object: message', exit 1)\n"
                   "  and lists every object with its derived drive quantities\n",
                   args.empty() ? stderr : stdout);
        return args.empty() ? 2 : 0;
    }
    mbx::ObjectLibrary lib;
    for (const std::string& path : args) lib.load_file(path);
    for (const mbx::LibraryError& e : lib.errors()) std::fprintf(stderr, "mbx: %s\n", e.text().c_str());
    for (const mbx::LibraryFolder& folder : lib.folders()) {
        std::printf("%s\n", folder.name.c_str());
        for (const mbx::LibraryClass& cls : folder.classes) {
            std::printf("  %s (%s)\n", cls.name.c_str(), cls.modelica.c_str());
            for (const mbx::LibraryObject& obj : cls.objects) {
                std::printf("    %s  %s\n", obj.id.c_str(), obj.name.c_str());
                const mbx::ObjectLibrary::Found f{&cls, &obj};
                std::string why;
                if (cls.kind == "dc_motor") {
                    if (const auto c = mbx::dc_motor_constants(lib, f, why))
                        std::printf("      k %.4g N m/A, stall torque %.4g N m, no-load speed %.4g rad/s, "
                                    "rotor %.4g kg m2 x ratio %.4g^2 = %.4g kg m2 at the joint\n",
                                    c->torque_constant, c->stall_torque, c->no_load_speed, c->rotor_inertia,
                                    c->ratio, c->reflected_inertia);
                    else
                        std::printf("      (no motor constants: %s)\n", why.c_str());
                } else if (cls.kind == "gearbox" || cls.kind == "ball_screw") {
                    if (const auto t = mbx::transmission_constants(lib, f, why))
                        std::printf("      ratio %.6g%s, efficiency %.3g, own inertia %.4g kg m2 -> %.4g %s\n",
                                    t->ratio, t->linear ? " rad/m" : "", t->efficiency, t->inertia,
                                    t->reflected_inertia, t->linear ? "kg at the carriage" : "kg m2 at the output");
                    else
                        std::printf("      (no transmission constants: %s)\n", why.c_str());
                }
            }
        }
    }
    return lib.ok() ? 0 : 1;
}

}  // namespace mbx_cli
