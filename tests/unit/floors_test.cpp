// The tree's floors only look down (docs/architecture.md): every quoted
// include of the product's code is resolved the way the compiler resolves it
// (beside the including file, then from the repository's root, then the
// public header folder) and must land on the including file's floor or one
// below it; on the same floor, only in the rooms the table below lets it
// reach. An include that resolves nowhere fails too: it would be reached
// through some target's include path, which this check could not place.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace MBX_UNITY_ID {

namespace fs = std::filesystem;

namespace {

struct Room {
    const char* prefix;  // path from the root; the longest matching prefix wins
    int floor;
    // Rooms of the same floor this one may include.
    std::set<std::string> reaches;
    // When not empty, the only rooms below it may include: a host sees the
    // contract and host adapters, never the SDK's internals.
    std::set<std::string> only_below = {};
};

// Floor 0 is the core; 1 the modules that stand on it; 2 the SDK's C faces;
// 3 the hosts of that API. The public header (sdk/include) is the contract
// every floor shares: it includes nothing of the product.
const std::vector<Room>& rooms() {
    static const std::vector<Room> table = {
        {"sdk/include/", -1, {}},
        {"core/", 0, {}},
        {"host_adapters/", 1, {}},
        {"sim/", 1, {}},
        {"export/", 1, {"sim/"}},        // collision shapes of sim/contact
        {"calibration/", 1, {"sim/"}},   // the simulator's dynamics and replays
        {"view/", 1, {"sim/", "export/"}},  // forward kinematics, the glTF scene
        {"sdk/", 2, {}},
        {"host_adapters/files_capi/", 2, {}},
        {"apps/", 3, {"apps/stub_host/"}},  // the CLI serves the stub host's built-in assemblies
        {"apps/stub_host/", 3, {}, {"sdk/include/", "host_adapters/"}},
    };
    return table;
}

const Room* room_of(const std::string& path) {
    const Room* best = nullptr;
    for (const Room& r : rooms())
        if (path.rfind(r.prefix, 0) == 0 && (!best || std::string(r.prefix).size() > std::string(best->prefix).size()))
            best = &r;
    return best;
}

std::string root_relative(const fs::path& p, const fs::path& root) {
    return fs::relative(p, root).lexically_normal().generic_string();
}

// Where `#include "inc"` in `file` lands, relative to the root ("" if nowhere).
std::string resolve(const fs::path& root, const std::string& file, const std::string& inc) {
    const fs::path beside = root / fs::path(file).parent_path() / inc;
    if (fs::exists(beside)) return root_relative(beside, root);
    if (fs::exists(root / inc)) return root_relative(root / inc, root);
    if (fs::exists(root / "sdk/include" / inc)) return root_relative(root / "sdk/include" / inc, root);
    return "";
}

struct Violation {
    std::string file;
    int line;
    std::string include;
    std::string why;
};

std::vector<Violation> check_tree(const fs::path& root) {
    std::vector<Violation> out;
    const std::regex include_line(R"re(^\s*#\s*include\s+"([^"]+)")re");
    std::set<std::string> top_folders;
    for (const Room& r : rooms()) top_folders.insert(std::string(r.prefix).substr(0, std::string(r.prefix).find('/')));
    std::vector<fs::path> files;
    for (const std::string& top : top_folders)
        if (fs::is_directory(root / top))
            for (const fs::directory_entry& e : fs::recursive_directory_iterator(root / top))
                if (e.is_regular_file()) files.push_back(e.path());
    for (const fs::path& path : files) {
        const std::string ext = path.extension().string();
        if (ext != ".cpp" && ext != ".h" && ext != ".hxx" && ext != ".c") continue;
        const std::string file = root_relative(path, root);
        const Room* from = room_of(file);
        if (!from) continue;  // tests, benchmarks, fuzzers, samples: above every floor
        std::ifstream in(path);
        std::string text;
        int line_no = 0;
        while (std::getline(in, text)) {
            ++line_no;
            std::smatch m;
            if (!std::regex_search(text, m, include_line)) continue;
            const std::string inc = m[1];
            const std::string target = resolve(root, file, inc);
            if (target.empty()) {
                out.push_back({file, line_no, inc, "resolves neither beside the file nor from the root"});
                continue;
            }
            const Room* to = room_of(target);
            if (!to) {
                out.push_back({file, line_no, inc, "reaches " + target + ", which is on no floor"});
                continue;
            }
            if (to->floor < from->floor && !from->only_below.empty() && !from->only_below.count(to->prefix)) {
                out.push_back({file, line_no, inc, std::string(from->prefix) + " may include only the public header and host adapters, not " + target});
                continue;
            }
            if (to == from || to->floor < from->floor) continue;
            if (to->floor == from->floor && from->reaches.count(to->prefix)) continue;
            std::ostringstream why;
            why << "floor " << from->floor << " (" << from->prefix << ") includes " << target << " on floor "
                << to->floor << " (" << to->prefix << ")";
            out.push_back({file, line_no, inc, why.str()});
        }
    }
    return out;
}

}  // namespace

TEST_CASE("every include of the product runs down the floors, never up") {
    const fs::path root = MBX_SOURCE_DIR;
    REQUIRE(fs::exists(root / "core/finding.h"));
    const std::vector<Violation> violations = check_tree(root);
    for (const Violation& v : violations)
        MESSAGE(v.file << ":" << v.line << ": #include \"" << v.include << "\": " << v.why);
    CHECK(violations.empty());
}

TEST_CASE("the floors check catches an upward and an unplaceable include") {
    // A scratch tree with one file per kind of mistake, so a check that looks
    // at nothing (or resolves nothing) fails here.
    const fs::path root = fs::temp_directory_path() / ("mbx_floors_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root / "core/translator");
    fs::create_directories(root / "sim");
    fs::create_directories(root / "sdk/capi");
    fs::create_directories(root / "calibration");
    fs::create_directories(root / "view");
    auto write = [&](const char* path, const char* text) { std::ofstream(root / path) << text; };
    write("core/finding.h", "#pragma once\n");
    write("core/translator/up.cpp", "#include \"core/finding.h\"\n#include \"sim/model.h\"\n");
    write("sim/model.h", "#pragma once\n#include \"core/finding.h\"\n");
    write("sdk/capi/api.cpp", "#include \"sim/model.h\"\n");
    write("calibration/fit.cpp", "#include \"sim/model.h\"\n#include \"view/page.h\"\n#include \"fit_local.h\"\n");
    write("view/page.h", "#pragma once\n");
    fs::create_directories(root / "apps/stub_host");
    write("apps/stub_host/host.cpp", "#include \"core/finding.h\"\n");
    const std::vector<Violation> v = check_tree(root);
    fs::remove_all(root);
    std::map<std::string, std::string> by_file;
    for (const Violation& x : v) by_file[x.file + " " + x.include] = x.why;
    CHECK(v.size() == 4);
    CHECK(by_file.count("apps/stub_host/host.cpp core/finding.h"));         // a host seeing the SDK's internals
    CHECK(by_file.count("core/translator/up.cpp sim/model.h"));            // the core reaching floor 1
    CHECK(by_file.count("calibration/fit.cpp view/page.h"));               // a room it may not reach
    CHECK(by_file.count("calibration/fit.cpp fit_local.h"));               // resolvable only by an include path
    CHECK_FALSE(by_file.count("sdk/capi/api.cpp sim/model.h"));            // the face reaching down
}
}  // namespace MBX_UNITY_ID
