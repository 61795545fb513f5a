// Collision shapes and contact materials in the description file
// (<collision>, <contact>; docs/mechatronics.md, docs/contact.md): shapes
// keyed by a CAD part or body id (or the world), each with a pose in that
// part's frame, a material and collision filter bits, and per pair of
// materials the normal law and friction. Resolution places every shape in
// its rigid body's frame; the simulator builds its contact world from that
// (sim/contact), the exporters write geoms from it.
#pragma once
#include <string>
#include <vector>

#include "core/math.h"
#include "core/mechatronics/object_library.h"

namespace pugi {
class xml_node;
}

namespace mbx {

struct Mechanism;
class XmlLines;

enum class CollisionKind { Sphere, Box, Cylinder, Capsule, Plane, Hull };

struct CollisionSpec {
    // A rigid body's or CAD part's id, "world", or "*" (hull only): the
    // default, a hull per part of every moving body that no other
    // <collision> names (a body's own shapes replace the default).
    std::string body;
    std::string name;  // "" = made from the part and kind
    CollisionKind kind = CollisionKind::Sphere;
    double radius = 0, length = 0;   // sphere, cylinder, capsule (length along the shape's z)
    Vec3 size = Vec3::Zero();        // box, full side lengths
    Vec3 position = Vec3::Zero();    // in the part's frame (the world's for "world")
    Vec3 rpy = Vec3::Zero();         // roll, pitch, yaw (about fixed x, then y, then z), rad
    std::string material = "default";
    unsigned group = 1, mask = ~0u;
    std::string file;
    int line = 0;
};

enum class ContactNormalLaw { HuntCrossley, SpringDamper, Spring };
enum class ContactFrictionLaw { Spring, Regularised };

struct ContactMaterialSpec {
    std::string a, b;  // materials; both "" = every pair no other entry names
    ContactNormalLaw normal = ContactNormalLaw::HuntCrossley;
    double stiffness = 1e5;  // N/m^exponent
    double exponent = 1.5;
    double damping = 0;      // N s/m (spring_damper) or s/m (Hunt-Crossley's chi)
    bool use_restitution = false;
    double restitution = 1, impact_speed = 1;  // damping solved for this rebound at this impact speed
    double mu_static = 0.5, mu_kinetic = 0.4;
    ContactFrictionLaw friction = ContactFrictionLaw::Spring;
    double friction_stiffness = 1e4, friction_damping = 0;  // N/m, N s/m
    double stick_speed = 1e-3, smoothing_speed = 1e-3;      // m/s
    std::string file;
    int line = 0;
};

struct ContactSpec {
    std::vector<CollisionSpec> shapes;
    std::vector<ContactMaterialSpec> materials;
    bool empty() const { return shapes.empty() && materials.empty(); }
};

// One element of the description file: <collision> or <contact>. Problems go
// to `errors` with file and line; an element with a problem is not added.
void read_contact_element(const pugi::xml_node& n, const XmlLines& lines, const std::string& file, ContactSpec& spec,
                          std::vector<LibraryError>& errors);

// Problems of a material entry's values (also for entries from the C API).
std::vector<std::string> contact_material_problems(const ContactMaterialSpec& m);
// Problems of a shape's sizes, pose and kind, before any mechanism.
std::vector<std::string> collision_problems(const CollisionSpec& s);

// A shape on a rigid body (Mechanism::bodies index; 0 = the ground, whose
// shapes stay in the world), its pose in the body frame. A hull is not
// computed here (the meshes come from the host): `hull_part` names the CAD
// part (Assembly::parts index) whose mesh it wraps.
struct ResolvedCollision {
    CollisionSpec spec;
    std::string name;
    int body = -1;
    Pose pose;  // in the body frame
    int hull_part = -1;
    // From the body="*" default: a part without a mesh is skipped (and
    // noted) rather than refused, as a hull it was asked for by id is.
    bool from_default = false;
};

struct ResolvedContact {
    std::vector<ResolvedCollision> shapes;
    std::vector<std::string> materials;  // index = material id; 0 is "default"
    std::vector<int> shape_material;     // per shape
    // Material pairs by id (a <= b), and the default entry (-1: none given).
    struct Pair {
        int a = 0, b = 0;
        int entry = -1;  // index into entries
    };
    std::vector<Pair> pairs;
    int default_entry = -1;
    std::vector<ContactMaterialSpec> entries;  // the spec's materials
    bool empty() const { return shapes.empty(); }
};

// Resolves against the mechanism. The body="*" default gives a hull per part
// of each moving body no other shape is on (shapes on a body or on any of
// its parts override it). Refuses (with file, line and the id) an
// unknown body or part id, a shape on a joint node, a plane on a moving body,
// a hull of a body without parts, and a pair naming a material no shape is
// made of (most likely a misspelling).
ResolvedContact resolve_contact(const ContactSpec& spec, const Mechanism& m, std::vector<LibraryError>& errors);

// Rotation from roll, pitch, yaw (fixed axes x, y, z: R = Rz(yaw) Ry(pitch) Rx(roll)).
Mat3 rotation_from_rpy(const Vec3& rpy);

}  // namespace mbx
