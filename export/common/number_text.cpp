#include "export/common/number_text.h"

#include <charconv>
#include <cmath>

namespace mbx {

std::string number_text(double v) {
    if (!std::isfinite(v)) return "0";  // callers validate; never write nan/inf into a model
    if (std::fabs(v) < 1e-14) v = 0;
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string spaced_text(const Vec3& v) {
    return number_text(v.x()) + " " + number_text(v.y()) + " " + number_text(v.z());
}

std::string modelica_vector(const Vec3& v) {
    return "{" + number_text(v.x()) + ", " + number_text(v.y()) + ", " + number_text(v.z()) + "}";
}

}  // namespace mbx
