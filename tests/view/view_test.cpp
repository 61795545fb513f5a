// The view page (view/): the poses it plays are the simulator's forward
// kinematics, so at the CAD configuration they must be the bodies' CAD poses
// (which the glTF nodes carry, from the host) and a turn of the first joint
// must turn every body rigidly about that joint's CAD axis; the page must
// carry everything it needs (no fetch), and a trajectory that does not fit
// the model must be refused by name.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>

#include "core/finding.h"
#include "tests/export/export_fixture.h"
#include "core/mechatronics/contact_description.h"
#include "export/mesh/mesh_export.h"
#include "sim/build_model.h"
#include "sim/simulation.h"
#include "view/view_page.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

std::unique_ptr<xtest::Translated> arm() {
    mbx_files::FileAdapterOptions o;
    o.shapes_path = std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm_a.wrl";
    return xtest::translate_file(std::string(MBX_SAMPLES_DIR) + "/five_axis_arm/five_axis_arm.xml", o);
}

Pose pose_at(const PosedTrajectory& p, size_t frame, size_t node) {
    const double* x = &p.poses[(frame * p.nodes.size() + node) * 7];
    Pose out;
    out.position = Vec3(x[0], x[1], x[2]);
    out.rotation = Eigen::Quaterniond(x[3], x[4], x[5], x[6]).toRotationMatrix();
    return out;
}

int body_of_stem(ExportModel& model, const std::string& stem) {
    for (size_t b = 0; b < model.mechanism().bodies.size(); ++b)
        if (model.has_mesh(int(b)) && model.mesh_stem(int(b)) == stem) return int(b);
    return -1;
}

std::string decode_base64(const std::string& s) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        return c == '+' ? 62 : c == '/' ? 63 : -1;
    };
    std::string out;
    unsigned buffer = 0;
    int bits = 0;
    for (char c : s) {
        const int v = value(c);
        if (v < 0) break;
        buffer = buffer << 6 | unsigned(v), bits += 6;
        if (bits >= 8) bits -= 8, out += char(buffer >> bits & 0xff);
    }
    return out;
}

}  // namespace

TEST_CASE("view: at the CAD configuration every node is posed where the CAD put its body") {
    for (const char* name : {"five_axis_arm", "fourbar"}) {
        CAPTURE(name);
        auto t = std::string(name) == "fourbar" ? xtest::translate_builtin("fourbar") : arm();
        ExportModel model = xtest::export_model(*t);
        const sim::Model sim_model = sim::build_model(*t->mechanism);
        const std::vector<double> q(sim_model.q_reference.data(), sim_model.q_reference.data() + sim_model.nq);
        const PosedTrajectory p = pose_configuration(model, q);
        if (std::string(name) == "five_axis_arm") CHECK(p.nodes.size() == 5);
        for (size_t k = 0; k < p.nodes.size(); ++k) {
            const int body = body_of_stem(model, p.nodes[k]);
            REQUIRE(body > 0);
            const Pose expected = t->mechanism->bodies[size_t(body)].pose, got = pose_at(p, 0, k);
            CHECK((got.position - expected.position).norm() < 1e-9);
            CHECK((got.rotation - expected.rotation).norm() < 1e-9);
        }
    }
}

TEST_CASE("view: turning the waist turns every arm body rigidly about the waist's CAD axis") {
    auto t = arm();
    ExportModel model = xtest::export_model(*t);
    const sim::Model sim_model = sim::build_model(*t->mechanism);
    const sim::JointT<double>& waist = sim_model.joints[0];
    REQUIRE(waist.kind == sim::JointKind::Revolute);
    const Joint& cad = t->mechanism->joints[size_t(waist.source)];
    std::vector<double> q(sim_model.q_reference.data(), sim_model.q_reference.data() + sim_model.nq);
    const double turn = 0.7;
    q[size_t(waist.q_index)] += turn;
    const PosedTrajectory p = pose_configuration(model, q);
    // Positive coordinate: the child turns about the axis as the host gave it,
    // unless the tree runs the CAD joint backwards.
    Pose rotate;
    rotate.rotation = Eigen::AngleAxisd(cad.reversed ? -turn : turn, cad.axis).toRotationMatrix();
    rotate.position = cad.frame.position - rotate.rotation * cad.frame.position;
    for (size_t k = 0; k < p.nodes.size(); ++k) {
        const int body = body_of_stem(model, p.nodes[k]);
        const Pose expected = rotate * t->mechanism->bodies[size_t(body)].pose, got = pose_at(p, 0, k);
        CHECK((got.position - expected.position).norm() < 1e-9);
        CHECK((got.rotation - expected.rotation).norm() < 1e-9);
    }
}

