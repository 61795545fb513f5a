// Shared by the drive tests: a drive description resolved against a
// translated mechanism (REQUIREs that the file and the drives are clean), and
// the MJCF joint of a mechanism joint.
#pragma once
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "core/mechatronics/drive_file.h"
#include "export/mjcf/mjcf_layout.h"
#include "core/translator/mechanism.h"

namespace xtest {

inline std::vector<mbx::Drive> resolve_drive_file(const mbx::Mechanism& m, const std::string& path) {
    mbx::MechatronicSpec spec;
    std::vector<mbx::DriveError> errors;
    mbx::load_drive_file(path, spec, errors);
    for (const auto& e : spec.library.errors()) FAIL_CHECK(e.text());
    for (const auto& e : errors) FAIL_CHECK(e.text());
    std::vector<mbx::Drive> drives = mbx::resolve_drives(spec, m, errors);
    for (const auto& e : errors) FAIL_CHECK(e.text());
    REQUIRE(errors.empty());
    return drives;
}

inline std::string mjcf_joint_name(const mbx::MjcfLayout& layout, int joint) {
    for (const mbx::MjcfBody& b : layout.bodies)
        for (const mbx::MjcfJoint& j : b.joints)
            if (j.joint == joint) return j.name;
    return {};
}

}  // namespace xtest
