#include <algorithm>
#include <charconv>
#include <vector>
#include <cmath>

#include "core/report/report.h"
#include "core/report/report_detail.h"
#include "core/report/utf8.h"
#include "core/translator/translate.h"

namespace mbx {
namespace {

using namespace report_detail;

constexpr std::size_t kMaxLine = 119;       // bytes, so always < 120 characters
constexpr std::size_t kMaxTreeLines = 2000;  // beyond this an outline is unreadable anyway
constexpr std::size_t kMaxIndentDepth = 20;  // deeper levels print their depth instead

// Builds the report one line at a time; every line is clipped or wrapped to
// kMaxLine and host strings are sanitized on the way in.
class Text {
public:
    explicit Text(std::size_t reserve) { out_.reserve(reserve); }

    Text& raw(std::string_view s) {
        line_.append(s);
        return *this;
    }
    Text& str(std::string_view s) {  // host text: names, ids, messages
        append_printable_utf8(line_, s);
        return *this;
    }
    Text& quoted(std::string_view s) {
        line_.push_back('\'');
        str(s);
        line_.push_back('\'');
        return *this;
    }
    Text& num(long long v) {
        char buf[24];
        line_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
        return *this;
    }
    // Six significant digits: enough to read, and round-off such as 6e-17 in
    // a unit axis is shown as 0. The JSON report keeps the exact values.
    Text& real(double v) {
        if (std::isnan(v)) return raw("nan");
        if (std::isinf(v)) return raw(v > 0 ? "inf" : "-inf");
        if (std::fabs(v) < 1e-12) v = 0;
        char buf[32];
        line_.append(buf, std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6).ptr);
        return *this;
    }
    Text& vec(const Vec3& v) {
        raw("(").real(v.x()).raw(", ").real(v.y()).raw(", ").real(v.z());
        return raw(")");
    }
    // "1 error" / "2 errors"
    Text& count(std::size_t n, const char* singular, const char* plural) {
        num(static_cast<long long>(n)).raw(" ");
        return raw(n == 1 ? singular : plural);
    }

    // Where the current line stands, for end_line(keep_from).
    std::size_t mark() const { return line_.size(); }

    // Ends the line; if it is too long, the text before `keep_from` is clipped
    // so that what follows it (e.g. a cut marker) survives.
    void end_line(std::size_t keep_from = std::string::npos) {
        if (line_.size() > kMaxLine && keep_from < line_.size() && line_.size() - keep_from < kMaxLine / 2) {
            std::string tail = line_.substr(keep_from);
            line_.resize(keep_from);
            clip_utf8(line_, kMaxLine - tail.size());
            line_.append(tail);
        }
        clip_utf8(line_, kMaxLine);
        out_.append(line_).push_back('\n');
        line_.clear();
    }
    void blank() { out_.push_back('\n'); }
    void discard_line() { line_.clear(); }

    // Ends the line, breaking it at spaces; continuation lines get `indent`.
    void end_wrapped(std::size_t indent) {
        std::string_view rest = line_;
        std::size_t width = kMaxLine;
        while (rest.size() > width) {
            std::size_t cut = rest.rfind(' ', width);
            if (cut == std::string_view::npos || cut <= width / 2) {
                cut = width;  // one long word: break it, on a code point boundary
                while (cut > 0 && (static_cast<unsigned char>(rest[cut]) & 0xC0) == 0x80) --cut;
            }
            out_.append(rest.substr(0, cut)).push_back('\n');
            rest.remove_prefix(cut);
            while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
            out_.append(indent, ' ');
            width = kMaxLine - indent;
        }
        out_.append(rest).push_back('\n');
        line_.clear();
    }

