#include "pmxml_model.h"

#include <cstring>
#include <type_traits>

namespace mbx_files {
namespace {

// Field-by-field comparison that names the first field to differ.
class Compare {
public:
    template <class T>
    Compare& operator()(const char* field, const T& a, const T& b) {
        if (diff_.empty() && !same(a, b)) diff_ = where_ + field;
        return *this;
    }
    template <class T, class Each>
    Compare& list(const char* field, const std::vector<T>& a, const std::vector<T>& b, Each each) {
        if (!diff_.empty()) return *this;
        if (a.size() != b.size()) {
            diff_ = where_ + field + " count (" + std::to_string(a.size()) + " vs " + std::to_string(b.size()) + ")";
            return *this;
        }
        const std::string outer = where_;
        for (size_t i = 0; i < a.size() && diff_.empty(); ++i) {
            where_ = outer + field + "[" + std::to_string(i) + "].";
            each(a[i], b[i]);
        }
        where_ = outer;
        return *this;
    }
    const std::string& difference() const { return diff_; }

private:
    template <class T>
    static bool same(const T& a, const T& b) {
        if constexpr (std::is_base_of_v<Eigen::MatrixBase<T>, T>)
            return std::memcmp(a.data(), b.data(), sizeof(double) * size_t(a.size())) == 0;
        else if constexpr (std::is_floating_point_v<T>)
            return std::memcmp(&a, &b, sizeof a) == 0;
        else
            return a == b;
    }
    std::string where_, diff_;
};

}  // namespace

std::string first_difference(const PmxmlModel& a, const PmxmlModel& b) {
    Compare c;
    c("file", a.file, b.file)("name", a.name, b.name)("container", a.container, b.container);
    c("created_using", a.created_using, b.created_using);
    c.list("bodies", a.bodies, b.bodies, [&](const PmxmlBody& x, const PmxmlBody& y) {
        c("id", x.id, y.id)("name", x.name, y.name)("node_id", x.node_id, y.node_id);
        c("subsystem_path", x.subsystem_path, y.subsystem_path)("flags", x.flags, y.flags)("mass", x.mass, y.mass);
        c("mass_unit", x.mass_unit, y.mass_unit)("mass_to_kg", x.mass_to_kg, y.mass_to_kg);
        c("volume", x.volume, y.volume)("volume_to_m3", x.volume_to_m3, y.volume_to_m3);
        c("inertia", x.inertia, y.inertia)("inertia_unit", x.inertia_unit, y.inertia_unit);
        c("inertia_to_kg_m2", x.inertia_to_kg_m2, y.inertia_to_kg_m2)("com", x.com, y.com);
        c("cs1", x.cs1, y.cs1)("cg", x.cg, y.cg)("geometry_file", x.geometry_file, y.geometry_file);
        c("geometry_line", x.geometry_line, y.geometry_line)("line", x.line, y.line);
    });
    c.list("frames", a.frames, b.frames, [&](const PmxmlFrame& x, const PmxmlFrame& y) {
        c("id", x.id, y.id)("name", x.name, y.name)("display_name", x.display_name, y.display_name);
        c("node_id", x.node_id, y.node_id)("ref", x.ref, y.ref)("body", x.body, y.body);
        c("position", x.position, y.position)("rotation", x.rotation, y.rotation);
        c("length_unit", x.length_unit, y.length_unit)("length_to_m", x.length_to_m, y.length_to_m);
        c("to_host", x.to_host, y.to_host)("line", x.line, y.line);
    });
    c.list("joints", a.joints, b.joints, [&](const PmxmlJoint& x, const PmxmlJoint& y) {
        c("id", x.id, y.id)("name", x.name, y.name)("node_id", x.node_id, y.node_id);
        c("subsystem_path", x.subsystem_path, y.subsystem_path)("base_frame", x.base_frame, y.base_frame);
        c("follower_frame", x.follower_frame, y.follower_frame)("status", x.status, y.status)("line", x.line, y.line);
        c.list("primitives", x.primitives, y.primitives, [&](const PmxmlPrimitive& p, const PmxmlPrimitive& q) {
            c("type", p.type, q.type)("axis", p.axis, q.axis)("line", p.line, q.line);
        });
    });
    c.list("diagnostics", a.diagnostics, b.diagnostics,
           [&](const mbx_memory::Diagnostic& x, const mbx_memory::Diagnostic& y) {
               c("severity", x.severity, y.severity)("code", x.code, y.code)("subject_kind", x.subject_kind, y.subject_kind);
               c("subject_id", x.subject_id, y.subject_id)("subject_name", x.subject_name, y.subject_name);
               c("file", x.file, y.file)("line", x.line, y.line)("message", x.message, y.message);
           });
    return c.difference();
}

Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& r) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    return svd.matrixU() * svd.matrixV().transpose();
}

}  // namespace mbx_files
