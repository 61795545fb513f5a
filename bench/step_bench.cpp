// STEP files read by mbx's Part 21 reader against OpenCASCADE's
// STEPControl_Reader::ReadFile (its Part 21 parse into the StepData model,
// before any shape is built), on the real files of ../shared/data/step and
// Debian's occt-misc and gmsh-doc: milliseconds, MB/s and the ratio, with a
// bare pass over the bytes (counting ';') as the floor.
#include <STEPControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "host_adapters/step/part21.h"

namespace {

double best_ms(int runs, const std::function<void()>& f) {
    double best = 1e300;
    for (int k = 0; k < runs; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

int main(int argc, char** argv) {
    const std::string shared = argc > 1 ? argv[1] : MBX_SHARED_DATA;
    std::vector<std::string> files = {
        shared + "/step/dfki_double_pendulum/lever_200.STEP",
        shared + "/step/dfki_double_pendulum/double_pendulum.STEP",
        shared + "/step/nist_ctc_02/nist_ctc_02_asme1_ap242-1.stp",
        "/usr/share/opencascade/data/step/screw.step",
        "/usr/share/opencascade/data/step/linkrods.step",
    };
    // OpenCASCADE reports each file it reads on its messenger: silenced, so the
    // table stays readable and the printing is not timed.
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_Printer));
    std::printf("%-34s %9s %9s %8s %8s %9s %9s %7s\n", "file", "MB", "instances", "bare ms", "mbx ms", "mbx MB/s",
                "OCCT ms", "ratio");
    for (const std::string& path : files) {
        const std::string text = read_text(path);
        if (text.empty()) {
            std::printf("%-34s (missing)\n", path.substr(path.rfind('/') + 1).c_str());
            continue;
        }
        const double mb = double(text.size()) / 1e6;
        size_t statements = 0;
        const double bare = best_ms(5, [&] {
            statements = 0;
            for (const char* p = text.data(); (p = static_cast<const char*>(std::memchr(p, ';', size_t(text.data() + text.size() - p))));
                 ++p)
                ++statements;
        });
        size_t instances = 0;
        const double ours = best_ms(5, [&] { instances = mbx_step::read_part21_file(path).instances.size(); });
        const double occt = best_ms(3, [&] {
            STEPControl_Reader reader;
            if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) std::printf("OCCT could not read %s\n", path.c_str());
        });
        std::printf("%-34s %9.2f %9zu %8.2f %8.2f %9.0f %9.1f %6.1fx\n", path.substr(path.rfind('/') + 1).c_str(), mb,
                    instances, bare, ours, mb / (ours / 1e3), occt, occt / ours);
        (void)statements;
    }
    return 0;
}