TEST_CASE("view: the page carries three.js, the scene and the motion, and fetches nothing") {
    auto t = arm();
    ExportModel model = xtest::export_model(*t);
    const sim::Model sim_model = sim::build_model(*t->mechanism);
    // A trajectory as `mbx simulate` writes it: the waist sweeping 0 -> 1 rad.
    const std::vector<std::string> columns = sim::trajectory_columns(sim_model);
    const std::string dir = "view_test_tmp";
    std::filesystem::create_directories(dir);
    {
        std::ofstream csv(dir + "/trajectory.csv");
        for (size_t c = 0; c < columns.size(); ++c) csv << (c ? "," : "") << columns[c];
        csv << "\n";
        for (int r = 0; r <= 10; ++r) {
            csv << r * 0.1;
            for (size_t c = 1; c < columns.size(); ++c) csv << "," << (c == 1 ? r * 0.1 : 0.0);
            csv << "\n";
        }
    }
    const OutputFiles files = view_files(model, dir + "/trajectory.csv");
    REQUIRE(files.size() == 1);
    const std::string& page = files[0].contents;
    CHECK(files[0].path == "view.html");
    // Self-contained: no script, style or image from elsewhere.
    CHECK(page.find("<script src") == std::string::npos);
    CHECK(page.find("<link") == std::string::npos);
    CHECK(page.find("THREE.GLTFLoader") != std::string::npos);
    CHECK(page.find("OrbitControls") != std::string::npos);
    // The scene inlined is the scene export's, byte for byte.
    OutputFiles scene;
    export_scene(model, scene);
    const size_t at = page.find("const MBX_SCENE = \"");
    REQUIRE(at != std::string::npos);
    const size_t from = at + 19, to = page.find('"', from);
    CHECK(decode_base64(page.substr(from, to - from)) == scene.front().contents);
    // Eleven frames of five nodes; the last one's waist at 1 rad.
    const PosedTrajectory p = pose_trajectory(model, dir + "/trajectory.csv");
    CHECK(p.frames() == 11);
    CHECK(p.poses.size() == 11 * 5 * 7);
    CHECK(page.find("\"times\":[0,0.1,0.2") != std::string::npos);

    // Refusals, named.
    std::ofstream(dir + "/short.csv") << "time,nothing\n0,1\n";
    CHECK_THROWS_WITH_AS(pose_trajectory(model, dir + "/short.csv"), doctest::Contains(("short.csv: no column '" + columns[1] + "'").c_str()), Error);
    {
        std::ofstream csv(dir + "/back.csv");
        for (size_t c = 0; c < columns.size(); ++c) csv << (c ? "," : "") << columns[c];
        csv << "\n";
        for (double time : {0.0, 0.2, 0.1}) {
            csv << time;
            for (size_t c = 1; c < columns.size(); ++c) csv << ",0";
            csv << "\n";
        }
    }
    CHECK_THROWS_WITH_AS(pose_trajectory(model, dir + "/back.csv"), doctest::Contains("back.csv:4: time does not increase"), Error);
    std::filesystem::remove_all(dir);
}

TEST_CASE("view: the page holds the collision shapes behind a checkbox, only when the model has them") {
    auto t = arm();
    {
        ExportModel plain = xtest::export_model(*t);
        const std::string page = view_files(plain, "").front().contents;
        CHECK(page.find("id=\"mbx-collision\"") == std::string::npos);
        CHECK(page.find("const MBX_COLLISION = [];") != std::string::npos);
    }
    // The default hulls: one per moving part with a mesh.
    ContactSpec spec;
    CollisionSpec hulls;
    hulls.body = "*", hulls.kind = CollisionKind::Hull;
    spec.shapes.push_back(hulls);
    std::vector<LibraryError> errors;
    ExportSettings settings;
    settings.contact = resolve_contact(spec, *t->mechanism, errors);
    REQUIRE(errors.empty());
    REQUIRE(settings.contact.shapes.size() >= 4);
    ExportModel model = xtest::export_model(*t, settings);
    const std::string page = view_files(model, "").front().contents;
    CHECK(page.find("<input type=\"checkbox\" id=\"mbx-collision\">") != std::string::npos);
    // The scene inlined is the scene export with its collision shapes.
    OutputFiles scene;
    export_scene(model, scene, true);
    const size_t at = page.find("const MBX_SCENE = \"");
    REQUIRE(at != std::string::npos);
    const size_t from = at + 19, to = page.find('"', from);
    const std::string glb = decode_base64(page.substr(from, to - from));
    CHECK(glb == scene.front().contents);
    // Every shape listed for the toggle, and a node of that name in the glTF.
    const size_t list = page.find("const MBX_COLLISION = [");
    REQUIRE(list != std::string::npos);
    const std::string names = page.substr(list, page.find("];", list) - list);
    size_t listed = 0;
    for (const ResolvedCollision& c : settings.contact.shapes) {
        std::string node = "collision_";
        for (char ch : c.name) node += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
        CAPTURE(node);
        CHECK(names.find("\"" + node + "\"") != std::string::npos);
        CHECK(glb.find("\"name\":\"" + node + "\"") != std::string::npos);
        ++listed;
    }
    CHECK(listed == settings.contact.shapes.size());
}
}  // namespace MBX_UNITY_ID
