// mbx's own URDF export read back by mbx's URDF adapter is the same
// mechanism: for every built-in and sample whose joints URDF can hold as
// they are (revolute and prismatic; a spherical joint is written as three
// revolutes, a floating body as a floating joint, each with other
// coordinates), the mass matrix and inverse dynamics at random states equal
// the original's to 1e-12, coordinates matched through the exporter's joint
// names, loops closed again from the cut-joint file beside the URDF.
#include <random>

#include "export/urdf/urdf_layout.h"
#include "host_adapters/urdf/urdf_adapter.h"
#include "sim/build_model.h"
#include "sim/dynamics.h"
#include "tests/export/test_inputs.h"
#include "tests/common/near.h"

namespace MBX_UNITY_ID {

using namespace mbx;

namespace {

// Whether URDF holds every joint of `m` with the same coordinates.
bool urdf_keeps_coordinates(const Mechanism& m) {
    for (const Joint& j : m.joints)
        if (j.type == MBX_PRIMITIVE_SPHERICAL) return false;
    for (const RigidBody& b : m.bodies)
        if (&b != &m.bodies[0] && b.parent_joint < 0) return false;  // a floating body
    return true;
}

}  // namespace

TEST_CASE("urdf round trip: every built-in and sample exported to URDF and read back has the same mass matrix and inverse dynamics") {
    std::vector<simtest::Input> inputs = simtest::builtin_inputs();
    for (const simtest::Input& s : simtest::sample_inputs()) inputs.push_back(s);
    int compared = 0, loops = 0;
    for (const simtest::Input& c : inputs) {
        CAPTURE(c.label);
        auto t = c.open();
        const Mechanism& m = *t->mechanism;
        if (!urdf_keeps_coordinates(m)) continue;
        mbx_test::TempDir dir("mbx_urdf_round_trip");
        ExportSettings settings;
        settings.model_name = "robot";
        xtest::export_to(*t, dir, MBX_EXPORT_URDF, settings);
        const UrdfLayout layout = plan_urdf(xtest::export_model(*t, settings));

        std::shared_ptr<mbx_files::UrdfAdapter> adapter = mbx_files::UrdfAdapter::open(dir.file("urdf/robot.urdf"));
        const auto back = xtest::translate_table(adapter->table(), adapter);
        const sim::Model original = sim::build_model(m), read = sim::build_model(*back->mechanism);
        REQUIRE(read.nv == original.nv);
        REQUIRE(read.nq == original.nq);
        REQUIRE(read.closures.size() == original.closures.size());
        loops += int(original.closures.size());

        // original coordinate -> read-back coordinate, by the exporter's joint names.
        std::vector<int> to_read(size_t(original.nv), -1);
        for (const auto& j : original.joints) {
            if (j.nv() == 0) continue;
            const std::string& name = layout.joint_name[size_t(j.source)];
            int found = -1;
            for (const auto& k : read.joints)
                if (k.constraint_id == name) found = k.v_index;
            CAPTURE(name);
            REQUIRE(found >= 0);
            to_read[size_t(j.v_index)] = found;
        }
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(-1, 1);
        sim::Data a(original), b(read);
        for (int sample = 0; sample < 3; ++sample) {
            Eigen::VectorXd q(original.nq), v(original.nv), acc(original.nv), qb(read.nq), vb(read.nv), accb(read.nv);
            for (int k = 0; k < original.nv; ++k) {
                q[k] = 0.5 * u(rng), v[k] = u(rng), acc[k] = u(rng);
                qb[to_read[size_t(k)]] = q[k], vb[to_read[size_t(k)]] = v[k], accb[to_read[size_t(k)]] = acc[k];
            }
            a.q = q, a.v = v, b.q = qb, b.v = vb;
            sim::update_kinematics(original, a);
            sim::update_kinematics(read, b);
            sim::mass_matrix(original, a);
            sim::mass_matrix(read, b);
            Eigen::VectorXd tau_a, tau_b;
            sim::inverse_dynamics(original, a, acc, tau_a);
            sim::inverse_dynamics(read, b, accb, tau_b);
            const double scale = std::max(1e-300, a.M.cwiseAbs().maxCoeff());
            const double tau_scale = std::max(1e-300, tau_a.cwiseAbs().maxCoeff());
            for (int r = 0; r < original.nv; ++r) {
                CAPTURE(r);
                for (int k = 0; k < original.nv; ++k)
                    CHECK(b.M(to_read[size_t(r)], to_read[size_t(k)]) == mbx_test::within(a.M(r, k), 1e-12 * scale, "the original's"));
                CHECK(tau_b[to_read[size_t(r)]] == mbx_test::within(tau_a[r], 1e-12 * tau_scale, "the original's"));
            }
        }
        ++compared;
    }
    MESSAGE(compared << " mechanisms read back, " << loops << " loops closed from the cut-joint file");
    CHECK(compared >= 8);
    CHECK(loops >= 3);
}

}  // namespace MBX_UNITY_ID
