// The calibration experiment file from text.
#include "calibration/records/experiment.h"
#include "core/finding.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const mbx::calibration::Experiment e =
            mbx::calibration::parse_experiment(fuzz_text(data, size), std::string(kFuzzDir) + "/experiment.xml");
        (void)e;
    } catch (const mbx::Error&) {
    }
    return 0;
}