    std::string take() { return std::move(out_); }

private:
    std::string out_;
    std::string line_;
};

const std::string& display_name(const RigidBody& b) { return b.name.empty() ? b.id : b.name; }

void write_header(Text& t, const Mechanism& m, const Counts& c) {
    t.raw("mbx " MBX_VERSION_STRING " translation report").end_line();
    t.raw("Model: ").str(m.assembly.name.empty() ? std::string_view("(unnamed)") : m.assembly.name);
    if (!m.assembly.source.empty()) t.raw("  (source: ").str(m.assembly.source).raw(")");
    t.end_line();
    t.blank();
    t.raw("Summary").end_line();
    const std::size_t cad_parts = m.assembly.cad_part_count();
    t.raw("  ").count(cad_parts, "part", "parts");
    if (cad_parts != m.assembly.parts.size())
        t.raw(" (+").count(m.assembly.parts.size() - cad_parts, "world datum", "world datums").raw(")");
    t.raw(", ");
    t.count(c.dynamic_bodies, "rigid body", "rigid bodies").raw(" + ground, ");
    t.count(c.joint_nodes, "joint node", "joint nodes").end_line();
    t.raw("  ").count(m.joints.size(), "joint", "joints").raw(": revolute ").num(static_cast<long long>(c.revolute));
    t.raw(", prismatic ").num(static_cast<long long>(c.prismatic));
    t.raw(", spherical ").num(static_cast<long long>(c.spherical)).raw("; ");
    t.count(c.cut_joints, "cut joint", "cut joints").raw("; welds merged ").num(m.weld_count).end_line();
    t.raw("  ").count(m.loops.size(), "loop", "loops").raw(" (").num(static_cast<long long>(c.planar_loops));
    t.raw(" planar), collapsed weld loops ").num(m.collapsed_weld_loops);
    t.raw(", floating bodies ").num(m.floating_roots).end_line();
    t.raw("  DoF ").num(m.dof).raw(" (Gruebler ").num(m.gruebler_dof).raw("), redundant constraints ");
    t.num(m.redundant).end_line();
    t.raw("  findings: ").count(c.errors, "error", "errors").raw(", ").count(c.warnings, "warning", "warnings");
    t.raw(", ").num(static_cast<long long>(c.info)).raw(" info; length tolerance ").real(m.length_tolerance);
    t.raw(" m").end_line();
}

void write_body_label(Text& t, const RigidBody& b) {
    t.str(display_name(b));
    switch (b.kind) {
        case MBX_RIGID_BODY_GROUND: t.raw(" [ground]"); break;
        case MBX_RIGID_BODY_JOINT_NODE: t.raw(" [joint node]"); break;
        case MBX_RIGID_BODY_DYNAMIC: t.raw(" [").real(b.mass).raw(" kg]"); break;
    }
}

void write_joint_label(Text& t, const Joint& j) {
    t.raw(joint_type_name(j.type)).raw(" ").quoted(j.name);
    if (j.type == MBX_PRIMITIVE_REVOLUTE || j.type == MBX_PRIMITIVE_PRISMATIC) t.raw(" axis ").vec(j.axis);
    if (j.has_limits) t.raw(" limits [").real(j.lower).raw(", ").real(j.upper).raw("]");
}

// The outline: pre-order from ground, then from each floating root, children
// in joint order. Iterative, since a 100k-link chain would overflow the stack.
class Outline {
public:
    Outline(Text& t, const Mechanism& m) : t_(t), m_(m), by_parent_(joints_by_parent(m, true)) {
        visited_.assign(m.bodies.size(), false);
    }

    void write() {
        t_.raw("Tree (from ground; '->' marks a cut joint, listed under its parent body)").end_line();
        std::vector<bool> is_child(m_.bodies.size(), false);
        for (std::size_t b = 0; b < m_.bodies.size(); ++b)
            for (const int* j = by_parent_.begin(b); j != by_parent_.end(b); ++j) {
                const Joint& joint = m_.joints[static_cast<std::size_t>(*j)];
                if (!joint.cut) is_child[static_cast<std::size_t>(joint.child)] = true;
            }
        if (!m_.bodies.empty()) walk(0);
        for (std::size_t b = 1; b < m_.bodies.size(); ++b)
            if (!is_child[b]) walk(b);
        if (lines_ > kMaxTreeLines) {
            t_.raw("  ... ").num(static_cast<long long>(lines_ - kMaxTreeLines));
            t_.raw(" more (the full tree is in report.json)").end_line();
        }
    }

private:
    struct Item {
        int joint;  // joint leading here, -1 for a root
        std::size_t body;
        std::size_t depth;
    };

