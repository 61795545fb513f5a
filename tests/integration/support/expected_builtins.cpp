#include "expected_builtins.h"

#include <stdexcept>

namespace itest {

const std::vector<ExpectedBuiltin>& expected_builtins() {
    static const std::vector<ExpectedBuiltin> table = [] {
        std::vector<ExpectedBuiltin> t;
        {
            ExpectedBuiltin e;
            e.name = "double_cardan";
            const std::string p = "double_cardan/";
            e.parts = 6;
            e.rigid_bodies = 4;
            e.joint_nodes = 1;
            e.joints = e.revolutes = 7;
            e.welds = 1;
            e.loops = 2;
            e.planar_loops = 0;
            e.dof = 1;
            e.gruebler = 6 * 5 - 5 * 7;
            e.redundant = 6;
            e.loop_list = {
                {{p + "bearing_centre", 0},
                 {{p + "bearing_in", 0}, {p + "cross1_in", 0}, {p + "cross1_out", 0}, {p + "bearing_centre", 0}},
                 1, 3, 4 - 6, false},
                {{p + "cardan2", 1},
                 {{p + "bearing_in", 0}, {p + "cross1_in", 0}, {p + "cross1_out", 0}, {p + "bearing_out", 0},
                  {p + "cardan2", 0}, {p + "cardan2", 1}},
                 1, 1, 6 - 6, false},
            };
            e.merged = {{p + "input_shaft", p + "input_yoke"}};
            e.in_ground = {p + "frame"};
            t.push_back(e);
        }
        {
            ExpectedBuiltin e;
            e.name = "fourbar";
            const std::string p = "fourbar/";
            e.parts = 6;
            e.rigid_bodies = 3;
            e.joints = e.revolutes = 4;
            e.welds = 2;
            e.loops = 1;
            e.planar_loops = 1;
            e.dof = 1;
            e.gruebler = 6 * 3 - 5 * 4;
            e.redundant = 3;
            e.loop_list = {
                {{p + "rev_D", 0}, {{p + "rev_A", 0}, {p + "rev_B", 0}, {p + "rev_C", 0}, {p + "rev_D", 0}}, 1, 3,
                 4 - 3, true},
            };
            e.in_ground = {p + "ground", p + "RootPart", p + "ground_link"};
            t.push_back(e);
        }
        {
            ExpectedBuiltin e;
            e.name = "planar_sixbar";
            const std::string p = "planar_sixbar/";
            e.parts = 6;
            e.rigid_bodies = 5;
            e.joints = e.revolutes = 7;
            e.loops = 2;
            e.planar_loops = 2;
            e.dof = 1;
            e.gruebler = 6 * 5 - 5 * 7;
            e.redundant = 6;
            e.loop_list = {
                {{p + "g_R", 0}, {{p + "g_A", 0}, {p + "A_C1", 0}, {p + "C1_R", 0}, {p + "g_R", 0}}, 1, 3, 4 - 3, true},
                {{p + "g_D", 0},
                 {{p + "g_A", 0}, {p + "A_C1", 0}, {p + "C1_R", 0}, {p + "R_C2", 0}, {p + "C2_D", 0}, {p + "g_D", 0}},
                 3, 3, 6 - 3, true},
            };
            e.in_ground = {p + "ground"};
            t.push_back(e);
        }
        {
            ExpectedBuiltin e;
            e.name = "six_axis_arm";
            const std::string p = "six_axis_arm/";
            e.parts = 9;
            e.rigid_bodies = 6;
            e.joints = e.revolutes = 6;
            e.welds = 2;
            e.dof = 6;
            e.gruebler = 6 * 6 - 5 * 6;
            e.redundant = 0;
            e.merged = {{p + "link2_housing", p + "link2_tube", p + "link2_elbow"}};
            e.in_ground = {p + "base"};
            e.reversed = {{p + "J5", 0}};
            t.push_back(e);
        }
        return t;
    }();
    return table;
}

const ExpectedBuiltin& expected_builtin(const std::string& name) {
    for (const auto& e : expected_builtins())
        if (e.name == name) return e;
    throw std::out_of_range("no expectations for builtin " + name);
}

}  // namespace itest
