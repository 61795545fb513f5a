// PMXML as the file adapter reads it: parse, build the host assembly, and
// translate it through the C API (what `mbx translate file.xml` does, minus
// mesh files), so values the reader lets through meet the translator too.
#include <mbx/mbx.h>

#include "fuzz_common.h"
#include "memory_host.h"
#include "pmxml_assembly.h"
#include "pmxml_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    mbx_files::PmxmlModel model;
    try {
        model = mbx_files::parse_pmxml(fuzz_text(data, size), std::string(kFuzzDir) + "/fuzz.xml");
    } catch (const mbx_files::FileError&) {
        return 0;  // the documented rejection
    }
    mbx_memory::Host host(mbx_files::to_assembly(model));
    mbx_context* context = nullptr;
    if (mbx_context_create(&context) != MBX_OK) __builtin_trap();
    mbx_translate_options options{};
    options.struct_size = sizeof options;
    mbx_mechanism* mechanism = nullptr;
    if (mbx_translate(context, host.table(), &options, &mechanism) == MBX_OK) {
        mbx_mechanism_summary summary{};
        summary.struct_size = sizeof summary;
        mbx_mechanism_get_summary(mechanism, &summary);
        mbx_mechanism_destroy(mechanism);
    } else if (mbx_context_last_error(context) == nullptr) {
        __builtin_trap();  // a failure must say why
    }
    mbx_context_destroy(context);
    return 0;
}