    void walk(std::size_t root) {
        if (visited_[root]) return;
        stack_.push_back({-1, root, 0});
        while (!stack_.empty()) {
            const Item item = stack_.back();
            stack_.pop_back();
            const bool cut = item.joint >= 0 && m_.joints[static_cast<std::size_t>(item.joint)].cut;
            const bool repeat = !cut && visited_[item.body];  // only in malformed trees
            line(item, cut, repeat);
            if (cut || repeat) continue;
            visited_[item.body] = true;
            // Pushed in reverse so they pop in joint order.
            for (const int* j = by_parent_.end(item.body); j != by_parent_.begin(item.body);) {
                --j;
                const auto child = static_cast<std::size_t>(m_.joints[static_cast<std::size_t>(*j)].child);
                stack_.push_back({*j, child, item.depth + 1});
            }
        }
    }

    void line(const Item& item, bool cut, bool repeat) {
        if (++lines_ > kMaxTreeLines) return;  // still counted for the "... N more" line
        const std::size_t shown = item.depth < kMaxIndentDepth ? item.depth : kMaxIndentDepth;
        t_.raw(std::string(2 + 2 * shown, ' '));
        if (item.depth > kMaxIndentDepth) t_.raw("[depth ").num(static_cast<long long>(item.depth)).raw("] ");
        if (cut) t_.raw("-> ");
        const RigidBody& b = m_.bodies[item.body];
        write_body_label(t_, b);
        std::size_t tail = t_.mark();  // markers after the names must stay readable
        if (item.joint < 0) {
            if (item.body != 0) t_.raw(" (floating, not attached to ground)");
        } else {
            const Joint& j = m_.joints[static_cast<std::size_t>(item.joint)];
            t_.raw(" <- ");
            write_joint_label(t_, j);
            tail = t_.mark();
            if (cut) {
                t_.raw(" (cut, closes loop ");
                if (j.loop >= 0)
                    t_.num(j.loop);
                else
                    t_.raw("?");
                t_.raw(")");
            }
        }
        if (repeat) t_.raw(" (already shown above)");
        t_.end_line(tail);
    }

