// The assembly as pulled from a host, converted to SI and world coordinates.
// Nothing here is merged or interpreted yet: one Part per host body, one
// Constraint per host constraint, in host order (order drives determinism).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/finding.h"
#include "core/math.h"

namespace mbx {

struct Part {
    std::string id;
    std::string name;
    uint32_t flags = 0;  // mbx_body_flags
    double mass = 0;     // kg
    Vec3 com = Vec3::Zero();          // body frame, m
    Mat3 inertia = Mat3::Zero();      // about com, body axes, kg m^2
    Pose pose;                        // world, m
    double volume = 0;                // CAD solid volume, m^3; 0 = unknown
    // mass / volume as the host wrote both (its own units), 0 if unknown: 1
    // there is a CAD default density whatever the units are.
    double host_density = 0;

    bool is_ground() const { return flags & MBX_BODY_GROUND; }
    bool is_helper() const { return flags & MBX_BODY_HELPER; }
    // A datum standing for the world (PMXML's RootGround), not a CAD part.
    bool is_world_datum() const { return is_ground() && is_helper(); }
};

struct Frame {
    std::string id;
    std::string name;
    int part = -1;  // index into Assembly::parts
    Pose world;     // world pose at the assembly configuration
};

struct Primitive {
    mbx_primitive_type type = MBX_PRIMITIVE_WELD;
    Vec3 axis = Vec3::UnitZ();  // unit, world; unused for weld and spherical
    bool has_limits = false;
    double lower = 0, upper = 0;  // SI
    double velocity_limit = 0, effort_limit = 0;  // SI, the host's rated speed and effort; 0: not given
};

// Base -> chain[0] (J_N) ... chain.back() (J_1) -> Follower.
struct Constraint {
    std::string id;
    std::string name;
    int base_frame = -1;      // index into Assembly::frames
    int follower_frame = -1;
    std::vector<Primitive> chain;
    std::string host_status;  // exporter diagnostic, "" if none

    bool is_weld() const {
        for (const Primitive& p : chain)
            if (p.type != MBX_PRIMITIVE_WELD) return false;
        return true;
    }
};

struct Assembly {
    std::string name;
    std::string source;
    std::vector<Part> parts;
    std::vector<Frame> frames;
    std::vector<Constraint> constraints;
    double size = 1.0;  // bounding-box diagonal of part and frame origins, m (>0)
    double stated_mass = 0;  // kg, the host's whole-assembly mass; 0 = not stated
    // Host diagnostics pulled so far: a version-4 host may append more while
    // it serves shapes, and those are pulled from here on.
    size_t host_diagnostics_read = 0;

    size_t cad_part_count() const {
        size_t n = 0;
        for (const Part& p : parts) n += !p.is_world_datum();
        return n;
    }
};

}  // namespace mbx
