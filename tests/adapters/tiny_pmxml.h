// A hand-written PMXML model small enough to reason about, in the exact
// layout SimMechanics Link writes (quoted strings, comma lists, column-major
// orientations), for unit tests of the reader and of the adapter.
//
//   RootGround =weld= RootPart -revolute z @ (100,0,0)- ARM -revolute y @ (200,0,0)- LINK
//                                                            SUB/RootPart =weld= LINK
//
// ARM's CS1 and CG are turned by a rotation that is not symmetric, so reading
// the matrix row-major instead of column-major gives a different pose. LINK
// sits in subsystem "SUB" and uses lbm / lbm*in^2; the joint ARM--LINK is
// stored at the top level and reaches into SUB through the global refs
// (one of them non-contiguous: 16000).
#pragma once
#include <charconv>
#include <string>

#include <Eigen/Geometry>

namespace atest {

inline Eigen::Matrix3d tiny_arm_rotation() {
    return Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
}

inline std::string number_text(double v) {
    char buffer[64];
    const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, r.ptr);
}

// Column-major, as the exporter writes it.
inline std::string orientation_text(const Eigen::Matrix3d& r) {
    std::string s;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) s += (s.empty() ? "" : ",") + number_text(r(i, j));
    return s;
}

inline std::string tiny_frame(const std::string& indent, const std::string& ref, const std::string& name,
                              const std::string& node_id, const std::string& position, const std::string& orientation,
                              const std::string& display_name = "") {
    const std::string in = indent + "  ";
    return indent + "<Frame" + (ref.empty() ? "" : " ref=\"" + ref + "\"") + ">\n" +
           in + "<name>\"" + name + "\"</name>\n" +
           in + "<displayName>\"" + display_name + "\"</displayName>\n" +
           in + "<nodeID>\"" + node_id + "\"</nodeID>\n" +
           in + "<position>" + position + "</position>\n" +
           in + "<positionOrigin>\"WORLD\"</positionOrigin>\n" +
           in + "<positionReferenceFrame>\"WORLD\"</positionReferenceFrame>\n" +
           in + "<positionUnits>\"mm\"</positionUnits>\n" +
           in + "<orientation>" + orientation + "</orientation>\n" +
           in + "<orientationType>\"3x3 Transform\"</orientationType>\n" +
           in + "<orientationUnits>\"rad\"</orientationUnits>\n" +
           in + "<orientationReferenceFrame>\"WORLD\"</orientationReferenceFrame>\n" +
           indent + "</Frame>\n";
}

inline std::string tiny_joint(const std::string& indent, const std::string& name, const std::string& node_id,
                              const std::string& base_ref, const std::string& follower_ref,
                              const std::string& primitives, const std::string& status = "") {
    const std::string in = indent + "  ";
    return indent + "<SimpleJoint>\n" +
           in + "<name>\"" + name + "\"</name>\n" +
           in + "<nodeID>\"" + node_id + "\"</nodeID>\n" +
           in + "<status>\"" + status + "\"</status>\n" +
           in + "<base><JointSide><name>\"\"</name><connection><Frame ref=\"" + base_ref +
           "\"></Frame></connection></JointSide></base>\n" +
           in + "<follower><JointSide><name>\"\"</name><connection><Frame ref=\"" + follower_ref +
           "\"></Frame></connection></JointSide></follower>\n" +
           in + "<primitives>\n" + primitives + in + "</primitives>\n" +
           indent + "</SimpleJoint>\n";
}

inline std::string tiny_primitive(const std::string& indent, const std::string& name, const std::string& axis) {
    return indent + "<Primitive><name>\"" + name + "\"</name><nodeID>\"\"</nodeID>" +
           "<referenceFrame>\"WORLD\"</referenceFrame><axis>" + axis + "</axis></Primitive>\n";
}

