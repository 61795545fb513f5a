#include "export/modelica/modelica_text.h"

#include <cmath>

#include "export/common/names.h"

namespace mbx {

std::string modelica_string(std::string_view text) {
    std::string out;
    out.reserve(text.size() + 2);
    out += '"';
    for (char c : text) {
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        default:
            // Other control characters have no portable escape; a space keeps the text readable.
            out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? ' ' : c;
        }
    }
    out += '"';
    return out;
}

std::string modelica_package_name(std::string_view model_name) {
    std::string name = sanitize_identifier(model_name, "Model");
    if (name[0] >= 'a' && name[0] <= 'z') name[0] = char(name[0] - 'a' + 'A');
    // A package called Modelica (or ModelicaServices, Complex) would hide the
    // library every class reference starts from.
    if (is_modelica_keyword(name) || name == "Modelica" || name == "ModelicaServices" || name == "Complex")
        name += "_model";
    return name;
}

bool is_identity_pose(const Pose& pose) {
    return pose.position.norm() <= 1e-12 && (pose.rotation - Mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-12;
}

Vec3 cardan_angles_123(const Mat3& r) {
    // R = Rx(a) Ry(b) Rz(c) has first row (cb cc, -cb sc, sb) and last column (sb, -sa cb, ca cb).
    const double cb = std::hypot(r(0, 0), r(0, 1));
    const double b = std::atan2(r(0, 2), cb);
    if (cb < 1e-12) return {std::atan2(r(2, 1), r(1, 1)), b, 0.0};  // gimbal lock: c folded into a
    return {std::atan2(-r(1, 2), r(2, 2)), b, std::atan2(-r(0, 1), r(0, 0))};
}

}  // namespace mbx
