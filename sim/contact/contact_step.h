// Contact as a force element of the simulator (sim::AppliedForces): at every
// dynamics evaluation (each RK4 stage, each CVODE right-hand side) the
// contacts are detected at the evaluated poses, their normal and friction
// forces computed from the laws of normal_force.h and friction.h and applied
// through the bodies' point Jacobians as generalised efforts. The friction
// springs' anchors persist per contact (matched across steps by shape pair
// and feature) and change only when the integrator keeps a step: every
// fixed step, the accurate mode's accepted ones.
#pragma once
#include <map>
#include <tuple>
#include <vector>

#include "sim/contact/detection.h"
#include "sim/contact/friction.h"
#include "sim/contact/normal_force.h"
#include "sim/integrator.h"

namespace mbx::sim::contact {

struct ContactSettings {
    NormalLaw normal;
    FrictionLaw friction;
    bool friction_spring = true;    // false: regularised Coulomb
    double smoothing_speed = 1e-3;  // regularised Coulomb's v_s, m/s
};

// The settings of the contacts between shapes of materials a and b (either
// order); pairs not listed take the world's default settings.
struct MaterialPair {
    int a = 0, b = 0;
    ContactSettings settings;
};

struct ContactForce {
    Contact contact;
    double normal_force = 0;       // N, along the contact normal onto shape b
    Eigen::Vector3d friction;      // N, world, onto shape b
    bool sticking = false;
};

class ContactWorld : public AppliedForces {
public:
    ContactWorld(const Model& m, std::vector<Shape> shapes, ContactSettings settings,
                 std::vector<MaterialPair> pairs = {});

    // One fixed step (Euler or RK4 of `s`) with contact: attaches itself to
    // `d` for the step. For the accurate mode (sim::advance), or to keep it
    // attached, set d.applied_forces = &world.
    void step(const Model& m, Data& d, const IntegratorSettings& s);

    void apply(const Model& m, Data& d) override;
    void step_taken(const Model& m, Data& d) override;

    // What persists between steps (the friction springs' anchors and the
    // kept step's forces), so a caller that rolls its Data back (a failed
    // run) can roll the contact back with it.
    struct Memory;
    Memory memory() const;
    void restore(const Memory& m);

    const std::vector<ContactForce>& forces() const { return forces_; }  // at the last evaluation
    const Scene& scene() const { return scene_; }
    const ContactSettings& settings() const { return settings_; }
    // The settings acting between two shapes of the scene.
    const ContactSettings& settings_for(int shape_a, int shape_b) const;

private:
    using Key = std::tuple<int, int, int>;  // shape a, shape b, feature
    Scene scene_;
    ContactSettings settings_;
    std::map<std::pair<int, int>, ContactSettings> pairs_;  // (lower material, higher)
    bool any_spring_ = false;                               // some pair uses the friction spring
    std::map<Key, FrictionState> anchors_;
    std::vector<Contact> contacts_;
    std::vector<ContactForce> forces_;
    // Forces at data's state (kinematics current) into forces_ and, when
    // given, next anchors; tau gets their generalised efforts.
    void evaluate(const Model& m, const Data& d, Eigen::VectorXd& tau, std::map<Key, FrictionState>* next);
    // The kept step's end state and its efforts: the next step starts there
    // (Euler's one evaluation, RK4's first stage), so they serve again.
    bool cached_ = false;
    double cached_time_ = 0;
    Eigen::VectorXd cached_q_, cached_v_, cached_tau_;
};

struct ContactWorld::Memory {
    std::map<Key, FrictionState> anchors;
    bool cached = false;
    double cached_time = 0;
    Eigen::VectorXd cached_q, cached_v, cached_tau;
};

// Adds the generalised effort of world force f applied at world point p of
// body b to tau (J_p^T f; needs update_positions).
void add_point_force(const Model& m, const Data& d, int body, const Eigen::Vector3d& p, const Eigen::Vector3d& f,
                     Eigen::VectorXd& tau);

}  // namespace mbx::sim::contact
