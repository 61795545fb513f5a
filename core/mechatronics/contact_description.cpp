#include "core/mechatronics/contact_description.h"

#include <pugixml.hpp>

#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "core/mechatronics/xml_text.h"
#include "core/translator/mechanism.h"

namespace mbx {

namespace {

const std::set<std::string> kCollisionAttributes = {"body", "name", "shape", "radius", "length", "size", "xyz",
                                                    "rpy", "unit", "material", "group", "mask"};
const std::set<std::string> kContactAttributes = {
    "a", "b", "normal", "stiffness", "exponent", "damping", "restitution", "impact_speed", "mu_static", "mu_kinetic",
    "mu", "friction", "friction_stiffness", "friction_damping", "stick_speed", "smoothing_speed"};

class ElementReader {
public:
    ElementReader(const pugi::xml_node& n, const XmlLines& lines, const std::string& file,
                  std::vector<LibraryError>& errors)
        : n_(n), lines_(lines), file_(file), errors_(errors) {}

    void error(const std::string& who, std::string message) {
        errors_.push_back({file_, lines_.line(n_), who, std::move(message)});
        bad = true;
    }
    void check(const std::set<std::string>& allowed, const std::string& who) {
        for (pugi::xml_attribute a : n_.attributes())
            if (!allowed.count(a.name())) error(who, "unknown attribute '" + std::string(a.name()) + "' on <" + n_.name() + ">");
        for (pugi::xml_node c : n_.children())
            if (c.type() == pugi::node_element)
                error(who, "unknown element <" + std::string(c.name()) + "> in <" + n_.name() + "> (it takes attributes only)");
    }
    double number(const char* name, double fallback, const std::string& who) {
        const pugi::xml_attribute a = n_.attribute(name);
        if (!a) return fallback;
        double v = 0;
        if (!parse_xml_number(a.as_string(), v)) {
            error(who, std::string(name) + " = '" + a.as_string() + "' is not a number");
            return fallback;
        }
        return v;
    }
    Vec3 triple(const char* name, const std::string& who) {
        const pugi::xml_attribute a = n_.attribute(name);
        if (!a) return Vec3::Zero();
        std::istringstream words(a.as_string());
        std::vector<std::string> parts;
        for (std::string w; words >> w;) parts.push_back(w);
        Vec3 v = Vec3::Zero();
        bool ok = parts.size() == 3;
        for (size_t k = 0; ok && k < 3; ++k) ok = parse_xml_number(parts[k], v[int(k)]);
        if (!ok) error(who, std::string(name) + " = '" + a.as_string() + "' is not three numbers");
        return v;
    }
    unsigned bits(const char* name, unsigned fallback, const std::string& who) {
        const pugi::xml_attribute a = n_.attribute(name);
        if (!a) return fallback;
        const double v = number(name, -1, who);
        if (!(v >= 0 && v <= 4294967295.0 && v == std::floor(v))) {
            error(who, std::string(name) + " must be a whole number from 0 to 2^32 - 1 (collision filter bits)");
            return fallback;
        }
        return unsigned(v);
    }

