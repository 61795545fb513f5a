// The Modelica MultiBody exporter, read back by an independent parser and
// checked against the MSL 4.0 class index and against mbx's own mechanism:
// structure (classes, modifiers, connectors), mass data, loop handling,
// flanges and the frame chain at zero and non-zero joint coordinates.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "apps/stub_host/assemblies/builder.h"
#include "export/modelica/modelica_text.h"
#include "modelica_support.h"
#include "tests/common/file_text.h"
#include "tests/common/skip.h"
#include "tests/common/shared_data.h"

namespace MBX_UNITY_ID {

using namespace mbx;
namespace fs = std::filesystem;

namespace {

const std::string kMB = "Modelica.Mechanics.MultiBody.";

bool has_note(const Findings& notes, mbx_finding_code code, const std::string& fragment) {
    for (const Finding& f : notes)
        if (f.code == code && f.message.find(fragment) != std::string::npos) return true;
    return false;
}

std::string pmxml_dir() {
    return mbx_test::shared_data("pmxml");
}

using mbx_stub::build::Builder;
using mbx_stub::build::Mat3;
using mbx_stub::build::Prim;
using mbx_stub::build::Vec3;
using mbx_stub::build::axis_angle;
using mbx_stub::build::box_inertia;
using mbx_stub::build::box_mesh;
using mbx_stub::build::revolute;
using mbx_stub::build::spherical;

const mbx_units kSI{1, 1, 1};

Prim prismatic(const Vec3& axis, double lower, double upper) {
    Prim p;
    p.type = MBX_PRIMITIVE_PRISMATIC;
    p.axis = axis;
    p.has_limits = true;
    p.lower = lower;
    p.upper = upper;
    return p;
}

void add_box_body(Builder& b, const std::string& local, const std::string& name, uint32_t flags, const Mat3& rotation,
                  const Vec3& at, const Vec3& size) {
    const double mass = 1.0 + size.sum();
    b.body(local, name, flags, mass, rotation, at, at + rotation * Vec3(0.01, -0.02, 0.005),
           box_inertia(mass, size.x(), size.y(), size.z()));
    b.mesh(local, box_mesh(name, size, Mat3::Identity(), Vec3::Zero()));
}

// A prismatic carriage (with limits), a spherical pendulum on it (a tree
// spherical: relative states), a universal joint (revolute + node +
// revolute) below, and a free-floating drone with a propeller.
mbx_memory::Assembly mixed_assembly() {
    mbx_memory::Assembly a;
    a.name = "mixed";
    Builder b(a, "mixed", kSI, kSI);
    const Mat3 I = Mat3::Identity();
    add_box_body(b, "ground", "Base", MBX_BODY_GROUND, I, Vec3(0, 0, -0.05), Vec3(1, 1, 0.1));
    const Mat3 r1 = axis_angle(Vec3(0, 0, 1), 0.4);
    add_box_body(b, "carriage", "Carriage", 0, r1, Vec3(0.1, 0.1, 0.1), Vec3(0.2, 0.1, 0.05));
    const Mat3 r2 = axis_angle(Vec3(1, 2, 3).normalized(), 0.7);
    add_box_body(b, "pendulum", "Pendulum", 0, r2, Vec3(0.15, 0.1, -0.1), Vec3(0.05, 0.05, 0.3));
    const Mat3 r3 = axis_angle(Vec3(-1, 0.5, 0.2).normalized(), 1.1);
    add_box_body(b, "tip", "Tip", 0, r3, Vec3(0.15, 0.12, -0.35), Vec3(0.04, 0.04, 0.04));
    const Mat3 r4 = axis_angle(Vec3(0.3, -1, 0.4).normalized(), 2.0);
    add_box_body(b, "drone", "Drone", 0, r4, Vec3(1, 2, 3), Vec3(0.3, 0.3, 0.08));
    add_box_body(b, "propeller", "Propeller", 0, r4, Vec3(1, 2, 3) + r4 * Vec3(0, 0, 0.1), Vec3(0.25, 0.02, 0.01));

    b.joint("slide", "ground", "carriage", Vec3(0.1, 0.1, 0.1), I,
            {prismatic(Vec3(1, 1, 0).normalized(), -0.2, 0.3)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_BODY);
    b.joint("ball", "carriage", "pendulum", Vec3(0.15, 0.1, 0.05), r2, {spherical()}, MBX_FRAME_IN_BODY,
            MBX_FRAME_IN_WORLD);
    b.joint("cardan", "pendulum", "tip", Vec3(0.15, 0.12, -0.3), r2,
            {revolute(Vec3(1, 0, 0)), revolute(Vec3(0, 0.6, 0.8))}, MBX_FRAME_IN_BODY, MBX_FRAME_IN_BODY);
    b.joint("spin", "drone", "propeller", Vec3(1, 2, 3) + r4 * Vec3(0, 0, 0.1), r4,
            {revolute(r4 * Vec3(0, 0, 1))}, MBX_FRAME_IN_BODY, MBX_FRAME_IN_WORLD);
    return a;
}

// A planar slider-crank whose loop the tree cuts at the prismatic slide:
// MSL has no planar-loop prismatic, so a revolute must carry the constraint.
mbx_memory::Assembly slider_crank() {
    mbx_memory::Assembly a;
    a.name = "slider crank";
    Builder b(a, "sc", kSI, kSI);
    const Mat3 I = Mat3::Identity();
    const Vec3 A(0, 0, 0), B(0.05, 0.03, 0), C(0.2, 0, 0), z(0, 0, 1);
    add_box_body(b, "frame", "Frame", MBX_BODY_GROUND, I, Vec3(0.1, -0.05, 0), Vec3(0.3, 0.02, 0.02));
    add_box_body(b, "crank", "Crank", 0, mbx_stub::build::rotation_x_to(B - A, z), A, Vec3(0.06, 0.01, 0.01));
    add_box_body(b, "rod", "Rod", 0, mbx_stub::build::rotation_x_to(C - B, z), B, Vec3(0.16, 0.01, 0.01));
    add_box_body(b, "slider", "Slider", 0, I, C, Vec3(0.03, 0.02, 0.02));
    b.joint("rev_A", "frame", "crank", A, I, {revolute(z)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.joint("rev_B", "crank", "rod", B, I, {revolute(z)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    b.joint("rev_C", "rod", "slider", C, I, {revolute(z)}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    Prim slide = prismatic(Vec3(1, 0, 0), 0, 0);
    slide.has_limits = false;
    b.joint("slide", "frame", "slider", C, I, {slide}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
    return a;
}

// A serial chain whose CAD names collide, carry quotes, backslashes and
// spaces, start with digits or are Modelica keywords and fixed names.
mbx_memory::Assembly awkward_names() {
    mbx_memory::Assembly a;
    a.name = "names";
    Builder b(a, "n", kSI, kSI);
    const std::vector<std::string> names = {"end", "model", "my part", "a \"quoted\" \\ name", "3d printed", "link",
                                            "link", "world", "Modelica", "LINK", "Mechanics", "axis_j1", "", "Real"};
    add_box_body(b, "ground", "ground", MBX_BODY_GROUND, Mat3::Identity(), Vec3::Zero(), Vec3(0.1, 0.1, 0.1));
    std::string previous = "ground";
    for (size_t k = 0; k < names.size(); ++k) {
        const std::string local = "b" + std::to_string(k);
        add_box_body(b, local, names[k], 0, axis_angle(Vec3(0, 1, 0), 0.1 * double(k)), Vec3(0.1 * double(k + 1), 0, 0),
                     Vec3(0.05, 0.02, 0.02));
        b.joint("j" + std::to_string(k), previous, local, Vec3(0.1 * double(k) + 0.05, 0, 0), Mat3::Identity(),
                {revolute(Vec3(0, 0, 1))}, MBX_FRAME_IN_WORLD, MBX_FRAME_IN_WORLD);
        previous = local;
    }
    // Joint names collide too (the builder derives frame ids from its local names).
    const std::vector<std::string> joint_names = {"end", "connect", "rev 1", "rev 1", "J1", "world", "axis"};
    for (size_t k = 0; k < a.constraints.size(); ++k) a.constraints[k].name = joint_names[k % joint_names.size()];
    return a;
}

// The same text, numbers equal to 1e-12 of their size: the last digit of a
// shortest round-trip number depends on the order of a sum, which a compiler
// (and Eigen's alignment-dependent reductions) may change between builds.
bool same_text_but_rounding(const std::string& a, const std::string& b) {
    if (a == b) return true;
    static const std::regex number(R"([-+]?[0-9]+\.[0-9]*(?:e[-+]?[0-9]+)?)");
    auto split = [&](const std::string& s, std::vector<std::string>& text, std::vector<double>& values) {
        size_t at = 0;
        for (auto it = std::sregex_iterator(s.begin(), s.end(), number); it != std::sregex_iterator(); ++it) {
            text.push_back(s.substr(at, size_t(it->position()) - at));
            values.push_back(std::stod(it->str()));
            at = size_t(it->position() + it->length());
        }
        text.push_back(s.substr(at));
    };
    std::vector<std::string> ta, tb;
    std::vector<double> va, vb;
    split(a, ta, va), split(b, tb, vb);
    if (ta != tb || va.size() != vb.size()) return false;
    for (size_t i = 0; i < va.size(); ++i)
        if (!(std::abs(va[i] - vb[i]) <= 1e-12 * std::max(std::abs(va[i]), std::abs(vb[i])))) return false;
    return true;
}

// Golden files are regression checks (docs/testing.md): they hold what the
// exporter wrote when last reviewed, so they catch a change, never prove a
// result right; each sits beside an independent check of the same text. They
// live beside this test; MBX_UPDATE_GOLDEN=1 rewrites them.
// Found from the samples folder, not __FILE__: a compiler cache with a base
// directory (.ci/configure) makes __FILE__ relative to the build folder.
void check_golden(const std::string& file, const std::string& contents) {
    const fs::path path = fs::path(MBX_SAMPLES_DIR).parent_path() / "tests" / "export" / "golden" / file;
    const char* update = std::getenv("MBX_UPDATE_GOLDEN");
    if (update && std::string(update) == "1") {
        fs::create_directories(path.parent_path());
        std::ofstream(path, std::ios::binary) << contents;
        MESSAGE("golden file rewritten: " << path.string());
        return;
    }
    REQUIRE_MESSAGE(fs::exists(path), "golden file " << path.string()
                                                     << " is missing; run the test with MBX_UPDATE_GOLDEN=1 to create it");
    CHECK_MESSAGE(same_text_but_rounding(mbx_test::read_file(path), contents),
                  "Mechanics.mo differs from golden file " << path.string()
                                                           << ". If the change is intended, review it and rerun with "
                                                              "MBX_UPDATE_GOLDEN=1 to rewrite the golden file.");
}

ExportSettings named(const std::string& name) {
    ExportSettings s;
    s.model_name = name;
    return s;
}

}  // namespace

TEST_CASE("modelica: every builtin passes the MSL structure check and reproduces the mechanism") {
    for (const std::string& name : mbx_stub::builtin_names()) {
        CAPTURE(name);
        auto t = xtest::translate_builtin(name);
        const mtest::Package p = mtest::export_package(*t, named(name));
        mtest::check_package(*t, p);
        CHECK_FALSE(p.stems.empty());  // the builtins carry box meshes
        // Redundancy MSL cannot remove is reported, loop by loop.
        for (size_t li = 0; li < t->mechanism->loops.size(); ++li) {
            const Loop& loop = t->mechanism->loops[li];
            CHECK(has_note(p.notes, MBX_FINDING_EXPORT_APPROXIMATION, "loop " + std::to_string(li) + " (cut joint") ==
                  (loop.redundant > (loop.planar ? 3 : 0)));
        }
    }
}

TEST_CASE("modelica: package layout, header, gravity, experiment and user model") {
    auto t = xtest::translate_builtin("fourbar");
    ExportSettings s = named("fourbar");
    s.stop_time = 2.5;
    const mtest::Package p = mtest::export_package(*t, s);
    CHECK(p.name == "Fourbar");
    const std::set<std::string> expected = {"modelica/Fourbar/package.mo", "modelica/Fourbar/package.order",
                                            "modelica/Fourbar/Mechanics.mo", "modelica/Fourbar/UserModel.mo"};
    size_t meshes = 0;
    for (const OutputFile& f : p.files) {
        if (f.path.rfind("modelica/Fourbar/Resources/Meshes/", 0) == 0) {
            CHECK(f.path.size() > 4);
            CHECK(f.path.compare(f.path.size() - 4, 4, ".stl") == 0);
            ++meshes;
        } else {
            CHECK_MESSAGE(expected.count(f.path), "unexpected file " << f.path);
        }
    }
    CHECK(meshes == p.stems.size());
    CHECK(meshes == 4);  // ground (plate + ground link), crank, coupler, rocker

    const std::string& package = p.file("package.mo")->contents;
    CHECK(package.find("within;\npackage Fourbar ") != std::string::npos);
    CHECK(package.find("uses(Modelica(version = \"4.0.0\"))") != std::string::npos);
    CHECK(package.find("end Fourbar;") != std::string::npos);
    const msl::Model user = msl::parse_model(p.file("UserModel.mo")->contents);
    CHECK(user.errors.empty());
    CHECK(user.name == "UserModel");
    CHECK(p.file("UserModel.mo")->contents.find("extends Fourbar.Mechanics;") != std::string::npos);

    CHECK(p.mechanics_text.rfind("// Generated by mbx", 0) == 0);
    CHECK(p.mechanics_text.find("Do not edit") != std::string::npos);
    const msl::Component* world = p.mechanics.find("world");
    REQUIRE(world);
    CHECK(world->inner);
    CHECK(world->class_name == kMB + "World");
    CHECK((msl::parse_vector(world->value("n")) - Vec3(0, 0, -1)).norm() == 0);
    CHECK(p.mechanics.annotation.find("experiment(StopTime = 2.5") != std::string::npos);

    // Visual shapes: the STL in the body frame at scale 1 (extra = 0: unscaled).
    size_t shapes = 0;
    for (const msl::Component& c : p.mechanics.components) {
        if (c.class_name != kMB + "Visualizers.FixedShape") continue;
        ++shapes;
        CHECK(c.value("shapeType").rfind("\"modelica://Fourbar/Resources/Meshes/", 0) == 0);
        CHECK(c.value("extra") == "0");
        CHECK(msl::parse_vector(c.value("r_shape")).norm() == 0);
        CHECK((msl::parse_vector(c.value("lengthDirection")) - Vec3(1, 0, 0)).norm() == 0);
        CHECK((msl::parse_vector(c.value("widthDirection")) - Vec3(0, 1, 0)).norm() == 0);
    }
    CHECK(shapes == 4);
    // Bodies that show a mesh hide MSL's default sphere and cylinder.
    for (const msl::Component& c : p.mechanics.components)
        if (c.class_name == kMB + "Parts.Body") CHECK(c.value("animation") == "false");
}

TEST_CASE("modelica: fourbar and planar six-bar close each planar loop with RevolutePlanarLoopConstraint") {
    for (const char* name : {"fourbar", "planar_sixbar"}) {
        CAPTURE(name);
        auto t = xtest::translate_builtin(name);
        const Mechanism& m = *t->mechanism;
        const mtest::Package p = mtest::export_package(*t, named(name));
        size_t planar = 0;
        for (const Loop& loop : m.loops) {
            if (!loop.planar) continue;
            ++planar;
            const msl::Component* cut = nullptr;
            for (const msl::Component& c : p.mechanics.components)
                if (mtest::joint_of(m, c) == loop.cut_joint) cut = &c;
            REQUIRE(cut);
            CHECK(cut->class_name == kMB + "Joints.RevolutePlanarLoopConstraint");
        }
        CHECK(planar >= 1);
        CHECK(mtest::count_class(p.mechanics, kMB + "Joints.RevolutePlanarLoopConstraint") == planar);
    }
}

TEST_CASE("modelica: prismatic, spherical, universal joint node, floating body and joint limits") {
    auto t = xtest::translate(mixed_assembly());
    const Mechanism& m = *t->mechanism;
    REQUIRE(m.floating_roots == 1);
    const mtest::Package p = mtest::export_package(*t, named("mixed"));
    mtest::check_package(*t, p);

    size_t nodes = 0;
    for (const RigidBody& b : m.bodies) nodes += b.kind == MBX_RIGID_BODY_JOINT_NODE;
    CHECK(nodes == 1);
    CHECK(mtest::count_class(p.mechanics, kMB + "Joints.Prismatic") == 1);
    CHECK(mtest::count_class(p.mechanics, "Modelica.Mechanics.Translational.Interfaces.Flange_a") == 2);
    CHECK(mtest::count_class(p.mechanics, "Modelica.Mechanics.Rotational.Interfaces.Flange_a") == 2 * 3);
    for (const msl::Component& c : p.mechanics.components) {
        if (c.class_name == kMB + "Joints.Spherical") CHECK(c.value("enforceStates") == "true");
        if (c.class_name == kMB + "Parts.Body" && c.description.find("'Drone'") != std::string::npos) {
            // Free body: absolute states from the CAD pose, at rest.
            CHECK(c.value("enforceStates") == "true");
            CHECK(c.value("angles_fixed") == "true");
            CHECK(c.value("w_0_fixed") == "true");
            REQUIRE(c.modifier("v_0"));
            CHECK(c.modifier("v_0")->nested == "each fixed = true");
        }
    }
    // One note for the limits, naming the joint.
    size_t limit_notes = 0;
    for (const Finding& f : p.notes)
        if (f.code == MBX_FINDING_EXPORT_APPROXIMATION && f.message.find("limits") != std::string::npos) {
            ++limit_notes;
            CHECK(f.message.find("'slide'") != std::string::npos);
        }
    CHECK(limit_notes == 1);
}

TEST_CASE("modelica: a planar loop cut at a prismatic joint moves the loop constraint to a revolute") {
    auto t = xtest::translate(slider_crank());
    const Mechanism& m = *t->mechanism;
    REQUIRE(m.loops.size() == 1);
    REQUIRE(m.loops[0].planar);
    REQUIRE(m.joints[size_t(m.loops[0].cut_joint)].type == MBX_PRIMITIVE_PRISMATIC);
    const mtest::Package p = mtest::export_package(*t, named("slider crank"));
    CHECK(p.name == "Slider_crank");
    mtest::check_package(*t, p);
    CHECK(mtest::count_class(p.mechanics, kMB + "Joints.RevolutePlanarLoopConstraint") == 1);
    CHECK(mtest::count_class(p.mechanics, kMB + "Joints.Revolute") == 2);
    // The prismatic cut stays an ordinary prismatic without flanges.
    CHECK(mtest::count_class(p.mechanics, kMB + "Joints.Prismatic") == 1);
    CHECK(mtest::count_class(p.mechanics, "Modelica.Mechanics.Translational.Interfaces.Flange_a") == 0);
    CHECK(mtest::count_class(p.mechanics, "Modelica.Mechanics.Rotational.Interfaces.Flange_a") == 2 * 2);
    CHECK(has_note(p.notes, MBX_FINDING_EXPORT_APPROXIMATION, "RevolutePlanarLoopConstraint and has no axis flange"));
    // Regression only (see the fourbar's golden file below); check_package above is the independent check.
    check_golden("modelica_slider_crank_Mechanics.mo", p.mechanics_text);
}

TEST_CASE("modelica: awkward CAD names give valid, unique identifiers and escaped descriptions") {
    auto t = xtest::translate(awkward_names());
    const mtest::Package p = mtest::export_package(*t, named("3d \"model\" end"));
    CHECK(p.name == "_3d_model_end");
    mtest::check_package(*t, p, false);  // includes identifier validity and uniqueness

    std::set<std::string> lower;
    for (const msl::Component& c : p.mechanics.components) {
        std::string l = c.name;
        for (char& ch : l) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        CHECK_MESSAGE(lower.insert(l).second, "names differ only in case: " << c.name);
        CHECK(c.name != "Modelica");
        CHECK(c.name != p.name);
        if (c.name == "world") CHECK(c.class_name == kMB + "World");
    }
    // The parser unescapes descriptions: the CAD name comes back verbatim.
    bool quoted = false;
    for (const msl::Component& c : p.mechanics.components)
        quoted = quoted || c.description.find("body 'a \"quoted\" \\ name'") != std::string::npos;
    CHECK(quoted);
    for (const char* keyword : {"end", "model", "connect", "Real"}) CHECK_FALSE(p.mechanics.find(keyword));
}

TEST_CASE("modelica: package names are capitalised identifiers that never hide the library") {
    CHECK(modelica_package_name("fourbar") == "Fourbar");
    CHECK(modelica_package_name("model") == "Model");
    CHECK(modelica_package_name("Modelica") == "Modelica_model");
    CHECK(modelica_package_name("end") == "End");
    CHECK(modelica_package_name("") == "Model");
    CHECK(modelica_package_name("ergo cub 1.0") == "Ergo_cub_1_0");
    CHECK(modelica_string("a\"b\\c\nd") == "\"a\\\"b\\\\c\\nd\"");
}

TEST_CASE("modelica: re-export is byte-identical and keeps the user's UserModel.mo") {
    mbx_test::TempDir dir("mbx_modelica");
    auto t = xtest::translate_builtin("six_axis_arm");
    const ExportSettings s = named("six_axis_arm");
    const OutputFiles first = xtest::export_to(*t, dir, MBX_EXPORT_MODELICA, s);

    // A second translation of the same input exports the same bytes.
    auto again = xtest::translate_builtin("six_axis_arm");
    const OutputFiles second = xtest::export_to(*again, dir, MBX_EXPORT_MODELICA, s);
    REQUIRE(first.size() == second.size());
    for (size_t i = 0; i < first.size(); ++i) {
        CHECK(first[i].path == second[i].path);
        CHECK_MESSAGE(first[i].contents == second[i].contents, first[i].path << " differs between exports");
    }

    const fs::path package = dir.path / "modelica" / "Six_axis_arm";
    const fs::path user = package / "UserModel.mo";
    const fs::path mechanics = package / "Mechanics.mo";
    REQUIRE(fs::exists(user));
    REQUIRE(fs::exists(mechanics));
    const std::string generated_user = mbx_test::read_file(user);
    const std::string edited_user = generated_user + "// my edit\n";
    std::ofstream(user, std::ios::binary) << edited_user;
    std::ofstream(mechanics, std::ios::binary) << "tampered";
    xtest::export_to(*t, dir, MBX_EXPORT_MODELICA, s);
    CHECK(mbx_test::read_file(user) == edited_user);
    CHECK(mbx_test::read_file(mechanics) == xtest::find_file(first, "modelica/Six_axis_arm/Mechanics.mo")->contents);
}

TEST_CASE("modelica: the golden files' comparison forgives a number's last digit, nothing else") {
    CHECK(same_text_but_rounding("I_11 = 1.4833333333333332e-07,", "I_11 = 1.4833333333333335e-07,"));
    CHECK_FALSE(same_text_but_rounding("I_11 = 1.48333e-07,", "I_11 = 1.48334e-07,"));
    CHECK_FALSE(same_text_but_rounding("I_11 = 1.5,", "I_22 = 1.5,"));
    CHECK_FALSE(same_text_but_rounding("n = {0, 0, -1}", "n = {0, 0, 1}"));
    CHECK_FALSE(same_text_but_rounding("m = 0.5, r = {1.0, 2.0}", "m = 0.5, r = {1.0}"));
}

// A regression check only: the golden file is what this exporter wrote when
// it was last reviewed. What the text means is checked independently beside
// it (check_package: every class against the MSL 4.0 sources, the masses, and
// the frame chain evaluated from the Modelica text against the mechanism).
TEST_CASE("modelica (regression): fourbar Mechanics.mo is unchanged from its reviewed golden file") {
    auto t = xtest::translate_builtin("fourbar");
    const mtest::Package p = mtest::export_package(*t, named("fourbar"));
    mtest::check_package(*t, p);
    check_golden("modelica_fourbar_Mechanics.mo", p.mechanics_text);
}

TEST_CASE("modelica: real PMXML files (ergoCub, ironCub, legs mechanisms) pass the MSL and pose checks") {
    const std::string data = pmxml_dir();
    if (data.empty()) return;
    struct Case {
        std::string xml;
        bool meshes;
    };
    const std::vector<Case> cases = {{data + "/ergocub/SIM_ERGOCUB_1-0.xml", true},
                                     {data + "/ironcub/IRONCUB-MK1_SIM_MODEL.xml", false},
                                     {data + "/ironcub/IRONCUB-MK1_1_SIM_MODEL.xml", false},
                                     {data + "/legs_mechanism_2014/LEGS_MECHANISM.xml", false},
                                     {data + "/legs_mechanism_2015/LEGS_MECHANISM.xml", false}};
    for (const Case& c : cases) {
        CAPTURE(c.xml);
        mbx_files::FileAdapterOptions options;
        if (c.meshes) options.mesh_dirs.push_back(data + "/ergocub/meshes/simmechanics");
        auto t = xtest::translate_file(c.xml, options);
        const Mechanism& m = *t->mechanism;
        const mtest::Package p = mtest::export_package(*t, named(fs::path(c.xml).stem().string()));
        mtest::check_package(*t, p);
        if (c.meshes) CHECK(p.stems.size() > 50);
        bool limits = false;
        for (const Joint& j : m.joints) limits = limits || j.has_limits;
        size_t limit_notes = 0;
        for (const Finding& f : p.notes)
            limit_notes += f.code == MBX_FINDING_EXPORT_APPROXIMATION && f.message.find("no position limits") != std::string::npos;
        CHECK(limit_notes == (limits ? 1u : 0u));
        MESSAGE(fs::path(c.xml).filename().string()
                << ": " << m.bodies.size() << " bodies, " << m.joints.size() << " joints, " << m.loops.size()
                << " loops, " << p.mechanics.components.size() << " components");
    }
}

TEST_CASE("modelica checker: rejects what a Modelica tool would reject") {
    // The checker must be able to fail: each flaw below is one a tool reports.
    const std::string text =
        "within P;\n"
        "model Mechanics\n"
        "  inner Modelica.Mechanics.MultiBody.World world;\n"
        "  Modelica.Mechanics.MultiBody.Parts.Bodyy a;\n"                                  // unknown class
        "  Modelica.Mechanics.MultiBody.Parts.Body b(mass = 1);\n"                         // undeclared modifier
        "  Modelica.Mechanics.MultiBody.Joints.Revolute r(n = {0, 0, 1});\n"               // flange not enabled
        "  Modelica.Mechanics.MultiBody.Joints.Prismatic p(useAxisFlange = true);\n"
        "  Modelica.Mechanics.Rotational.Interfaces.Flange_a f;\n"
        "  Modelica.Mechanics.MultiBody.Parts.FixedTranslation unused(r = {1, 0, 0});\n"   // never connected
        "  Modelica.Mechanics.MultiBody.Parts.FixedTranslation end(r = {1, 0, 0});\n"      // keyword
        "equation\n"
        "  connect(world.frame_b, r.frame_a);\n"
        "  connect(r.frame_b, b.frame_a);\n"
        "  connect(r.axis, f);\n"
        "  connect(p.axis, f);\n"                                                           // translational to rotational
        "  connect(world.frame_b, p.frame_a);\n"
        "  connect(p.frame_b, ghost.frame_a);\n"                                            // undeclared
        "  connect(b.frame_a, end.frame_a);\n"
        "end Mechanics;\n";
    const msl::Model model = msl::parse_model(text);
    CHECK(model.errors.empty());
    const std::vector<std::string> errors = msl::check_model(mtest::msl_index(), model);
    std::string all;
    for (const std::string& e : errors) all += e + "\n";
    CAPTURE(all);
    CHECK(all.find("Parts.Bodyy is not in MSL 4.0") != std::string::npos);
    CHECK(all.find("declares no element mass") != std::string::npos);
    CHECK(all.find("r.axis is connected but r does not set useAxisFlange = true") != std::string::npos);
    CHECK(all.find("connect(p.axis, f) joins different connector kinds") != std::string::npos);
    CHECK(all.find("connect uses undeclared ghost") != std::string::npos);
    CHECK(all.find("unused is declared but not connected") != std::string::npos);
    CHECK(all.find("invalid identifier 'end'") != std::string::npos);
    CHECK(all.find("end.frame_b is not connected") != std::string::npos);
    CHECK(all.find("world") == std::string::npos);  // inner world is used implicitly

    // Frame composition: a fixed rotation read back as MSL defines it.
    const msl::Model rotated = msl::parse_model(
        "model M\n"
        "  inner Modelica.Mechanics.MultiBody.World world;\n"
        "  Modelica.Mechanics.MultiBody.Parts.FixedRotation f(r = {1, 2, 3}, rotationType = "
        "Modelica.Mechanics.MultiBody.Types.RotationTypes.TwoAxesVectors, n_x = {0, 1, 0}, n_y = {-1, 0, 0});\n"
        "  Modelica.Mechanics.MultiBody.Parts.FixedTranslation g(r = {1, 0, 0});\n"
        "equation\n"
        "  connect(world.frame_b, f.frame_a);\n"
        "  connect(f.frame_b, g.frame_a);\n"
        "end M;\n");
    const msl::FramePoses poses = msl::compose_frames(rotated);
    CHECK(poses.conflicts.empty());
    REQUIRE(poses.pose.count("g.frame_b"));
    // frame_b of f is turned +90 degrees about z: its x axis is the world's y.
    CHECK((poses.pose.at("g.frame_b").position - Vec3(1, 3, 3)).norm() < 1e-15);
}
}  // namespace MBX_UNITY_ID
