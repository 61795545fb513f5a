// The description (drives) file from text, over the bundled object library so
// drives that name its objects get past the lookup into their own checks.
#include <cstdlib>

#include "fuzz_common.h"
#include "core/mechatronics/drive_file.h"

namespace {
const mbx::ObjectLibrary& bundled_library() {
    static const mbx::ObjectLibrary library = [] {
        mbx::ObjectLibrary l;
        if (!l.load_file(MBX_FUZZ_BUNDLED_LIBRARY) || !l.ok()) std::abort();
        return l;
    }();
    return library;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    mbx::MechatronicSpec spec;
    spec.library = bundled_library();
    std::vector<mbx::DriveError> errors;
    mbx::load_drive_text(fuzz_text(data, size), std::string(kFuzzDir) + "/drives.xml", kFuzzDir, spec, errors);
    return 0;
}
