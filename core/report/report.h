// The translation report: what an engineer reads to trust (or fix) a
// translation. report.json is for tools, report.txt for people. Both are
// deterministic (byte-identical for the same Mechanism) and linear in size.
#pragma once
#include <string>

#include "core/mechatronics/drive.h"
#include "core/mechatronics/joint_dynamics.h"
#include "core/translator/mechanism.h"

namespace mbx {

// The whole mechanism as JSON (schema in report_json.cpp), ending in '\n'.
// `drives` and `joint_dynamics` (each may be null or empty) add a "drives"
// and a "joint_dynamics" section.
std::string report_json(const Mechanism& m, const std::vector<Drive>* drives = nullptr,
                        const std::vector<ResolvedJointDynamics>* joint_dynamics = nullptr);

// A plain-text summary: counts, the tree outline from ground, loops, and
// findings grouped by severity. Lines stay under 120 characters.
std::string report_text(const Mechanism& m, const std::vector<Drive>* drives = nullptr,
                        const std::vector<ResolvedJointDynamics>* joint_dynamics = nullptr);

// Writes <directory>/report.json and <directory>/report.txt as one unit (see
// write_files_atomically), creating the directory if needed. Throws
// mbx::Error(MBX_ERROR_IO) naming the file that could not be written.
void write_report(const Mechanism& m, const std::string& directory, const std::vector<Drive>* drives = nullptr,
                  const std::vector<ResolvedJointDynamics>* joint_dynamics = nullptr);

}  // namespace mbx
