// A complete, exact text rendering of a translated mechanism (summary, every
// rigid body, joint, loop and finding, doubles to 17 digits), so two
// translations can be compared for equality with one string compare.
#pragma once

#include <string>

#include <mbx/mbx.h>

namespace itest {

std::string fingerprint(const mbx_mechanism* m);

}  // namespace itest
