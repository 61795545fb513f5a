// One translation through the C API with the mass check on, and what the
// samples tests read back from it.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <mbx/mbx.h>

namespace samples_test {

class Translation {
public:
    explicit Translation(const mbx_host* host);
    ~Translation();
    Translation(const Translation&) = delete;
    Translation& operator=(const Translation&) = delete;

    bool ok() const { return status_ == MBX_OK; }
    std::string error() const;
    mbx_mechanism_summary summary() const;
    // Finding code name -> count.
    std::map<std::string, int> finding_counts() const;
    std::vector<std::string> finding_messages() const;
    // Writes the report and returns report.json's text ("" on failure).
    std::string report_json(const std::string& directory) const;

private:
    mbx_context* ctx_ = nullptr;
    mbx_mechanism* mech_ = nullptr;
    mbx_status status_ = MBX_ERROR_INTERNAL;
};

// Every number that follows `"key": ` in a JSON text, in order.
std::vector<double> json_numbers(const std::string& json, const std::string& key);

}  // namespace samples_test