    bool bad = false;

private:
    const pugi::xml_node& n_;
    const XmlLines& lines_;
    const std::string& file_;
    std::vector<LibraryError>& errors_;
};

bool parse_kind(const std::string& word, CollisionKind& out) {
    static const std::map<std::string, CollisionKind> kinds = {
        {"sphere", CollisionKind::Sphere}, {"box", CollisionKind::Box},     {"cylinder", CollisionKind::Cylinder},
        {"capsule", CollisionKind::Capsule}, {"plane", CollisionKind::Plane}, {"hull", CollisionKind::Hull}};
    const auto it = kinds.find(word);
    if (it == kinds.end()) return false;
    out = it->second;
    return true;
}

void read_collision(const pugi::xml_node& n, ElementReader& r, const std::string& file, int line, ContactSpec& spec) {
    CollisionSpec s;
    s.file = file, s.line = line;
    s.body = n.attribute("body").as_string();
    s.name = n.attribute("name").as_string();
    const std::string who = !s.name.empty() ? s.name : !s.body.empty() ? s.body : "<collision>";
    r.check(kCollisionAttributes, who);
    if (s.body.empty()) r.error(who, "collision has no body (a CAD part or body id, or \"world\")");
    const std::string kind = n.attribute("shape").as_string();
    if (kind.empty()) r.error(who, "collision has no shape (sphere, box, cylinder, capsule, plane or hull)");
    else if (!parse_kind(kind, s.kind)) r.error(who, "shape '" + kind + "' is not sphere, box, cylinder, capsule, plane or hull");
    // Sizes and positions in `unit` (m or mm), angles in rad or deg.
    const std::string unit = n.attribute("unit").as_string();
    double length_unit = 1, angle_unit = 1;
    if (unit == "mm") length_unit = 1e-3;
    else if (unit == "deg") angle_unit = M_PI / 180;
    else if (unit == "mm,deg" || unit == "deg,mm") length_unit = 1e-3, angle_unit = M_PI / 180;
    else if (!unit.empty() && unit != "m" && unit != "rad" && unit != "m,rad" && unit != "rad,m" && unit != "m,deg" &&
             unit != "deg,m" && unit != "mm,rad" && unit != "rad,mm")
        r.error(who, "unit '" + unit + "' is not m or mm (lengths) with rad or deg (angles), e.g. \"mm,deg\"");
    if (unit == "m,deg" || unit == "deg,m") angle_unit = M_PI / 180;
    if (unit == "mm,rad" || unit == "rad,mm") length_unit = 1e-3;
    s.radius = r.number("radius", 0, who) * length_unit;
    s.length = r.number("length", 0, who) * length_unit;
    s.size = r.triple("size", who) * length_unit;
    s.position = r.triple("xyz", who) * length_unit;
    s.rpy = r.triple("rpy", who) * angle_unit;
    if (n.attribute("material")) s.material = n.attribute("material").as_string();
    if (s.material.empty()) r.error(who, "material is empty");
    s.group = r.bits("group", 1, who);
    s.mask = r.bits("mask", ~0u, who);
    // Attributes the kind does not use are most likely a mistake (radius on a box).
    auto unused = [&](const char* a) {
        if (n.attribute(a)) r.error(who, std::string("a ") + kind + " has no " + a);
    };
    if (s.kind != CollisionKind::Sphere && s.kind != CollisionKind::Cylinder && s.kind != CollisionKind::Capsule) unused("radius");
    if (s.kind != CollisionKind::Cylinder && s.kind != CollisionKind::Capsule) unused("length");
    if (s.kind != CollisionKind::Box) unused("size");
    if (!r.bad)
        for (const std::string& p : collision_problems(s)) r.error(who, p);
    if (!r.bad) spec.shapes.push_back(std::move(s));
}

void read_contact(const pugi::xml_node& n, ElementReader& r, const std::string& file, int line, ContactSpec& spec) {
    ContactMaterialSpec m;
    m.file = file, m.line = line;
    m.a = n.attribute("a").as_string();
    m.b = n.attribute("b").as_string();
    const std::string who = m.a.empty() && m.b.empty() ? "<contact>" : m.a + "/" + m.b;
    r.check(kContactAttributes, who);
    if (m.a.empty() != m.b.empty()) r.error(who, "a contact names both materials a and b, or neither (the default)");
    const std::string law = n.attribute("normal").as_string("hunt_crossley");
    if (law == "hunt_crossley") m.normal = ContactNormalLaw::HuntCrossley;
    else if (law == "spring_damper") m.normal = ContactNormalLaw::SpringDamper;
    else if (law == "spring") m.normal = ContactNormalLaw::Spring;
    else r.error(who, "normal law '" + law + "' is not hunt_crossley, spring_damper or spring");
    m.exponent = r.number("exponent", m.normal == ContactNormalLaw::HuntCrossley ? 1.5 : 1, who);
    if (!n.attribute("stiffness")) r.error(who, "contact needs a stiffness");
    m.stiffness = r.number("stiffness", m.stiffness, who);
    const bool damping = bool(n.attribute("damping")), restitution = bool(n.attribute("restitution"));
    if (damping && restitution) r.error(who, "give damping or restitution, not both");
    m.damping = r.number("damping", 0, who);
    m.use_restitution = restitution;
    m.restitution = r.number("restitution", 1, who);
    m.impact_speed = r.number("impact_speed", 1, who);
    if (n.attribute("impact_speed") && !restitution) r.error(who, "impact_speed goes with restitution");
    if (m.normal == ContactNormalLaw::Spring && (damping || restitution))
        r.error(who, "the spring law has no damping (use spring_damper or hunt_crossley)");
    if (n.attribute("mu") && (n.attribute("mu_static") || n.attribute("mu_kinetic")))
        r.error(who, "give mu (static = kinetic) or mu_static and mu_kinetic");
    if (n.attribute("mu")) m.mu_static = m.mu_kinetic = r.number("mu", 0, who);
    m.mu_static = r.number("mu_static", m.mu_static, who);
    m.mu_kinetic = r.number("mu_kinetic", n.attribute("mu_static") && !n.attribute("mu_kinetic") ? m.mu_static : m.mu_kinetic, who);
    const std::string friction = n.attribute("friction").as_string("spring");
    if (friction == "spring") m.friction = ContactFrictionLaw::Spring;
    else if (friction == "regularised" || friction == "regularized") m.friction = ContactFrictionLaw::Regularised;
    else r.error(who, "friction '" + friction + "' is not spring or regularised");
    m.friction_stiffness = r.number("friction_stiffness", m.friction_stiffness, who);
    m.friction_damping = r.number("friction_damping", 0, who);
    m.stick_speed = r.number("stick_speed", m.stick_speed, who);
    m.smoothing_speed = r.number("smoothing_speed", m.smoothing_speed, who);
    if (m.friction == ContactFrictionLaw::Regularised &&
        (n.attribute("friction_stiffness") || n.attribute("friction_damping") || n.attribute("stick_speed")))
        r.error(who, "friction_stiffness, friction_damping and stick_speed belong to friction=\"spring\"");
    if (m.friction == ContactFrictionLaw::Spring && n.attribute("smoothing_speed"))
        r.error(who, "smoothing_speed belongs to friction=\"regularised\"");
    for (const std::string& p : contact_material_problems(m)) r.error(who, p);
    for (const ContactMaterialSpec& other : spec.materials)
        if ((other.a == m.a && other.b == m.b) || (other.a == m.b && other.b == m.a))
            r.error(who, (m.a.empty() ? std::string("a second default <contact>")
                                      : "a second <contact> for materials " + m.a + " and " + m.b) +
                             " (the first is at line " + std::to_string(other.line) + ")");
    if (!r.bad) spec.materials.push_back(std::move(m));
}

}  // namespace

Mat3 rotation_from_rpy(const Vec3& rpy) {
    return (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
            Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
        .toRotationMatrix();
}

std::vector<std::string> collision_problems(const CollisionSpec& s) {
    std::vector<std::string> out;
    auto positive = [&](double v, const char* what) {
        if (!(std::isfinite(v) && v > 0)) out.push_back(std::string(what) + " must be a positive number");
    };
    switch (s.kind) {
    case CollisionKind::Sphere: positive(s.radius, "radius"); break;
    case CollisionKind::Cylinder:
    case CollisionKind::Capsule: positive(s.radius, "radius"), positive(s.length, "length"); break;
    case CollisionKind::Box:
        if (!(s.size.allFinite() && s.size.minCoeff() > 0)) out.push_back("size must be three positive side lengths");
        break;
    case CollisionKind::Plane:
        if (s.body == "*") out.push_back("a plane belongs to the world or the ground");
        break;
    case CollisionKind::Hull:
        if (s.body == "world") out.push_back("the world has no mesh to wrap in a hull");
        break;
    }
    if (s.body == "*" && s.kind != CollisionKind::Hull) out.push_back("body=\"*\" (every moving body) takes shape=\"hull\" only");
    if (!s.position.allFinite() || !s.rpy.allFinite()) out.push_back("the pose is not finite");
    if (s.kind == CollisionKind::Hull && (!s.position.isZero() || !s.rpy.isZero()))
        out.push_back("a hull sits where its part's mesh is: it takes no xyz or rpy");
    return out;
}

std::vector<std::string> contact_material_problems(const ContactMaterialSpec& m) {
    std::vector<std::string> out;
    if (!(std::isfinite(m.stiffness) && m.stiffness > 0)) out.push_back("stiffness must be positive");
    if (!(std::isfinite(m.exponent) && m.exponent >= 1 && m.exponent <= 3)) out.push_back("exponent must be within [1, 3]");
    if (!(std::isfinite(m.damping) && m.damping >= 0)) out.push_back("damping must not be negative");
    if (m.use_restitution) {
        if (!(std::isfinite(m.restitution) && m.restitution >= 0 && m.restitution <= 1))
            out.push_back("restitution must be within [0, 1]");
        if (!(std::isfinite(m.impact_speed) && m.impact_speed > 0)) out.push_back("impact_speed must be positive");
    }
    if (!(std::isfinite(m.mu_static) && m.mu_static >= 0)) out.push_back("mu_static must not be negative");
    if (!(std::isfinite(m.mu_kinetic) && m.mu_kinetic >= 0)) out.push_back("mu_kinetic must not be negative");
    if (m.mu_kinetic > m.mu_static) out.push_back("mu_kinetic must not exceed mu_static");
    if (m.friction == ContactFrictionLaw::Spring) {
        if (!(std::isfinite(m.friction_stiffness) && m.friction_stiffness > 0)) out.push_back("friction_stiffness must be positive");
        if (!(std::isfinite(m.friction_damping) && m.friction_damping >= 0)) out.push_back("friction_damping must not be negative");
        if (!(std::isfinite(m.stick_speed) && m.stick_speed > 0)) out.push_back("stick_speed must be positive");
    } else if (!(std::isfinite(m.smoothing_speed) && m.smoothing_speed > 0)) {
        out.push_back("smoothing_speed must be positive");
    }
    return out;
}

void read_contact_element(const pugi::xml_node& n, const XmlLines& lines, const std::string& file, ContactSpec& spec,
                          std::vector<LibraryError>& errors) {
    ElementReader r(n, lines, file, errors);
    const std::string name = n.name();
    if (name == "collision") read_collision(n, r, file, lines.line(n), spec);
    else read_contact(n, r, file, lines.line(n), spec);
}

ResolvedContact resolve_contact(const ContactSpec& spec, const Mechanism& m, std::vector<LibraryError>& errors) {
    ResolvedContact out;
    out.entries = spec.materials;
    // A body answers to its own id and to its parts' ids; each id's frame is
    // that part's (the body's principal part gives the body frame).
    std::map<std::string, int> body_of, part_of;
    for (size_t b = 0; b < m.bodies.size(); ++b) {
        body_of.emplace(m.bodies[b].id, int(b));
        for (int p : m.bodies[b].parts) {
            body_of.emplace(m.assembly.parts[size_t(p)].id, int(b));
            part_of.emplace(m.assembly.parts[size_t(p)].id, p);
        }
    }
    out.materials.push_back("default");
    auto material_id = [&](const std::string& name) {
        for (size_t k = 0; k < out.materials.size(); ++k)
            if (out.materials[k] == name) return int(k);
        out.materials.push_back(name);
        return int(out.materials.size() - 1);
    };
    const Pose ground = m.bodies.empty() ? Pose{} : m.bodies[0].pose;
    std::map<std::string, int> names;
    auto add = [&](const CollisionSpec& s, int body, const Pose& pose, int hull_part, std::string name) {
        if (const int count = names[name]++; count > 0) name += "#" + std::to_string(count);
        out.shapes.push_back({s, name, body, pose, hull_part, s.body == "*"});
        out.shape_material.push_back(material_id(s.material));
    };
    // Bodies a shape of their own is given for: the default leaves them be.
    std::set<int> overridden;
    for (const CollisionSpec& s : spec.shapes)
        if (const auto it = body_of.find(s.body); it != body_of.end() && s.body != "*" && s.body != "world")
            overridden.insert(it->second);
    bool default_done = false;
    for (const CollisionSpec& s : spec.shapes) {
        auto fail = [&](const std::string& message) { errors.push_back({s.file, s.line, s.body, message}); };
        bool problems = false;
        for (const std::string& p : collision_problems(s)) fail(p), problems = true;
        if (problems) continue;
        const std::string kind_name[] = {"sphere", "box", "cylinder", "capsule", "plane", "hull"};
        const Pose local{rotation_from_rpy(s.rpy), s.position};
        if (s.body == "*") {
            // Asked for twice (the file and `--collision hulls`): once is meant.
            if (default_done) continue;
            default_done = true;
            for (size_t b = 1; b < m.bodies.size(); ++b)
                if (m.bodies[b].kind == MBX_RIGID_BODY_DYNAMIC && !overridden.count(int(b)))
                    for (int p : m.bodies[b].parts)
                        add(s, int(b), Pose{}, p, m.assembly.parts[size_t(p)].name + "_hull");
            continue;
        }
        if (s.body == "world") {
            add(s, 0, ground.inverse() * local, -1, s.name.empty() ? "world_" + kind_name[int(s.kind)] : s.name);
            continue;
        }
        const auto it = body_of.find(s.body);
        if (it == body_of.end()) {
            fail("no rigid body or CAD part '" + s.body + "' in the mechanism");
            continue;
        }
        const int b = it->second;
        const RigidBody& body = m.bodies[size_t(b)];
        if (body.kind != MBX_RIGID_BODY_DYNAMIC && b != 0) {
            fail("'" + s.body + "' is a joint node, not a part: collision shapes go on parts");
            continue;
        }
        if (s.kind == CollisionKind::Plane && b != 0) {
            fail("a plane is unbounded: it belongs to the world or the ground, not to the moving body '" + body.name + "'");
            continue;
        }
        const auto part = part_of.find(s.body);
        const Pose part_in_body = part == part_of.end() ? Pose{} : body.pose.inverse() * m.assembly.parts[size_t(part->second)].pose;
        const std::string base = s.name.empty() ? (part == part_of.end() ? body.name : m.assembly.parts[size_t(part->second)].name) + "_" +
                                                      kind_name[int(s.kind)]
                                                : s.name;
        if (s.kind == CollisionKind::Hull) {
            // The body's id is also its principal part's: it asks for a hull
            // per part of the body; another part's id for that part's only.
            const bool whole_body = s.body == body.id;
            if (whole_body) {
                if (body.parts.empty()) fail("body '" + body.name + "' has no CAD part to wrap in a hull");
                for (int p : body.parts) add(s, b, Pose{}, p, s.name.empty() ? m.assembly.parts[size_t(p)].name + "_hull" : s.name);
            } else {
                add(s, b, Pose{}, part->second, base);
            }
            continue;
        }
        add(s, b, part_in_body * local, -1, base);
    }
    const size_t used_materials = out.materials.size();
    auto used = [&](const std::string& name) {
        for (size_t k = 0; k < used_materials; ++k)
            if (out.materials[k] == name) return true;
        return false;
    };
    for (size_t i = 0; i < spec.materials.size(); ++i) {
        const ContactMaterialSpec& c = spec.materials[i];
        bool problems = false;
        // A pair no shape is made of is most likely a misspelt material.
        for (const std::string* name : {&c.a, &c.b})
            if (!name->empty() && !used(*name) && (name == &c.a || c.b != c.a)) {
                errors.push_back({c.file, c.line, c.a + "/" + c.b, "no collision shape is made of material '" + *name + "'"});
                problems = true;
            }
        for (const std::string& p : contact_material_problems(c)) {
            errors.push_back({c.file, c.line, c.a + "/" + c.b, p});
            problems = true;
        }
        if (problems) continue;
        if (c.a.empty()) {
            out.default_entry = int(i);
            continue;
        }
        const int a = material_id(c.a), b = material_id(c.b);
        out.pairs.push_back({std::min(a, b), std::max(a, b), int(i)});
    }
    return out;
}

}  // namespace mbx
