// VRML scenes built by hand, as read_vrml would produce them: each node's
// world transform is its parent's times its own local one.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "host_adapters/common/shape_matching.h"
#include "host_adapters/common/vrml_scene.h"

namespace matching_test {

inline Eigen::Affine3d pose(const Eigen::Vector3d& t, const Eigen::Matrix3d& r = Eigen::Matrix3d::Identity(),
                            double scale = 1) {
    Eigen::Affine3d a = Eigen::Affine3d::Identity();
    a.translate(t);
    a.linear() = r * scale;
    return a;
}

inline Eigen::Matrix3d rot(const Eigen::Vector3d& axis, double angle) {
    return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

inline mbx_files::BodyPose body(const std::string& id, const std::string& name, const Eigen::Vector3d& t,
                                const Eigen::Matrix3d& r = Eigen::Matrix3d::Identity()) {
    Eigen::Isometry3d w = Eigen::Isometry3d::Identity();
    w.translate(t);
    w.linear() = r;
    return {id, name, w};
}

// A tetrahedron with one vertex at the local origin, so the first vertex
// shows where the node's origin went.
inline mbx_files::VrmlMesh tetra(const std::string& name = "", double size = 1) {
    mbx_files::VrmlMesh m;
    m.name = name;
    m.vertices = {0, 0, 0, size, 0, 0, 0, size, 0, 0, 0, size};
    m.triangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    return m;
}

class SceneBuilder {
public:
    explicit SceneBuilder(std::string file = "assembly_a.wrl") : file_(std::move(file)) {}

    // Adds a node under `parent` (-1: top level) and returns its index.
    int add(int parent, const Eigen::Affine3d& local, const std::string& name = "", const std::string& part_name = "",
            const std::string& kind = "Transform") {
        mbx_files::VrmlNode n;
        n.parent = parent;
        n.kind = kind;
        n.name = name;
        n.part_name = part_name;
        n.file = file_;
        n.line = 10 * int(scene.nodes.size() + 1);
        n.world = parent < 0 ? local : scene.nodes[size_t(parent)].world * local;
        scene.nodes.push_back(std::move(n));
        return int(scene.nodes.size() - 1);
    }
    void mesh(int node, const mbx_files::VrmlMesh& m) { scene.nodes[size_t(node)].meshes.push_back(m); }

    mbx_files::VrmlScene scene;

private:
    std::string file_;
};

inline Eigen::Vector3d first_vertex(const mbx_files::MatchedMesh& m) {
    return Eigen::Vector3d(m.vertices[0], m.vertices[1], m.vertices[2]);
}

}  // namespace matching_test
