#include "core/finding.h"

namespace mbx {

const char* finding_code_name(mbx_finding_code code) {
    switch (code) {
        case MBX_FINDING_INERTIA_NOT_POSITIVE_DEFINITE: return "inertia_not_positive_definite";
        case MBX_FINDING_INERTIA_TRIANGLE_INEQUALITY: return "inertia_triangle_inequality";
        case MBX_FINDING_JOINT_FRAMES_APART: return "joint_frames_apart";
        case MBX_FINDING_BODY_UNCONNECTED: return "body_unconnected";
        case MBX_FINDING_ZERO_MASS_BODY: return "zero_mass_body";
        case MBX_FINDING_ROTATION_REORTHONORMALIZED: return "rotation_reorthonormalized";
        case MBX_FINDING_HOST_STATUS: return "host_status";
        case MBX_FINDING_WELD_LOOP_COLLAPSED: return "weld_loop_collapsed";
        case MBX_FINDING_REDUNDANT_CONSTRAINTS: return "redundant_constraints";
        case MBX_FINDING_FLOATING_SUBASSEMBLY: return "floating_subassembly";
        case MBX_FINDING_HELPER_BODY_DROPPED: return "helper_body_dropped";
        case MBX_FINDING_PLANAR_LOOP: return "planar_loop";
        case MBX_FINDING_MOBILITY_MISMATCH: return "mobility_mismatch";
        case MBX_FINDING_DEGENERATE_AXIS: return "degenerate_axis";
        case MBX_FINDING_SELF_CONSTRAINT: return "self_constraint";
        case MBX_FINDING_NEGATIVE_MASS: return "negative_mass";
        case MBX_FINDING_LIMITS_INVERTED: return "limits_inverted";
        case MBX_FINDING_HOST_DIAGNOSTIC: return "host_diagnostic";
        case MBX_FINDING_MASS_MISMATCH: return "mass_mismatch";
        case MBX_FINDING_SHAPE_NOT_CLOSED: return "shape_not_closed";
        case MBX_FINDING_EXPORT_LOOPS_AS_TREE: return "export_loops_as_tree";
        case MBX_FINDING_EXPORT_APPROXIMATION: return "export_approximation";
        case MBX_FINDING_EXPORT_MESH_MISSING: return "export_mesh_missing";
        case MBX_FINDING_IMPLAUSIBLE_DENSITY: return "implausible_density";
        case MBX_FINDING_ASSEMBLY_MASS_MISMATCH: return "assembly_mass_mismatch";
    }
    return "unknown";
}

const char* Finding::code_name() const { return code_text.empty() ? finding_code_name(code) : code_text.c_str(); }

const char* severity_name(mbx_severity severity) {
    switch (severity) {
        case MBX_SEVERITY_INFO: return "info";
        case MBX_SEVERITY_WARNING: return "warning";
        case MBX_SEVERITY_ERROR: return "error";
    }
    return "unknown";
}

const char* subject_kind_name(mbx_subject_kind kind) {
    switch (kind) {
        case MBX_SUBJECT_NONE: return "none";
        case MBX_SUBJECT_BODY: return "body";
        case MBX_SUBJECT_FRAME: return "frame";
        case MBX_SUBJECT_CONSTRAINT: return "constraint";
        case MBX_SUBJECT_RIGID_BODY: return "rigid_body";
        case MBX_SUBJECT_LOOP: return "loop";
        case MBX_SUBJECT_FILE: return "file";
        case MBX_SUBJECT_MODEL: return "model";
    }
    return "unknown";
}

}  // namespace mbx
