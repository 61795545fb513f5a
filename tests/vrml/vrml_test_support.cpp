#include "vrml_test_support.h"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <utility>

#include <doctest/doctest.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace vrml_test {

TempDir::TempDir() {
    static std::atomic<int> counter{0};
    const fs::path p =
        fs::temp_directory_path() / ("mbx_vrml_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(p);
    fs::create_directories(p);
    path_ = p.string();
}

TempDir::~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
}

std::string TempDir::write(const std::string& relative, const std::string& text) const {
    const fs::path p = fs::path(path_) / relative;
    fs::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out << text;
    REQUIRE(out.good());
    return p.string();
}

double signed_volume(const mbx_files::VrmlMesh& mesh) {
    double v = 0;
    const auto& p = mesh.vertices;
    for (size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
        const size_t a = mesh.triangles[t] * 3, b = mesh.triangles[t + 1] * 3, c = mesh.triangles[t + 2] * 3;
        // a . (b x c)
        v += p[a] * (p[b + 1] * p[c + 2] - p[b + 2] * p[c + 1]) - p[a + 1] * (p[b] * p[c + 2] - p[b + 2] * p[c]) +
             p[a + 2] * (p[b] * p[c + 1] - p[b + 1] * p[c]);
    }
    return v / 6;
}

bool is_closed(const mbx_files::VrmlMesh& mesh) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t t = 0; t + 2 < mesh.triangles.size(); t += 3)
        for (int k = 0; k < 3; ++k) ++edges[{mesh.triangles[t + k], mesh.triangles[t + (k + 1) % 3]}];
    if (edges.empty()) return false;
    for (const auto& [e, count] : edges) {
        auto it = edges.find({e.second, e.first});
        if (count != 1 || it == edges.end() || it->second != 1) return false;
    }
    return true;
}

int find_node(const mbx_files::VrmlScene& scene, const std::string& name) {
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (scene.nodes[i].name == name) return static_cast<int>(i);
    return -1;
}

void check_error(const std::function<void()>& f, const std::string& file_suffix, int line,
                 const std::string& fragment) {
    try {
        f();
        FAIL("no VrmlError thrown; expected one at " << file_suffix << ":" << line << " with '" << fragment << "'");
    } catch (const mbx_files::VrmlError& e) {
        const std::string what = e.what();
        INFO("message: " << what);
        CHECK(e.file().size() >= file_suffix.size());
        CHECK(e.file().compare(e.file().size() - std::min(e.file().size(), file_suffix.size()), file_suffix.size(),
                               file_suffix) == 0);
        CHECK(e.line() == line);
        CHECK(what.find(fragment) != std::string::npos);
        CHECK(what.find(file_suffix + ":" + std::to_string(line) + ": ") != std::string::npos);
    }
}

mbx_files::VrmlScene read_written(const std::string& text, const std::string& name,
                                  const mbx_files::VrmlLimits& limits) {
    const TempDir dir;
    return mbx_files::read_vrml(dir.write(name, text), limits);
}

std::string vrml(const std::string& body) { return "#VRML V2.0 utf8\n" + body; }

}  // namespace vrml_test