    Text& t_;
    const Mechanism& m_;
    JointsByParent by_parent_;
    std::vector<bool> visited_;
    std::vector<Item> stack_;
    std::size_t lines_ = 0;
};

void write_loops(Text& t, const Mechanism& m) {
    t.raw("Loops (").num(static_cast<long long>(m.loops.size())).raw(")").end_line();
    if (m.loops.empty()) t.raw("  none").end_line();
    for (std::size_t i = 0; i < m.loops.size(); ++i) {
        const Loop& l = m.loops[i];
        t.raw("  loop ").num(static_cast<long long>(i)).raw(": cut joint ");
        if (valid_index(m.joints, l.cut_joint))
            t.quoted(m.joints[static_cast<std::size_t>(l.cut_joint)].name);
        else
            t.raw("?");
        t.raw(", ").count(l.joints.size(), "joint", "joints").raw(", DoF ").num(l.dof);
        t.raw(" (Gruebler ").num(l.gruebler_dof).raw("), redundant ").num(l.redundant);
        if (l.planar)
            t.raw(", planar, normal ").vec(l.planar_normal);
        else
            t.raw(", spatial");
        t.end_line();
    }
}

// Parts whose CAD mass data was checked against their meshes, worst first;
// only printed when the check ran.
void write_shape_checks(Text& t, const Mechanism& m) {
    std::vector<std::size_t> checked;
    for (std::size_t i = 0; i < m.shape_checks.size(); ++i)
        if (m.shape_checks[i].checked) checked.push_back(i);
    if (checked.empty()) return;
    std::stable_sort(checked.begin(), checked.end(), [&](std::size_t a, std::size_t b) {
        return m.shape_checks[a].centroid_mismatch > m.shape_checks[b].centroid_mismatch;
    });
    t.raw("Mass data against meshes (").num(static_cast<long long>(checked.size()))
        .raw(" closed parts; centroid mismatch, worst first)").end_line();
    const std::size_t shown = checked.size() < 50 ? checked.size() : 50;
    for (std::size_t k = 0; k < shown; ++k) {
        const ShapeCheck& c = m.shape_checks[checked[k]];
        t.raw("  ").quoted(m.assembly.parts[checked[k]].name).raw(": ").real(c.centroid_mismatch * 1e3).raw(" mm");
        t.raw(c.centroid_mismatch > c.tolerance ? " (above " : " (within ").real(c.tolerance * 1e3).raw(" mm)");
        t.raw(", mesh volume ").real(c.volume * 1e9).raw(" mm^3, density ").real(c.density).raw(" kg/m^3");
        t.end_line();
    }
    if (shown < checked.size()) t.raw("  ... ").num(static_cast<long long>(checked.size() - shown)).raw(" more").end_line();
    t.blank();
}

// The spread of CAD densities (mass over CAD volume), so a reader sees at a
// glance whether a file's parts carry real materials; only with volumes.
void write_densities(Text& t, const Mechanism& m) {
    const Part* light = nullptr;
    const Part* heavy = nullptr;
    long long n = 0, outside = 0;
    for (const Part& p : m.assembly.parts) {
        if (p.is_helper() || p.is_ground() || !(p.mass > 0) || !(p.volume > 0)) continue;
        const double d = p.mass / p.volume;
        ++n;
        outside += d < kDensityMin || d > kDensityMax;
        if (!light || d < light->mass / light->volume) light = &p;
        if (!heavy || d > heavy->mass / heavy->volume) heavy = &p;
    }
    if (n == 0) return;
    t.raw("CAD densities (").num(n).raw(" parts with a CAD volume; ").real(kDensityMin).raw(" to ").real(kDensityMax);
    t.raw(" kg/m^3 accepted): lightest ").quoted(light->name).raw(" ").real(light->mass / light->volume);
    t.raw(" kg/m^3, densest ").quoted(heavy->name).raw(" ").real(heavy->mass / heavy->volume).raw(" kg/m^3, ");
    t.num(outside).raw(" outside");
    t.end_wrapped(4);
    t.blank();
}

// One line per drive: what it amounts to at its joint.
void write_drives(Text& t, const std::vector<Drive>& drives) {
    t.raw("Drives (").num(static_cast<long long>(drives.size())).raw(")").end_line();
    for (const Drive& d : drives) {
        const char* effort = d.linear ? " N" : " N m";
        t.raw("  ").quoted(d.name).raw(": ").str(d.motor_name);
        if (!d.transmission_name.empty()) t.raw(" + ").str(d.transmission_name);
        t.raw(", ratio ").real(d.ratio).raw(", armature ").real(d.armature).raw(d.linear ? " kg" : " kg m^2");
        t.raw(", effort limit ").real(d.effort_limit).raw(effort).raw(", speed limit ").real(d.velocity_limit);
        t.raw(d.linear ? " m/s" : " rad/s").raw(", servo K ").real(d.servo.stiffness).raw(" D ");
        t.real(d.servo.damping + d.servo.emf_damping).raw(", ");
        t.num(static_cast<long long>(d.spec.motion.points().size())).raw(" motion points");
        t.end_wrapped(4);
    }
    t.blank();
}

// One line per joint with dynamics: what acts on it besides the bodies.
void write_joint_dynamics(Text& t, const std::vector<ResolvedJointDynamics>& all) {
    t.raw("Joint dynamics (").num(static_cast<long long>(all.size())).raw(")").end_line();
    for (const ResolvedJointDynamics& d : all) {
        const char* rate = d.linear ? " N s/m" : " N m s/rad";
        const char* effort = d.linear ? " N" : " N m";
        t.raw("  ").quoted(d.name).raw(": damping ").real(d.damping);
        if (d.damping_negative != d.damping) t.raw(" (q' > 0) / ").real(d.damping_negative).raw(" (q' < 0)");
        t.raw(rate).raw(", Coulomb ").real(d.coulomb);
        if (d.coulomb_negative != d.coulomb) t.raw(" (q' > 0) / ").real(d.coulomb_negative).raw(" (q' < 0)");
        t.raw(effort);
        if (d.stribeck > 0)
            t.raw(", Stribeck peak ").real(d.stribeck).raw(effort).raw(" over ").real(d.stribeck_velocity)
                .raw(d.linear ? " m/s" : " rad/s");
        if (d.offset != 0) t.raw(", effort offset ").real(d.offset).raw(effort);
        t.raw(", spring ").real(d.stiffness).raw(d.linear ? " N/m" : " N m/rad");
        t.raw(" about ").real(d.rest).raw(", armature ").real(d.armature).raw(d.linear ? " kg" : " kg m^2");
        if (d.limited) t.raw(", limits ").real(d.lower).raw(" .. ").real(d.upper);
        t.end_wrapped(4);
    }
    t.blank();
}

void write_findings(Text& t, const Mechanism& m, const Counts& c) {
    t.raw("Findings (").num(static_cast<long long>(m.findings.size())).raw(")").end_line();
    if (m.findings.empty()) t.raw("  none").end_line();
    struct Group {
        mbx_severity severity;
        const char* title;
        std::size_t n;
    };
    const Group groups[] = {{MBX_SEVERITY_ERROR, "Errors", c.errors},
                            {MBX_SEVERITY_WARNING, "Warnings", c.warnings},
                            {MBX_SEVERITY_INFO, "Info", c.info}};
    for (const Group& g : groups) {
        if (g.n == 0) continue;
        t.raw("  ").raw(g.title).raw(" (").num(static_cast<long long>(g.n)).raw(")").end_line();
        for (const Finding& f : m.findings) {
            if (f.severity != g.severity) continue;
            t.raw("    ").raw(severity_name(f.severity)).raw(" ").raw(f.code_name());
            if (f.subject.kind != MBX_SUBJECT_NONE) t.raw(" ").raw(subject_kind_name(f.subject.kind));
            if (!f.subject.name.empty()) t.raw(" ").quoted(f.subject.name);
            if (!f.subject.id.empty()) t.raw(" (").str(f.subject.id).raw(")");
            t.raw(": ").str(f.message);
            t.end_wrapped(8);
        }
    }
}

std::size_t text_size_estimate(const Mechanism& m) {
    const std::size_t tree_lines = m.bodies.size() + m.joints.size();
    std::size_t n = 2048 + 90 * (tree_lines < kMaxTreeLines ? tree_lines : kMaxTreeLines);
    n += 110 * m.loops.size();
    for (const Finding& f : m.findings) n += 80 + f.message.size() + f.subject.id.size() + f.subject.name.size();
    return n;
}

}  // namespace

std::string report_text(const Mechanism& m, const std::vector<Drive>* drives,
                        const std::vector<ResolvedJointDynamics>* joint_dynamics) {
    const Counts c = count(m);
    Text t(text_size_estimate(m));
    write_header(t, m, c);
    t.blank();
    Outline(t, m).write();
    t.blank();
    write_loops(t, m);
    t.blank();
    write_shape_checks(t, m);
    write_densities(t, m);
    if (drives && !drives->empty()) write_drives(t, *drives);
    if (joint_dynamics && !joint_dynamics->empty()) write_joint_dynamics(t, *joint_dynamics);
    write_findings(t, m, c);
    return t.take();
}

}  // namespace mbx
