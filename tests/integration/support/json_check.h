// A strict JSON syntax check (RFC 8259 grammar, no extensions) for the
// report: enough to know a reader will parse it, with no JSON dependency.
#pragma once

#include <set>
#include <string>

namespace itest {

struct JsonCheck {
    bool ok = false;
    std::string error;                 // "offset N: what", when !ok
    std::set<std::string> top_keys;    // keys of the top-level object
    std::set<std::string> all_keys;    // keys of every object at any depth
};

JsonCheck check_json(const std::string& text);

}  // namespace itest
