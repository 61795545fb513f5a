// Progress reporting with cancellation. Hot loops call tick() every item; the
// host callback runs only every `stride` items so a 100k-body translation
// does not spend its time in the UI.
#pragma once
#include <cstddef>

#include "core/finding.h"
#include "mbx/mbx.h"

namespace mbx {

class Progress {
public:
    Progress() = default;
    Progress(mbx_progress_fn fn, void* user) : fn_(fn), user_(user) {}

    // Starts a stage of `total` items (0 if unknown) and reports 0.
    void stage(const char* name, size_t total) {
        name_ = name;
        total_ = total;
        done_ = 0;
        report(0.0);
    }
    void tick() {
        if (++done_ % kStride == 0 && fn_) report(total_ ? double(done_) / double(total_) : 0.0);
    }
    void finish() { report(1.0); }

private:
    static constexpr size_t kStride = 1024;

    void report(double fraction) {
        if (fn_ && fn_(user_, name_, fraction > 1.0 ? 1.0 : fraction) != 0)
            throw Error(MBX_ERROR_CANCELLED, Subject::model({}),
                        std::string("translation cancelled by the host during '") + name_ + "'");
    }

    mbx_progress_fn fn_ = nullptr;
    void* user_ = nullptr;
    const char* name_ = "";
    size_t total_ = 0, done_ = 0;
};

}  // namespace mbx
