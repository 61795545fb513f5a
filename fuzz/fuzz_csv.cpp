// The measured-data CSV reader from text.
#include "calibration/records/records.h"
#include "core/finding.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const mbx::calibration::Table t =
            mbx::calibration::read_csv_text(fuzz_text(data, size), std::string(kFuzzDir) + "/record.csv");
        for (const auto& column : t.columns)
            if (column.size() != t.columns.front().size()) __builtin_trap();  // ragged table
    } catch (const mbx::Error&) {
    }
    return 0;
}
