#include "translation.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace samples_test {

Translation::Translation(const mbx_host* host) {
    if (mbx_context_create(&ctx_) != MBX_OK) return;
    mbx_translate_options o{};
    o.struct_size = sizeof o;
    o.flags = MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES;
    status_ = mbx_translate(ctx_, host, &o, &mech_);
}

Translation::~Translation() {
    mbx_mechanism_destroy(mech_);
    mbx_context_destroy(ctx_);
}

std::string Translation::error() const { return ctx_ ? mbx_context_last_error(ctx_) : "no context"; }

mbx_mechanism_summary Translation::summary() const {
    mbx_mechanism_summary s{};
    s.struct_size = sizeof s;
    mbx_mechanism_get_summary(mech_, &s);
    return s;
}

std::map<std::string, int> Translation::finding_counts() const {
    std::map<std::string, int> out;
    for (uint32_t i = 0; i < mbx_mechanism_finding_count(mech_); ++i) {
        mbx_finding f{};
        f.struct_size = sizeof f;
        if (mbx_mechanism_get_finding(mech_, i, &f) == MBX_OK) ++out[f.code_name ? f.code_name : "?"];
    }
    return out;
}

std::vector<std::string> Translation::finding_messages() const {
    std::vector<std::string> out;
    for (uint32_t i = 0; i < mbx_mechanism_finding_count(mech_); ++i) {
        mbx_finding f{};
        f.struct_size = sizeof f;
        if (mbx_mechanism_get_finding(mech_, i, &f) == MBX_OK)
            out.push_back(std::string(f.code_name ? f.code_name : "?") + ": " + (f.message ? f.message : ""));
    }
    return out;
}

std::string Translation::report_json(const std::string& directory) const {
    if (mbx_mechanism_write_report(ctx_, mech_, directory.c_str()) != MBX_OK) return "";
    std::ifstream in(directory + "/report.json");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

std::vector<double> json_numbers(const std::string& json, const std::string& key) {
    std::vector<double> out;
    const std::string needle = "\"" + key + "\": ";
    for (size_t at = json.find(needle); at != std::string::npos; at = json.find(needle, at + 1)) {
        const char* start = json.c_str() + at + needle.size();
        char* end = nullptr;
        const double v = std::strtod(start, &end);
        if (end != start) out.push_back(v);
    }
    return out;
}

}  // namespace samples_test
