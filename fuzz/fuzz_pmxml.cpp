// PMXML as the file adapter reads it: parse, build the host assembly, and
// translate it through the C API (what `mbx translate file.xml` does, minus
// mesh files), so values the reader lets through meet the translator too.
// Every input is also read as one DOM, which reading by parts must match.
#include <mbx/mbx.h>

#include "fuzz_common.h"
#include "host_adapters/memory/memory_host.h"
#include "host_adapters/pmxml_vrml/pmxml_assembly.h"
#include "host_adapters/pmxml_vrml/pmxml_reader.h"

namespace {

// The text read one way: the model, or the error's text.
bool read(std::string_view text, mbx_files::PmxmlParse how, mbx_files::PmxmlModel& model, std::string& error) {
    try {
        model = mbx_files::parse_pmxml(text, std::string(kFuzzDir) + "/fuzz.xml", how);
        return true;
    } catch (const mbx_files::FileError& e) {
        error = e.what();  // the documented rejection
        return false;
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text = fuzz_text(data, size);
    // Read by parts where the outline takes it, and as one DOM: the two
    // must agree on the model or on the error, to the byte.
    mbx_files::PmxmlModel model, dom_model;
    std::string error, dom_error;
    const bool ok = read(text, mbx_files::PmxmlParse::automatic, model, error);
    const bool dom_ok = read(text, mbx_files::PmxmlParse::whole_dom, dom_model, dom_error);
    if (ok != dom_ok || (ok && !mbx_files::first_difference(model, dom_model).empty()) || error != dom_error)
        __builtin_trap();
    if (!ok) return 0;
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