inline std::string tiny_pmxml() {
    const std::string I = "1,0,0,0,1,0,0,0,1";
    const std::string R = orientation_text(tiny_arm_rotation());
    const std::string weld_axis = "0.57735,0.57735,0.57735";
    std::string s;
    s += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\" ?>\n";
    s += "<PhysicalModelingXMLFile>\n";
    s += "  <formatVersion>\"1.0.4\"</formatVersion>\n";
    s += "  <createdUsing>\"SimMechanics Link Version 4.0\"</createdUsing>\n";
    s += "  <name>\"TINY\"</name>\n";
    s += "  <SimMechanics>\n";
    s += "    <name>\"TINY\"</name>\n";
    s += "    <nodeID>\"TINY\"</nodeID>\n";
    s += "    <bodies>\n";
    s += "      <Body>\n";
    s += "        <name>\"RootPart\"</name>\n";
    s += "        <nodeID>\"TINY/RootPart\"</nodeID>\n";
    s += "        <status>\"\"</status>\n";
    s += "        <mass>0</mass>\n";
    s += "        <massUnits>\"kg\"</massUnits>\n";
    s += "        <inertia>0,0,0,0,0,0,0,0,0</inertia>\n";
    s += "        <inertiaUnits>\"kg*m^2\"</inertiaUnits>\n";
    s += "        <frames>\n";
    s += tiny_frame("          ", "", "CG", "TINY/RootPart::CG(AUTOGEN)", "0,0,0", I);
    s += tiny_frame("          ", "", "CS1", "TINY/RootPart::CS1(AUTOGEN)", "0,0,0", I);
    s += tiny_frame("          ", "2", "CS2", "RootGround:-:TINY/RootPart::TINY/RootPart(AUTOGEN)", "0,0,-0", I);
    s += tiny_frame("          ", "3", "CS3", "TINY/RootPart:-:12::TINY/RootPart(AUTOGEN)", "100,0,0", I);
    s += "        </frames>\n";
    s += "        <geometryFileName>\"\"</geometryFileName>\n";
    s += "      </Body>\n";
    s += "      <Body>\n";
    s += "        <name>\"ARM\"</name>\n";
    s += "        <nodeID>\"12\"</nodeID>\n";
    s += "        <status>\"\"</status>\n";
    s += "        <mass>2.5</mass>\n";
    s += "        <massUnits>\"kg\"</massUnits>\n";
    s += "        <inertia>0.01,0.001,0.002,0.001,0.02,0.003,0.002,0.003,0.03</inertia>\n";
    s += "        <inertiaUnits>\"kg*m^2\"</inertiaUnits>\n";
    s += "        <volume>1.5e+005</volume>\n";
    s += "        <volumeUnits>\"mm^3\"</volumeUnits>\n";
    s += "        <frames>\n";
    s += tiny_frame("          ", "", "CG", "12::CG(AUTOGEN)", "150,20,10", R);
    s += tiny_frame("          ", "", "CS1", "12::CS1(AUTOGEN)", "100,0,0", R);
    s += tiny_frame("          ", "4", "CS2", "TINY/RootPart:-:12::12(AUTOGEN)", "100.0,0,0", I);
    s += tiny_frame("          ", "5", "CS3", "12:-:SUB/31::12(AUTOGEN)", "200,0,0", I);
    s += tiny_frame("          ", "", "CS4", "77(USERADDED)", "120,0,0", R, "SENSOR");
    s += "        </frames>\n";
    s += "        <geometryFileName>\"ARM.stl\"</geometryFileName>\n";
    s += "      </Body>\n";
    s += "    </bodies>\n";
    s += "    <joints>\n";
    s += tiny_joint("      ", "RootGround--RootPart", "RootGround:-:TINY/RootPart", "1", "2",
                    tiny_primitive("        ", "weld", weld_axis));
    s += tiny_joint("      ", "RootPart--ARM", "TINY/RootPart:-:12", "3", "4",
                    tiny_primitive("        ", "revolute", "0,0,1"));
    s += tiny_joint("      ", "ARM--LINK", "12:-:SUB/31", "5", "16000",
                    tiny_primitive("        ", "revolute", "0,1.5e-006,-1"), "Could not solve for constraint ");
    s += "    </joints>\n";
    s += "    <grounds>\n";
    s += "      <Ground>\n";
    s += "        <name>\"RootGround\"</name>\n";
    s += "        <nodeID>\"RootGround\"</nodeID>\n";
    s += "        <status>\"\"</status>\n";
    s += "        <frame>\n";
    s += tiny_frame("          ", "1", "CS1", "RootGround:-:TINY/RootPart::RootGround(AUTOGEN)", "-0,0,0", I);
    s += "        </frame>\n";
    s += "      </Ground>\n";
    s += "    </grounds>\n";
    s += "    <subsystems>\n";
    s += "      <Subsystem>\n";
    s += "        <name>\"SUB\"</name>\n";
    s += "        <nodeID>\"SUB\"</nodeID>\n";
    s += "        <status>\"\"</status>\n";
    s += "        <bodies>\n";
    s += "          <Body>\n";
    s += "            <name>\"RootPart\"</name>\n";
    s += "            <nodeID>\"TINY/SUB/RootPart\"</nodeID>\n";
    s += "            <mass>0</mass>\n";
    s += "            <massUnits>\"kg\"</massUnits>\n";
    s += "            <inertia>0,0,0,0,0,0,0,0,0</inertia>\n";
    s += "            <inertiaUnits>\"kg*m^2\"</inertiaUnits>\n";
    s += "            <frames>\n";
    s += tiny_frame("              ", "", "CG", "TINY/SUB/RootPart::CG(AUTOGEN)", "200,0,0.0", I);
    s += tiny_frame("              ", "", "CS1", "TINY/SUB/RootPart::CS1(AUTOGEN)", "200,0,-0.0", I);
    s += tiny_frame("              ", "7", "CS2", "TINY/SUB/RootPart:-:SUB/31::TINY/SUB/RootPart(AUTOGEN)",
                    "200,-0,0", I);
    s += "            </frames>\n";
    s += "            <geometryFileName>\"\"</geometryFileName>\n";
    s += "          </Body>\n";
    s += "          <Body>\n";
    s += "            <name>\"LINK\"</name>\n";
    s += "            <nodeID>\"SUB/31\"</nodeID>\n";
    s += "            <mass>2.20462</mass>\n";
    s += "            <massUnits>\"lbm\"</massUnits>\n";
    s += "            <inertia>20,0,0,0,30,0,0,0,40</inertia>\n";
    s += "            <inertiaUnits>\"lbm*in^2\"</inertiaUnits>\n";
    s += "            <frames>\n";
    s += tiny_frame("              ", "", "CG", "SUB/31::CG(AUTOGEN)", "250,0,0", I);
    s += tiny_frame("              ", "", "CS1", "SUB/31::CS1(AUTOGEN)", "200.00,0,0", I);
    s += tiny_frame("              ", "16000", "CS2", "12:-:SUB/31::SUB/31(AUTOGEN)", "2e+002,0,0", I);
    s += tiny_frame("              ", "8", "CS3", "TINY/SUB/RootPart:-:SUB/31::SUB/31(AUTOGEN)", "200,0,+0", I);
    s += "            </frames>\n";
    s += "            <geometryFileName>\"link.stl\"</geometryFileName>\n";
    s += "          </Body>\n";
    s += "        </bodies>\n";
    s += "        <joints>\n";
    s += tiny_joint("          ", "RootPart--LINK", "TINY/SUB/RootPart:-:SUB/31", "7", "8",
                    tiny_primitive("            ", "weld", weld_axis));
    s += "        </joints>\n";
    s += "        <grounds></grounds>\n";
    s += "        <subsystems></subsystems>\n";
    s += "        <connectionPorts></connectionPorts>\n";
    s += "        <id>0</id>\n";
    s += "      </Subsystem>\n";
    s += "    </subsystems>\n";
    s += "    <connectionPorts></connectionPorts>\n";
    s += "    <id>0</id>\n";
    s += "  </SimMechanics>\n";
    s += "</PhysicalModelingXMLFile>\n";
    return s;
}

}  // namespace atest
