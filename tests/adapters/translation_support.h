// Translating through the C API for the adapter tests: an owned context and
// mechanism, findings as plain structs, reports written to a temp directory.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <mbx/mbx.h>

namespace atest {

struct FindingCopy {
    mbx_severity severity;
    mbx_finding_code code;
    std::string code_name, subject_id, subject_name, message, file;
    int line;
};

class Translation {
public:
    Translation(const mbx_host* host, uint32_t flags, double centroid_tolerance = 0) {
        REQUIRE(mbx_context_create(&ctx_) == MBX_OK);
        mbx_translate_options o{};
        o.struct_size = sizeof o;
        o.flags = flags;
        o.centroid_tolerance = centroid_tolerance;
        status_ = mbx_translate(ctx_, host, &o, &mech_);
        if (status_ != MBX_OK) MESSAGE("translation failed: " << mbx_context_last_error(ctx_));
    }
    ~Translation() {
        mbx_mechanism_destroy(mech_);
        mbx_context_destroy(ctx_);
    }
    Translation(const Translation&) = delete;
    Translation& operator=(const Translation&) = delete;

    mbx_status status() const { return status_; }
    mbx_context* context() const { return ctx_; }
    mbx_mechanism* mechanism() const { return mech_; }

    mbx_mechanism_summary summary() const {
        mbx_mechanism_summary s{};
        s.struct_size = sizeof s;
        REQUIRE(mbx_mechanism_get_summary(mech_, &s) == MBX_OK);
        return s;
    }

    std::vector<FindingCopy> findings() const {
        std::vector<FindingCopy> out;
        for (uint32_t i = 0; i < mbx_mechanism_finding_count(mech_); ++i) {
            mbx_finding f{};
            f.struct_size = sizeof f;
            REQUIRE(mbx_mechanism_get_finding(mech_, i, &f) == MBX_OK);
            out.push_back({f.severity, f.code, f.code_name, f.subject_id, f.subject_name, f.message, f.file, f.line});
        }
        return out;
    }

    size_t count(mbx_finding_code code) const {
        size_t n = 0;
        for (const FindingCopy& f : findings()) n += f.code == code;
        return n;
    }

    size_t count(const std::string& code_name) const {
        size_t n = 0;
        for (const FindingCopy& f : findings()) n += f.code_name == code_name;
        return n;
    }

    std::set<std::string> subjects(mbx_finding_code code) const {
        std::set<std::string> out;
        for (const FindingCopy& f : findings())
            if (f.code == code) out.insert(f.subject_id);
        return out;
    }

    mbx_rigid_body_info rigid_body(uint32_t index) const {
        mbx_rigid_body_info r{};
        r.struct_size = sizeof r;
        REQUIRE(mbx_mechanism_get_rigid_body(mech_, index, &r) == MBX_OK);
        return r;
    }

    uint32_t rigid_body_total() const {
        const mbx_mechanism_summary s = summary();
        return 1 + s.rigid_body_count + s.joint_node_count;
    }

    // Meshes over all rigid bodies (asks the host for every shape).
    uint64_t mesh_total() const {
        uint64_t n = 0;
        for (uint32_t b = 0; b < rigid_body_total(); ++b) {
            mbx_shape_stats st{};
            st.struct_size = sizeof st;
            REQUIRE(mbx_mechanism_get_shape_stats(ctx_, mech_, b, &st) == MBX_OK);
            n += st.mesh_count;
        }
        return n;
    }

    void write_report(const std::string& dir) const {
        REQUIRE_MESSAGE(mbx_mechanism_write_report(ctx_, mech_, dir.c_str()) == MBX_OK, mbx_context_last_error(ctx_));
    }

private:
    mbx_context* ctx_ = nullptr;
    mbx_mechanism* mech_ = nullptr;
    mbx_status status_ = MBX_ERROR_INTERNAL;
};

}  // namespace atest
