// Shared by the Modelica exporter tests: export one translation as a
// Modelica package, read Mechanics.mo back with the independent checker and
// compare it with the mechanism (counts, mass data, frame poses).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "export_fixture.h"
#include "msl_checker.h"

namespace mtest {

const msl::Index& msl_index();

struct Package {
    std::string name;                 // Modelica package
    mbx::OutputFiles files;           // everything the Modelica exporter returned
    mbx::Findings notes;              // export notes
    std::map<int, std::string> stems; // body -> mesh stem
    std::string mechanics_text;
    msl::Model mechanics;

    const mbx::OutputFile* file(const std::string& relative) const;  // below modelica/<name>/
};

Package export_package(xtest::Translated& t, mbx::ExportSettings settings = {});

// Structural check against the MSL index, and the semantic checks every
// export must pass: one Body per dynamic body with the mechanism's mass
// data, one RevolutePlanarLoopConstraint per planar loop, a flange pair per
// actuated tree joint, and the frame chain reproducing mbx's forward
// kinematics at zero and at non-zero joint coordinates.
// `strict_flange_names`: flanges must be exactly axis_<joint> / support_<joint>
// (false where CAD names are chosen to collide with them).
void check_package(xtest::Translated& t, const Package& p, bool strict_flange_names = true);

// Components whose description names the mechanism's joint j (by CAD
// constraint id and primitive index).
int joint_of(const mbx::Mechanism& m, const msl::Component& c);

size_t count_class(const msl::Model& model, const std::string& class_name);

}  // namespace mtest
