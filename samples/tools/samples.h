// The committed samples under samples/: each writes its PMXML file, VRML
// assembly and part geometry files into `directory` (which must exist).
#pragma once
#include <string>

namespace mbx_samples {

void make_fourbar_imperial(const std::string& directory);
void make_double_cardan(const std::string& directory);
void make_five_axis_arm(const std::string& directory);
void make_joints_showcase(const std::string& directory);
void make_emps_axis(const std::string& directory);
// A Simscape Multibody second-generation export on the DFKI double
// pendulum's real STEP levers (read from ../shared when the tool runs).
void make_double_pendulum_simscape(const std::string& directory);

}  // namespace mbx_samples
