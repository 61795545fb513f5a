#include "core/report/report.h"

#include <filesystem>

#include "core/report/atomic_file.h"

namespace mbx {

void write_report(const Mechanism& m, const std::string& directory, const std::vector<Drive>* drives,
                  const std::vector<ResolvedJointDynamics>* joint_dynamics) {
    const std::filesystem::path dir(directory);
    // Both texts are built before anything touches the disk, so a failure
    // while building (out of memory) leaves the old report in place.
    std::vector<std::pair<std::string, std::string>> files;
    files.reserve(2);
    // emplace, not an initializer list, which would copy megabytes of text.
    files.emplace_back((dir / "report.json").string(), report_json(m, drives, joint_dynamics));
    files.emplace_back((dir / "report.txt").string(), report_text(m, drives, joint_dynamics));
    write_files_atomically(files);
}

}  // namespace mbx
